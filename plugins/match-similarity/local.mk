# The skeletal-similarity matcher: libsimilarity (metrics, assignment, matching,
# explanations; linked by the plugin, the tests and the benchmark) and the plugin, which links
# the analysis and names libraries statically. The pipelines: map (compute and save a mapping)
# and map-edit (the same with a file of manual fixes applied on top).
noinst_LTLIBRARIES += plugins/match-similarity/libsimilarity.la
plugins_match_similarity_libsimilarity_la_SOURCES = \
	plugins/match-similarity/similarity.h \
	plugins/match-similarity/ms-internal.h \
	plugins/match-similarity/metrics.c \
	plugins/match-similarity/assign.c \
	plugins/match-similarity/match.c \
	plugins/match-similarity/gait.c \
	plugins/match-similarity/explain.c
plugins_match_similarity_libsimilarity_la_LIBADD = -lm

plugins_LTLIBRARIES += plugins/match-similarity.la
plugins_match_similarity_la_SOURCES = plugins/match-similarity/plugin.c

plugins_match_similarity_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_match_similarity_la_LIBADD = plugins/match-similarity/libsimilarity.la sdk/analysis/librigflow-analysis.la \
	sdk/match/librigflow-match.la -lm

dist_pipelines_DATA += pipelines/map.json pipelines/map-edit.json

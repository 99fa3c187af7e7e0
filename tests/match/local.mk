# Joint mapping tests: analysis on hand-built skeletons, the matcher's metrics and
# assignment, mapping files, name matching, accuracy on real skeletons against hand-written
# ground truth (tests/match/truth) and on generated ones.
MATCH_TEST_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins -I$(top_srcdir)/tests/match
MATCH_TEST_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
MATCH_LIBS = plugins/match-similarity/libsimilarity.la sdk/analysis/librigflow-analysis.la \
	sdk/match/librigflow-match.la -lm

check_PROGRAMS += tests/match/test_analysis tests/match/test_similarity tests/match/test_accuracy \
	tests/match/test_generated tests/match/test_mapfile tests/match/test_names \
	tests/match/test_map_pipeline tests/match/test_corr tests/match/test_rigs tests/match/test_facing
TESTS += tests/match/test_analysis tests/match/test_similarity tests/match/test_accuracy \
	tests/match/test_generated tests/match/test_mapfile tests/match/test_names \
	tests/match/test_map_pipeline tests/match/test_corr tests/match/test_rigs tests/match/test_facing
EXTRA_DIST += tests/match/truth/

tests_match_test_analysis_SOURCES = tests/match/test_analysis.c tests/match/skel-build.h
tests_match_test_analysis_CPPFLAGS = $(MATCH_TEST_CPPFLAGS)
tests_match_test_analysis_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_analysis_LDADD = sdk/analysis/librigflow-analysis.la $(CMOCKA_LIBS) -lm

tests_match_test_accuracy_SOURCES = tests/match/test_accuracy.c tests/match/truth.c \
	tests/match/truth.h
tests_match_test_accuracy_CPPFLAGS = $(MATCH_TEST_CPPFLAGS)
tests_match_test_accuracy_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_accuracy_LDADD = $(MATCH_LIBS) sdk/formats/assimp/librigflow-assimp.la \
	sdk/formats/bvh/librigflow-bvh.la

# Facing without a declared forward: shared rigs and a made-up quadruped turned about up.
tests_match_test_facing_SOURCES = tests/match/test_facing.c tests/match/truth.c tests/match/truth.h
tests_match_test_facing_CPPFLAGS = $(tests_match_test_accuracy_CPPFLAGS)
tests_match_test_facing_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_facing_LDADD = $(tests_match_test_accuracy_LDADD)

# Against the name maps of ../shared/data/correspondences.
tests_match_test_corr_SOURCES = tests/match/test_corr.c tests/match/truth.c tests/match/truth.h
tests_match_test_corr_CPPFLAGS = $(tests_match_test_accuracy_CPPFLAGS)
tests_match_test_corr_CFLAGS = $(MATCH_TEST_CFLAGS) $(JANSSON_CFLAGS)
tests_match_test_corr_LDADD = $(tests_match_test_accuracy_LDADD) $(JANSSON_LIBS)

tests_match_test_generated_SOURCES = tests/match/test_generated.c tests/match/gen.c \
	tests/match/gen.h tests/match/truth.c tests/match/truth.h
tests_match_test_generated_CPPFLAGS = $(tests_match_test_accuracy_CPPFLAGS)
tests_match_test_generated_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_generated_LDADD = $(tests_match_test_accuracy_LDADD)

# The second generator (rigs.h: skeletons built the way production rigs are), CMU as source.
tests_match_test_rigs_SOURCES = tests/match/test_rigs.c tests/match/rigs.c tests/match/rigs.h \
	tests/match/truth.c tests/match/truth.h
tests_match_test_rigs_CPPFLAGS = $(tests_match_test_accuracy_CPPFLAGS)
tests_match_test_rigs_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_rigs_LDADD = $(tests_match_test_accuracy_LDADD)

tests_match_test_similarity_SOURCES = tests/match/test_similarity.c tests/match/skel-build.h
tests_match_test_similarity_CPPFLAGS = $(MATCH_TEST_CPPFLAGS) -D_POSIX_C_SOURCE=200809L
tests_match_test_similarity_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_similarity_LDADD = $(MATCH_LIBS) $(CMOCKA_LIBS)

tests_match_test_mapfile_SOURCES = tests/match/test_mapfile.c
tests_match_test_mapfile_CPPFLAGS = $(MATCH_TEST_CPPFLAGS) -D_POSIX_C_SOURCE=200809L
tests_match_test_mapfile_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_mapfile_LDADD = plugins/mapping-file/libmapfile.la $(CMOCKA_LIBS)

tests_match_test_names_SOURCES = tests/match/test_names.c
tests_match_test_names_CPPFLAGS = $(MATCH_TEST_CPPFLAGS) -D_POSIX_C_SOURCE=200809L
tests_match_test_names_CFLAGS = $(MATCH_TEST_CFLAGS)
tests_match_test_names_LDADD = sdk/match/librigflow-match.la $(CMOCKA_LIBS)

# Through the host with the bundled plugins: every data file, strategies, overrides.
tests_match_test_map_pipeline_SOURCES = tests/match/test_map_pipeline.c
tests_match_test_map_pipeline_CPPFLAGS = $(MATCH_TEST_CPPFLAGS) -I$(top_srcdir)/framework
tests_match_test_map_pipeline_CFLAGS = $(MATCH_TEST_CFLAGS) $(GLIB_CFLAGS) $(JANSSON_CFLAGS)
tests_match_test_map_pipeline_LDADD = framework/librigflow.la plugins/mapping-file/libmapfile.la \
	$(GLIB_LIBS) $(CMOCKA_LIBS)

# The rigflow map command end to end.
TESTS += tests/match/test_map_cmd.sh
EXTRA_DIST += tests/match/test_map_cmd.sh

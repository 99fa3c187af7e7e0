# ik.compare: the IK comparison as a report node (CSV and SVG chart).
plugins_LTLIBRARIES += plugins/ik-compare.la
plugins_ik_compare_la_SOURCES = plugins/ik-compare/compare.c
plugins_ik_compare_la_CPPFLAGS = $(IK_CPPFLAGS)
plugins_ik_compare_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_ik_compare_la_LIBADD = sdk/ik/librigflow-ik.la -lm
dist_pipelines_DATA += pipelines/ik-compare.json

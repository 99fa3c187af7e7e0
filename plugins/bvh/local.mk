# The native BVH importer and exporter (bvh.import / bvh.export). The reader and writer are the
# SDK's (sdk/formats/bvh), shared with the format-dispatching converter.
plugins_LTLIBRARIES += plugins/bvh.la
plugins_bvh_la_SOURCES = plugins/bvh/bvh-plugin.c
plugins_bvh_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_bvh_la_LIBADD = sdk/formats/bvh/librigflow-bvh.la -lm

# Tests: reader, writer, number parser and the plugin's nodes (through a stand-in host).
check_PROGRAMS += tests/bvh/test_bvh
TESTS += tests/bvh/test_bvh
tests_bvh_test_bvh_SOURCES = tests/bvh/test_bvh.c
tests_bvh_test_bvh_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/sdk/formats/bvh
tests_bvh_test_bvh_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_bvh_test_bvh_LDADD = sdk/formats/bvh/librigflow-bvh.la $(CMOCKA_LIBS) $(LTDL_LIBS) -lm

# The native BVH importer and exporter.
#
# libbvh (reader, writer, number parser) is a convenience library so that other plugins (e.g. the
# format-dispatching converter) link the same code; plugins/bvh.la is the bvh.import / bvh.export
# module, which exports only rigflow_plugin_entry.
noinst_LTLIBRARIES += plugins/bvh/libbvh.la
plugins_bvh_libbvh_la_SOURCES = \
	plugins/bvh/bvh.h \
	plugins/bvh/bvh-num.h \
	plugins/bvh/bvh-math.h \
	plugins/bvh/bvh-num.c \
	plugins/bvh/bvh-euler.c \
	plugins/bvh/bvh-read.c \
	plugins/bvh/bvh-write.c
plugins_bvh_libbvh_la_LIBADD = -lm

plugins_LTLIBRARIES += plugins/bvh.la
plugins_bvh_la_SOURCES = plugins/bvh/bvh-plugin.c
plugins_bvh_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_bvh_la_LIBADD = plugins/bvh/libbvh.la -lm

# Tests: reader, writer, number parser and the plugin's nodes (through a stand-in host).
check_PROGRAMS += tests/bvh/test_bvh
TESTS += tests/bvh/test_bvh
tests_bvh_test_bvh_SOURCES = tests/bvh/test_bvh.c
tests_bvh_test_bvh_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins/bvh
tests_bvh_test_bvh_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_bvh_test_bvh_LDADD = plugins/bvh/libbvh.la $(CMOCKA_LIBS) $(LTDL_LIBS) -lm

# Mapping files: libmapfile (reader, resolver, writer; linked by the nodes, `rigflow
# map`, the tests and the fuzzers) and the mapping.read / mapping.write plugin.
noinst_LTLIBRARIES += plugins/mapping-file/libmapfile.la
plugins_mapping_file_libmapfile_la_SOURCES = \
	plugins/mapping-file/mapfile.h \
	plugins/mapping-file/mapfile-internal.h \
	plugins/mapping-file/mapfile-read.c \
	plugins/mapping-file/mapfile-resolve.c \
	plugins/mapping-file/mapfile-write.c
plugins_mapping_file_libmapfile_la_CFLAGS = $(AM_CFLAGS) $(JANSSON_CFLAGS)
plugins_mapping_file_libmapfile_la_LIBADD = $(JANSSON_LIBS) -lm

plugins_LTLIBRARIES += plugins/mapping-file.la
plugins_mapping_file_la_SOURCES = plugins/mapping-file/plugin.c
plugins_mapping_file_la_CPPFLAGS = $(AM_CPPFLAGS) -D_POSIX_C_SOURCE=200809L
plugins_mapping_file_la_CFLAGS = $(AM_CFLAGS) $(JANSSON_CFLAGS)
plugins_mapping_file_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_mapping_file_la_LIBADD = plugins/mapping-file/libmapfile.la

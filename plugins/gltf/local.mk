# The glTF 2.0 / GLB writer (convenience library librfgltf, linked by the export node and tests).
noinst_LTLIBRARIES += plugins/gltf/librfgltf.la
plugins_gltf_librfgltf_la_SOURCES = plugins/gltf/gltf-write.h plugins/gltf/gltf-write.c
plugins_gltf_librfgltf_la_CFLAGS = $(AM_CFLAGS) $(JANSSON_CFLAGS)
plugins_gltf_librfgltf_la_LIBADD = $(JANSSON_LIBS) -lm

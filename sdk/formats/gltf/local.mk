# The glTF 2.0 / GLB writer (rigflow/gltf-write.h), linked by the export node and the tests, and
# installed for plugins out of tree (`rigflow-gltf`).
lib_LTLIBRARIES += sdk/formats/gltf/librigflow-gltf.la
sdk_formats_gltf_librigflow_gltf_la_SOURCES = sdk/formats/gltf/gltf-write.c sdk/formats/gltf/gltf-axes.c \
	sdk/formats/gltf/gltf-axes.h
sdk_formats_gltf_librigflow_gltf_la_CFLAGS = $(AM_CFLAGS) $(SDK_LIB_CFLAGS) $(JANSSON_CFLAGS)
sdk_formats_gltf_librigflow_gltf_la_LDFLAGS = $(SDK_LIB_LDFLAGS)
sdk_formats_gltf_librigflow_gltf_la_LIBADD = $(JANSSON_LIBS) -lm
rigflowinclude_HEADERS += sdk/include/rigflow/gltf-write.h
pkgconfig_DATA += sdk/rigflow-gltf.pc

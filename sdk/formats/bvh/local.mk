# The BVH reader, writer and number parser (rigflow/bvh.h): shared by the bvh plugin and the
# format-dispatching converter, and installed for plugins out of tree (`rigflow-bvh`).
lib_LTLIBRARIES += sdk/formats/bvh/librigflow-bvh.la
sdk_formats_bvh_librigflow_bvh_la_SOURCES = \
	sdk/formats/bvh/bvh-num.h \
	sdk/formats/bvh/bvh-math.h \
	sdk/formats/bvh/bvh-num.c \
	sdk/formats/bvh/bvh-euler.c \
	sdk/formats/bvh/bvh-read.c \
	sdk/formats/bvh/bvh-write.c
sdk_formats_bvh_librigflow_bvh_la_CFLAGS = $(AM_CFLAGS) $(SDK_LIB_CFLAGS)
sdk_formats_bvh_librigflow_bvh_la_LDFLAGS = $(SDK_LIB_LDFLAGS)
sdk_formats_bvh_librigflow_bvh_la_LIBADD = -lm
rigflowinclude_HEADERS += sdk/include/rigflow/bvh.h
pkgconfig_DATA += sdk/rigflow-bvh.pc

# Assimp scenes into the data model (rigflow/aimport.h: skeleton, clips, merged skinned mesh;
# rigflow/aimport-node.h: the import node's process), shared by the assimp plugin and the
# format-dispatching converter, and installed for plugins out of tree (`rigflow-assimp`).
lib_LTLIBRARIES += sdk/formats/assimp/librigflow-assimp.la
sdk_formats_assimp_librigflow_assimp_la_SOURCES = \
	sdk/formats/assimp/aimport-internal.h \
	sdk/formats/assimp/aimport.c \
	sdk/formats/assimp/aimport-mesh.c \
	sdk/formats/assimp/aimport-look.c \
	sdk/formats/assimp/aimport-anim.c \
	sdk/formats/assimp/aimport-node.c \
	sdk/formats/assimp/aimport-node-import.c \
	sdk/formats/assimp/aimport-io.h \
	sdk/formats/assimp/aimport-io.c
sdk_formats_assimp_librigflow_assimp_la_CFLAGS = $(AM_CFLAGS) $(SDK_LIB_CFLAGS) $(ASSIMP_CFLAGS)
sdk_formats_assimp_librigflow_assimp_la_LDFLAGS = $(SDK_LIB_LDFLAGS)
sdk_formats_assimp_librigflow_assimp_la_LIBADD = $(ASSIMP_LIBS) -lm
rigflowinclude_HEADERS += sdk/include/rigflow/aimport.h sdk/include/rigflow/aimport-node.h
pkgconfig_DATA += sdk/rigflow-assimp.pc

# The Assimp importer: librfassimp (scene to skeleton, clip, merged skinned mesh; linked by the
# generic import node and the tests) and the assimp.import plugin.
noinst_LTLIBRARIES += plugins/assimp/librfassimp.la
plugins_assimp_librfassimp_la_SOURCES = \
	plugins/assimp/aimport.h \
	plugins/assimp/aimport-internal.h \
	plugins/assimp/aimport.c \
	plugins/assimp/aimport-mesh.c \
	plugins/assimp/aimport-look.c \
	plugins/assimp/aimport-anim.c \
	plugins/assimp/aimport-node.h \
	plugins/assimp/aimport-node.c \
	plugins/assimp/aimport-io.h \
	plugins/assimp/aimport-io.c
plugins_assimp_librfassimp_la_CFLAGS = $(AM_CFLAGS) $(ASSIMP_CFLAGS)
plugins_assimp_librfassimp_la_LIBADD = $(ASSIMP_LIBS) -lm

plugins_LTLIBRARIES += plugins/assimp.la
plugins_assimp_la_SOURCES = plugins/assimp/plugin.c
plugins_assimp_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_assimp_la_LIBADD = plugins/assimp/librfassimp.la

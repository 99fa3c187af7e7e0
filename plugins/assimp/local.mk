# The assimp.import plugin; the scene import itself is the SDK's (sdk/formats/assimp), shared
# with the format-dispatching converter.
plugins_LTLIBRARIES += plugins/assimp.la
plugins_assimp_la_SOURCES = plugins/assimp/plugin.c
plugins_assimp_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_assimp_la_LIBADD = sdk/formats/assimp/librigflow-assimp.la $(ASSIMP_LIBS)

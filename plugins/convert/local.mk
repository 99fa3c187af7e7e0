# Format-dispatching import and export nodes (pipelines/convert.json): BVH through the SDK's BVH library, the
# rest through its Assimp import and glTF writer (sdk/formats). A static library's own libraries are
# not carried into a module by libtool, so they are named here.
plugins_LTLIBRARIES += plugins/convert.la
plugins_convert_la_SOURCES = plugins/convert/convert.c
plugins_convert_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_convert_la_LIBADD = sdk/formats/assimp/librigflow-assimp.la sdk/formats/gltf/librigflow-gltf.la \
	sdk/formats/bvh/librigflow-bvh.la $(ASSIMP_LIBS) $(JANSSON_LIBS)

dist_pipelines_DATA += pipelines/convert.json

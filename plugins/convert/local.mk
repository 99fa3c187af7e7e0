# Format-dispatching import and export nodes (pipelines/convert.json): BVH through libbvh, the
# rest through Assimp (librfassimp) and our glTF writer (librfgltf).
plugins_LTLIBRARIES += plugins/convert.la
plugins_convert_la_SOURCES = plugins/convert/convert.c
plugins_convert_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_convert_la_LIBADD = plugins/assimp/librfassimp.la plugins/gltf/librfgltf.la \
	plugins/bvh/libbvh.la

dist_pipelines_DATA += pipelines/convert.json

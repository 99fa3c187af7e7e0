# Format-dispatching import and export nodes (pipelines/convert.json): BVH through the SDK's BVH library, the
# rest through its Assimp import and glTF writer (sdk/formats). A static library's own libraries are
# not carried into a module by libtool, so they are named here.
plugins_LTLIBRARIES += plugins/convert.la
plugins_convert_la_SOURCES = plugins/convert/convert.c plugins/convert/bone-mesh.c plugins/convert/bone-mesh.h
plugins_convert_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_convert_la_LIBADD = sdk/formats/assimp/librigflow-assimp.la sdk/formats/gltf/librigflow-gltf.la \
	sdk/formats/bvh/librigflow-bvh.la $(JANSSON_LIBS)
# The Assimp import, loaded by the plugin on first use from beside it (convert-assimp.c): libassimp
# is opened only by runs that import a model. Named .mod: the host opens every .so of a plugin
# folder as a plugin.
plugins_LTLIBRARIES += plugins/convert-assimp.la
plugins_convert_assimp_la_SOURCES = plugins/convert/convert-assimp.c plugins/convert/convert-assimp.h
plugins_convert_assimp_la_LDFLAGS = -module -avoid-version -no-undefined -shared -shrext .mod \
	-export-symbols-regex '^rf_cv_assimp_import$$'
plugins_convert_assimp_la_LIBADD = sdk/formats/assimp/librigflow-assimp.la $(ASSIMP_LIBS)

dist_pipelines_DATA += pipelines/convert.json

# The transform node: a skeleton and its mesh scaled, turned and moved together (rig-bench's
# --turn, --scale and --offset measure the riggers on turned, scaled and moved models with it).
plugins_LTLIBRARIES += plugins/transform.la
plugins_transform_la_SOURCES = plugins/transform/transform.c
plugins_transform_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_transform_la_LIBADD = -lm

# Retargeting: the library (libretarget: plan, frame, clip, contact pass, measures and their JSON
# report, written with jansson; linked by the plugin, the tests and the benchmarks) and the
# retarget plugin (node types retarget and retarget.measure).
noinst_LTLIBRARIES += plugins/retarget/libretarget.la
plugins_retarget_libretarget_la_SOURCES = \
	plugins/retarget/retarget.h \
	plugins/retarget/rt-internal.h \
	plugins/retarget/rt-body.c \
	plugins/retarget/rt-plan.c \
	plugins/retarget/rt-frame.c \
	plugins/retarget/rt-clip.c \
	plugins/retarget/rt-contact.c \
	plugins/retarget/rt-measure.c \
	plugins/retarget/rt-roles.c \
	plugins/retarget/rt-mesh.c \
	plugins/retarget/rt-volume.c \
	plugins/retarget/rt-report.c
plugins_retarget_libretarget_la_CFLAGS = $(AM_CFLAGS) $(JANSSON_CFLAGS)
plugins_retarget_libretarget_la_LIBADD = $(JANSSON_LIBS) -lpthread -lm

plugins_LTLIBRARIES += plugins/retarget.la
plugins_retarget_la_SOURCES = plugins/retarget/plugin.c
plugins_retarget_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_retarget_la_LIBADD = plugins/retarget/libretarget.la sdk/analysis/librigflow-analysis.la

dist_pipelines_DATA += pipelines/retarget.json pipelines/retarget-many.json

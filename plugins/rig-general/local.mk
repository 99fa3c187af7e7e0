# The general auto-rigger: librigauto (clean-up, voxel skeleton, bone heat; linked by the plugin
# and the tests, with the analysis library beside it) and the rig.general plugin. CHOLMOD, Embree and meshoptimizer are
# checked by configure.ac (doc/autorig.md says what each does). The pipelines: autorig (a mesh
# to a skinned GLB) and scan-to-animation (a mesh and a motion file to an animated GLB).
noinst_LTLIBRARIES += plugins/rig-general/librigauto.la
plugins_rig_general_librigauto_la_SOURCES = \
	plugins/rig-general/rig.h \
	plugins/rig-general/rig-internal.h \
	plugins/rig-general/rig-embree.h \
	plugins/rig-general/rig.c \
	plugins/rig-general/rig-mesh.c \
	plugins/rig-general/rig-skel.c \
	plugins/rig-general/rig-heat.c \
	plugins/rig-general/rig-place.c \
	plugins/rig-general/rig-frame.c \
	plugins/rig-general/rig-template.c \
	plugins/rig-general/rig-foot.c
plugins_rig_general_librigauto_la_LIBADD = $(CHOLMOD_LIBS) $(EMBREE_LIBS) $(MESHOPT_LIBS) -lm

plugins_LTLIBRARIES += plugins/rig-general.la
plugins_rig_general_la_SOURCES = plugins/rig-general/plugin.c plugins/rig-general/rig-node.h \
	plugins/rig-general/rig-node.c
# Embree's task threads (TBB) outlive a call and run library code until the process exits:
# the plugin, and with it Embree, must stay loaded when the host closes its plugins.
plugins_rig_general_la_LDFLAGS = $(PLUGIN_LDFLAGS) -Wl,-z,nodelete
plugins_rig_general_la_LIBADD = plugins/rig-general/librigauto.la sdk/analysis/librigflow-analysis.la

# The template rigger: a second plugin on the same core (rig-template.c), rig.template.
plugins_LTLIBRARIES += plugins/rig-template.la
plugins_rig_template_la_SOURCES = plugins/rig-general/plugin-template.c \
	plugins/rig-general/rig-node.h plugins/rig-general/rig-node.c
plugins_rig_template_la_LDFLAGS = $(PLUGIN_LDFLAGS) -Wl,-z,nodelete
plugins_rig_template_la_LIBADD = plugins/rig-general/librigauto.la sdk/analysis/librigflow-analysis.la

dist_pipelines_DATA += pipelines/autorig.json pipelines/scan-to-animation.json \
	pipelines/autorig-template.json pipelines/scan-to-animation-template.json

# librigflow (the host library) and the rigflow command.
# Installed for hosts that embed the engine (batch runners, tools); plugins never link it.
lib_LTLIBRARIES = framework/librigflow.la
framework_librigflow_la_SOURCES = \
	framework/rigflow-host.h \
	framework/diag.c \
	framework/registry.c \
	framework/plugin-index.c \
	framework/plugin-index.h \
	framework/host.c \
	framework/pipeline.c \
	framework/validate.c \
	framework/run.c \
	framework/run-group.c \
	framework/pipeline-internal.h
framework_librigflow_la_CPPFLAGS = $(AM_CPPFLAGS) -DRF_PLUGINSDIR='"$(pluginsdir)"'
framework_librigflow_la_CFLAGS = $(AM_CFLAGS) $(GLIB_CFLAGS) $(JANSSON_CFLAGS)
framework_librigflow_la_LIBADD = $(GLIB_LIBS) $(JANSSON_LIBS) $(LTDL_LIBS) -lm
framework_librigflow_la_LDFLAGS = -version-info 1:0:0 -no-undefined
rigflowinclude_HEADERS += framework/rigflow-host.h
pkgconfig_DATA += framework/rigflow.pc

bin_PROGRAMS += rigflow
rigflow_SOURCES = framework/rigflow.c framework/commands.h framework/cmd-info.c framework/cmd-check.c
rigflow_CPPFLAGS = $(AM_CPPFLAGS) -DRF_PLUGINSDIR='"$(pluginsdir)"'
rigflow_CFLAGS = $(AM_CFLAGS) $(GLIB_CFLAGS) $(JANSSON_CFLAGS)
rigflow_LDADD = framework/librigflow.la $(GLIB_LIBS)

dist_pipelines_DATA += pipelines/bvh-roundtrip.json

# rigflow inspect FILE: prints what an importer makes of a file.
rigflow_SOURCES += framework/inspect.c framework/inspect.h
rigflow_LDADD += $(JANSSON_LIBS)

# rigflow ik-bench: the IK solvers on the standard workloads.
rigflow_SOURCES += framework/ik-bench.c framework/ik-bench.h
rigflow_CPPFLAGS +=
rigflow_LDADD += sdk/ik/librigflow-ik.la

# rigflow map: the graph of pipelines/map.json from the command line.
rigflow_SOURCES += framework/map-cmd.c framework/map-cmd.h

# rigflow report: pipelines/retarget.json with its HTML report (doc/report.md).
rigflow_SOURCES += framework/report-cmd.c framework/report-cmd.h
rigflow_CPPFLAGS += -DRF_PIPELINESDIR='"$(pipelinesdir)"' \
	-DRF_SRC_PIPELINESDIR='"$(abs_top_srcdir)/pipelines"'

# rigflow rig-bench: the rigger plugins against artists' rigs (doc/autorig.md), through pipelines
# it builds in memory; the skeleton analysis tells humanoids from other bodies.
rigflow_SOURCES += framework/rig-bench.c framework/rig-bench.h framework/rig-bench-look.c \
	framework/rig-bench-look.h
rigflow_LDADD += sdk/analysis/librigflow-analysis.la

# rigflow batch: a pipeline over whole libraries, on a worker pool or a Slurm job array.
rigflow_SOURCES += framework/batch.c framework/batch.h framework/batch-pool.c \
	framework/batch-manifest.c framework/batch-slurm.c
rigflow_CFLAGS += $(NETTLE_CFLAGS)
rigflow_LDADD += $(NETTLE_LIBS)

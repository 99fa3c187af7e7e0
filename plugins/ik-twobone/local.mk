# Analytic two-bone solver: the solver as a convenience library (tests link it), and the ik.twobone module.
noinst_LTLIBRARIES += plugins/ik-twobone/libiktwobone.la
plugins_ik_twobone_libiktwobone_la_SOURCES = plugins/ik-twobone/twobone.c plugins/ik-twobone/twobone.h
plugins_ik_twobone_libiktwobone_la_CPPFLAGS = $(IK_CPPFLAGS)

plugins_LTLIBRARIES += plugins/ik-twobone.la
plugins_ik_twobone_la_SOURCES = plugins/ik-twobone/plugin.c
plugins_ik_twobone_la_CPPFLAGS = $(IK_CPPFLAGS)
plugins_ik_twobone_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_ik_twobone_la_LIBADD = plugins/ik-twobone/libiktwobone.la sdk/ik/librigflow-ik.la -lm

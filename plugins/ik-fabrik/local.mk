# FABRIK solver: the solver as a convenience library (tests link it), and the ik.fabrik module.
noinst_LTLIBRARIES += plugins/ik-fabrik/libikfabrik.la
plugins_ik_fabrik_libikfabrik_la_SOURCES = plugins/ik-fabrik/fabrik.c plugins/ik-fabrik/fabrik.h
plugins_ik_fabrik_libikfabrik_la_CPPFLAGS = $(IK_CPPFLAGS)

plugins_LTLIBRARIES += plugins/ik-fabrik.la
plugins_ik_fabrik_la_SOURCES = plugins/ik-fabrik/plugin.c
plugins_ik_fabrik_la_CPPFLAGS = $(IK_CPPFLAGS)
plugins_ik_fabrik_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_ik_fabrik_la_LIBADD = plugins/ik-fabrik/libikfabrik.la sdk/ik/librigflow-ik.la -lm

# CCD solver: the solver as a convenience library (tests link it), and the ik.ccd module.
noinst_LTLIBRARIES += plugins/ik-ccd/libikccd.la
plugins_ik_ccd_libikccd_la_SOURCES = plugins/ik-ccd/ccd.c plugins/ik-ccd/ccd.h
plugins_ik_ccd_libikccd_la_CPPFLAGS = $(IK_CPPFLAGS)

plugins_LTLIBRARIES += plugins/ik-ccd.la
plugins_ik_ccd_la_SOURCES = plugins/ik-ccd/plugin.c
plugins_ik_ccd_la_CPPFLAGS = $(IK_CPPFLAGS)
plugins_ik_ccd_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_ik_ccd_la_LIBADD = plugins/ik-ccd/libikccd.la sdk/ik/librigflow-ik.la -lm

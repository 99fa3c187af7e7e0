# Code shared by the IK solver plugins (problem checks, forward kinematics, limits, small linear
# algebra, node boilerplate) and the IK workloads of `rigflow ik-bench` and ik.compare. A
# convenience library: linked statically into each user, never installed.
noinst_LTLIBRARIES += plugins/ik-common/libikcommon.la
plugins_ik_common_libikcommon_la_SOURCES = \
	plugins/ik-common/ikcommon.h \
	plugins/ik-common/ikcommon.c \
	plugins/ik-common/constraint.c \
	plugins/ik-common/linalg.c \
	plugins/ik-common/node.c
plugins_ik_common_libikcommon_la_LIBADD = -lm
IK_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins/ik-common
plugins_ik_common_libikcommon_la_CPPFLAGS = $(IK_CPPFLAGS)
rigflowinclude_HEADERS += sdk/include/rigflow/ik.h

# The IK workloads and their measurement, CSV and SVG: for `rigflow ik-bench` and ik.compare.
noinst_LTLIBRARIES += plugins/ik-common/libikworkload.la
plugins_ik_common_libikworkload_la_SOURCES = plugins/ik-common/workload.c \
	plugins/ik-common/workload.h
plugins_ik_common_libikworkload_la_CPPFLAGS = $(IK_CPPFLAGS)
plugins_ik_common_libikworkload_la_LIBADD = -lm

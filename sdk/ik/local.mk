# IK building blocks (rigflow/ik-common.h): problem checks, forward kinematics, limits, the pole
# swivel, small linear algebra and the solver node boilerplate, shared by every IK solver plugin;
# and the standard IK workloads (rigflow/ik-workload.h) of `rigflow ik-bench` and ik.compare.
# An installed SDK library (`pkg-config --libs rigflow-ik`), static and position-independent.
lib_LTLIBRARIES += sdk/ik/librigflow-ik.la
sdk_ik_librigflow_ik_la_SOURCES = \
	sdk/ik/ikcommon.c \
	sdk/ik/constraint.c \
	sdk/ik/linalg.c \
	sdk/ik/node.c \
	sdk/ik/workload.c
sdk_ik_librigflow_ik_la_CFLAGS = $(AM_CFLAGS) $(SDK_LIB_CFLAGS)
sdk_ik_librigflow_ik_la_LDFLAGS = $(SDK_LIB_LDFLAGS)
sdk_ik_librigflow_ik_la_LIBADD = -lm
rigflowinclude_HEADERS += sdk/include/rigflow/ik.h sdk/include/rigflow/ik-common.h \
	sdk/include/rigflow/ik-workload.h
pkgconfig_DATA += sdk/rigflow-ik.pc
IK_CPPFLAGS = $(AM_CPPFLAGS)

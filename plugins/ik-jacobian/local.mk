# Jacobian solvers (transpose, pseudoinverse, damped least squares): a convenience library (tests
# link it), and one module with the three node types.
noinst_LTLIBRARIES += plugins/ik-jacobian/libikjacobian.la
plugins_ik_jacobian_libikjacobian_la_SOURCES = plugins/ik-jacobian/jacobian.c \
	plugins/ik-jacobian/jacobian.h
plugins_ik_jacobian_libikjacobian_la_CPPFLAGS = $(IK_CPPFLAGS)

plugins_LTLIBRARIES += plugins/ik-jacobian.la
plugins_ik_jacobian_la_SOURCES = plugins/ik-jacobian/plugin.c
plugins_ik_jacobian_la_CPPFLAGS = $(IK_CPPFLAGS)
plugins_ik_jacobian_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_ik_jacobian_la_LIBADD = plugins/ik-jacobian/libikjacobian.la \
	sdk/ik/librigflow-ik.la -lm

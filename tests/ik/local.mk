# IK tests: the solvers against geometry (linked from their convenience libraries).
IK_TEST_CPPFLAGS = $(IK_CPPFLAGS) -I$(top_srcdir)/plugins/ik-fabrik \
	-I$(top_srcdir)/plugins/ik-ccd -I$(top_srcdir)/plugins/ik-twobone \
	-I$(top_srcdir)/plugins/ik-jacobian
IK_TEST_LDADD = plugins/ik-fabrik/libikfabrik.la plugins/ik-ccd/libikccd.la \
	plugins/ik-twobone/libiktwobone.la plugins/ik-jacobian/libikjacobian.la \
	sdk/ik/librigflow-ik.la $(CMOCKA_LIBS) -lm

check_PROGRAMS += tests/ik/test_ik_solvers
TESTS += tests/ik/test_ik_solvers
tests_ik_test_ik_solvers_SOURCES = tests/ik/test_ik_solvers.c tests/ik/solvers.h \
	tests/ik/ik-fixtures.c tests/ik/ik-fixtures.h
tests_ik_test_ik_solvers_CPPFLAGS = $(IK_TEST_CPPFLAGS)
tests_ik_test_ik_solvers_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_ik_test_ik_solvers_LDADD = $(IK_TEST_LDADD)

check_PROGRAMS += tests/ik/test_ik_common
TESTS += tests/ik/test_ik_common
tests_ik_test_ik_common_SOURCES = tests/ik/test_ik_common.c tests/ik/ik-fixtures.c \
	tests/ik/ik-fixtures.h
tests_ik_test_ik_common_CPPFLAGS = $(IK_TEST_CPPFLAGS)
tests_ik_test_ik_common_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_ik_test_ik_common_LDADD = $(IK_TEST_LDADD)

# The plugins as loaded by the host, and ik.compare in a pipeline.
check_PROGRAMS += tests/ik/test_ik_pipeline
TESTS += tests/ik/test_ik_pipeline
tests_ik_test_ik_pipeline_SOURCES = tests/ik/test_ik_pipeline.c
tests_ik_test_ik_pipeline_CPPFLAGS = $(HOST_CPPFLAGS)
tests_ik_test_ik_pipeline_CFLAGS = $(AM_CFLAGS) $(GLIB_CFLAGS) $(JANSSON_CFLAGS) $(CMOCKA_CFLAGS)
tests_ik_test_ik_pipeline_LDADD = framework/librigflow.la $(GLIB_LIBS) $(CMOCKA_LIBS) -lm

# rigflow ik-bench from the command line.
TESTS += tests/ik/test_ik_bench.sh
EXTRA_DIST += tests/ik/test_ik_bench.sh

# Host tests: plugin loading and its refusals, pipeline validation, runs.

# One fixture source built as a good plugin and as plugins that each break one loading rule.
FIXTURE_SRC = tests/fixtures/fixture.c
check_LTLIBRARIES += tests/fixtures/fx_good.la tests/fixtures/fx_major.la \
	tests/fixtures/fx_minor.la tests/fixtures/fx_noentry.la tests/fixtures/fx_initfail.la \
	tests/fixtures/fx_dup.la tests/fixtures/fx_unresolved.la tests/fixtures/fx_baddefault.la \
	tests/fixtures/fx_crash.la tests/fixtures/fx_selftest.la tests/fixtures/fx_old.la \
	tests/fixtures/fx_abi10.la tests/fixtures/fx_wide.la tests/fixtures/fx_twice.la
tests_fixtures_fx_twice_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_twice_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_TYPE_TWICE -DFX_ID='"org.rigflow.test.twice"'
tests_fixtures_fx_twice_la_LDFLAGS = $(FIXTURE_LDFLAGS)
# A rigger whose skin names a joint past its skeleton, for rig-bench (test_bad_input.sh); in a
# folder of its own: the fixtures' folder is loaded whole by other tests.
check_LTLIBRARIES += tests/fixtures/rigger/fx_rigger.la
tests_fixtures_rigger_fx_rigger_la_SOURCES = tests/fixtures/fx_rigger.c
tests_fixtures_rigger_fx_rigger_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_rigger_fx_rigger_la_LIBADD = -lm
tests_fixtures_fx_good_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_good_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_major_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_major_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_MAJOR=2 -DFX_ID='"org.rigflow.test.major"'
tests_fixtures_fx_major_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_minor_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_minor_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_MINOR=RF_ABI_VERSION_MINOR+1 \
	-DFX_ID='"org.rigflow.test.minor"'
tests_fixtures_fx_minor_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_noentry_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_noentry_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_NO_ENTRY
tests_fixtures_fx_noentry_la_LDFLAGS = -module -avoid-version -shared -rpath /nowhere
tests_fixtures_fx_initfail_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_initfail_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_INIT_FAILS -DFX_ID='"org.rigflow.test.init"'
tests_fixtures_fx_initfail_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_dup_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_dup_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_ID='"org.rigflow.test.dup"'
tests_fixtures_fx_dup_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_unresolved_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_unresolved_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_UNRESOLVED -DFX_ID='"org.rigflow.test.unresolved"'
tests_fixtures_fx_unresolved_la_LDFLAGS = $(FIXTURE_LDFLAGS)

tests_fixtures_fx_old_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_old_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_MINOR=0 -DFX_ID='"org.rigflow.test.old"'
tests_fixtures_fx_old_la_LDFLAGS = $(FIXTURE_LDFLAGS)
# Built against the frozen ABI 1.0 headers only (tests/abi-1.0), as a plugin from then was.
tests_fixtures_fx_abi10_la_SOURCES = tests/fixtures/fx_abi10.c
tests_fixtures_fx_abi10_la_CPPFLAGS = -I$(top_srcdir)/tests/abi-1.0
tests_fixtures_fx_abi10_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_wide_la_SOURCES = tests/fixtures/fx_wide.c
tests_fixtures_fx_wide_la_LDFLAGS = $(FIXTURE_LDFLAGS)
EXTRA_DIST += tests/abi-1.0
EXTRA_DIST += tests/tap.sh # the TAP helpers sourced by shell tests of several areas
tests_fixtures_fx_baddefault_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_baddefault_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_VALUE_DEFAULT=250
tests_fixtures_fx_baddefault_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_crash_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_crash_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_CRASH_CREATE
tests_fixtures_fx_crash_la_LDFLAGS = $(FIXTURE_LDFLAGS)
tests_fixtures_fx_selftest_la_SOURCES = $(FIXTURE_SRC)
tests_fixtures_fx_selftest_la_CPPFLAGS = $(AM_CPPFLAGS) -DFX_SELFTEST_FAILS
tests_fixtures_fx_selftest_la_LDFLAGS = $(FIXTURE_LDFLAGS)

HOST_TEST_CFLAGS = $(AM_CFLAGS) $(GLIB_CFLAGS) $(JANSSON_CFLAGS) $(CMOCKA_CFLAGS)
HOST_TEST_LIBS = framework/librigflow.la $(GLIB_LIBS) $(JANSSON_LIBS) $(CMOCKA_LIBS)

check_PROGRAMS += tests/test_plugins tests/test_pipeline tests/test_math tests/test_sdk_helpers
TESTS += tests/test_plugins tests/test_pipeline tests/test_math tests/test_sdk_helpers
# model-copy.h with every allocation made to fail in turn
check_PROGRAMS += tests/test_copy_oom
TESTS += tests/test_copy_oom
tests_test_copy_oom_SOURCES = tests/test_copy_oom.c
tests_test_copy_oom_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_test_copy_oom_LDADD = $(CMOCKA_LIBS) -lm
tests_test_plugins_SOURCES = tests/test_plugins.c tests/testutil.h
tests_test_plugins_CPPFLAGS = $(HOST_CPPFLAGS)
tests_test_plugins_CFLAGS = $(HOST_TEST_CFLAGS)
tests_test_plugins_LDADD = $(HOST_TEST_LIBS)
tests_test_pipeline_SOURCES = tests/test_pipeline.c tests/testutil.h
tests_test_pipeline_CPPFLAGS = $(HOST_CPPFLAGS)
tests_test_pipeline_CFLAGS = $(HOST_TEST_CFLAGS)
tests_test_pipeline_LDADD = $(HOST_TEST_LIBS)
tests_test_math_SOURCES = tests/test_math.c
tests_test_math_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_test_math_LDADD = $(CMOCKA_LIBS) -lm
tests_test_sdk_helpers_SOURCES = tests/test_sdk_helpers.c
tests_test_sdk_helpers_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_test_sdk_helpers_LDADD = $(CMOCKA_LIBS) -lm

# The command end to end, with the bundled plugins.
# Ctrl-C during map, inspect and rig-bench: exit 130, nothing left.
TESTS += tests/test_ctrl_c.sh
dist_noinst_SCRIPTS += tests/test_ctrl_c.sh
TESTS += tests/test_cli.sh tests/test_plugin_check.sh tests/test_headers.sh tests/test_sdk.sh \
	tests/test_layout.sh tests/test_plugin_index.sh tests/test_run_jobs.sh
dist_noinst_SCRIPTS += tests/test_cli.sh tests/test_plugin_check.sh tests/test_headers.sh tests/test_layout.sh \
	tests/test_sdk.sh tests/test_plugin_index.sh tests/test_run_jobs.sh
# the tests' plugin index (Makefile.am: AM_TESTS_ENVIRONMENT), kept out of the user's cache
CLEANFILES += tests/plugin-index
EXTRA_DIST += sdk/examples/smooth/smooth.c sdk/examples/smooth/Makefile \
	sdk/examples/match-nearest/match_nearest.c sdk/examples/match-nearest/Makefile
EXTRA_DIST += tests/fixtures/arm.bvh

# Retargeting tests: hand-built skeletons (test_retarget), the shared data (test_retarget_data,
# skipped without $RF_DATA_DIR), and the retarget node through the host with pipelines
# (test_retarget_pipeline.sh, with the test.name-map fixture plugin). The contact pass runs
# through the two-bone solver's library.
RT_TEST_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins/retarget \
	-I$(top_srcdir)/plugins/ik-twobone
RT_TEST_LDADD = plugins/retarget/libretarget.la sdk/analysis/librigflow-analysis.la plugins/ik-twobone/libiktwobone.la \
	sdk/ik/librigflow-ik.la $(CMOCKA_LIBS) -lm

check_PROGRAMS += tests/retarget/test_retarget tests/retarget/test_retarget_data
TESTS += tests/retarget/test_retarget tests/retarget/test_retarget_data
tests_retarget_test_retarget_SOURCES = tests/retarget/test_retarget.c tests/retarget/rt-fixtures.h
tests_retarget_test_retarget_CPPFLAGS = $(RT_TEST_CPPFLAGS)
tests_retarget_test_retarget_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS) $(JANSSON_CFLAGS)
tests_retarget_test_retarget_LDADD = $(RT_TEST_LDADD)
tests_retarget_test_retarget_data_SOURCES = tests/retarget/test_retarget_data.c \
	tests/retarget/rt-maps.h
tests_retarget_test_retarget_data_CPPFLAGS = $(RT_TEST_CPPFLAGS)
tests_retarget_test_retarget_data_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_retarget_test_retarget_data_LDADD = sdk/formats/bvh/librigflow-bvh.la sdk/formats/assimp/librigflow-assimp.la \
	$(RT_TEST_LDADD)

check_PROGRAMS += tests/retarget/test_roles tests/retarget/test_retarget_rerig
TESTS += tests/retarget/test_roles tests/retarget/test_retarget_rerig
tests_retarget_test_retarget_rerig_SOURCES = tests/retarget/test_retarget_rerig.c \
	tests/retarget/rt-maps.h
tests_retarget_test_retarget_rerig_CPPFLAGS = $(RT_TEST_CPPFLAGS)
tests_retarget_test_retarget_rerig_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_retarget_test_retarget_rerig_LDADD = sdk/formats/bvh/librigflow-bvh.la \
	sdk/formats/assimp/librigflow-assimp.la $(RT_TEST_LDADD)
tests_retarget_test_roles_SOURCES = tests/retarget/test_roles.c tests/retarget/rt-fixtures.h
tests_retarget_test_roles_CPPFLAGS = $(RT_TEST_CPPFLAGS)
tests_retarget_test_roles_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_retarget_test_roles_LDADD = sdk/formats/assimp/librigflow-assimp.la \
	sdk/analysis/librigflow-analysis.la $(CMOCKA_LIBS) -lm

check_LTLIBRARIES += tests/retarget/fx_namemap.la
tests_retarget_fx_namemap_la_SOURCES = tests/retarget/fx_namemap.c
tests_retarget_fx_namemap_la_LDFLAGS = $(FIXTURE_LDFLAGS)

TESTS += tests/retarget/test_retarget_pipeline.sh tests/retarget/test_retarget_sweep.sh \
	tests/retarget/test_gait.sh tests/retarget/test_retarget_turned.sh \
	tests/retarget/test_retarget_window.sh
dist_noinst_SCRIPTS += tests/retarget/test_retarget_pipeline.sh \
	tests/retarget/test_retarget_sweep.sh tests/retarget/test_gait.sh \
	tests/retarget/test_retarget_turned.sh tests/retarget/test_retarget_window.sh
EXTRA_DIST += tests/retarget/sweep.mjs tests/retarget/turned.mjs
EXTRA_DIST += tests/retarget/maps

# gait-feet: each leg's foot height over the floor through a clip (test_gait.sh, doc/matching.md)
check_PROGRAMS += tests/retarget/gait-feet
tests_retarget_gait_feet_SOURCES = tests/retarget/gait-feet.c
tests_retarget_gait_feet_CPPFLAGS = $(RT_TEST_CPPFLAGS)
tests_retarget_gait_feet_LDADD = sdk/formats/bvh/librigflow-bvh.la \
	sdk/formats/assimp/librigflow-assimp.la sdk/analysis/librigflow-analysis.la -lm

# The mesh passes with each allocation failing in turn (malloc and calloc wrapped at link time).
check_PROGRAMS += tests/retarget/test_retarget_mesh_oom
TESTS += tests/retarget/test_retarget_mesh_oom
tests_retarget_test_retarget_mesh_oom_SOURCES = tests/retarget/test_retarget_mesh_oom.c \
	tests/retarget/rt-fixtures.h tests/alloc-fail.h
tests_retarget_test_retarget_mesh_oom_CPPFLAGS = $(RT_TEST_CPPFLAGS)
tests_retarget_test_retarget_mesh_oom_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_retarget_test_retarget_mesh_oom_LDFLAGS = -Wl,--wrap=malloc,--wrap=calloc
tests_retarget_test_retarget_mesh_oom_LDADD = $(RT_TEST_LDADD)

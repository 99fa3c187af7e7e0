# The auto-rigger: librigauto on the shared models and on made-up bad input, the pipelines end to
# end. rig-dump and rig-view.py draw a rig for a person to look at, skin-diag compares bone heat on
# an artist's skeleton with the artist's weights (doc/autorig.md).
noinst_PROGRAMS += tests/rig/rig-dump
tests_rig_rig_dump_SOURCES = tests/rig/rig-dump.c
tests_rig_rig_dump_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins/rig-general
tests_rig_rig_dump_LDADD = sdk/formats/assimp/librigflow-assimp.la plugins/rig-general/librigauto.la \
	sdk/analysis/librigflow-analysis.la -lm
EXTRA_DIST += tests/rig/rig-view.py
# rig-fit: the template rigger's layouts fitted to the artist rigs, scored leave-one-out
noinst_PROGRAMS += tests/rig/rig-fit
tests_rig_rig_fit_SOURCES = tests/rig/rig-fit.c
tests_rig_rig_fit_CPPFLAGS = $(tests_rig_rig_dump_CPPFLAGS)
tests_rig_rig_fit_LDADD = $(tests_rig_rig_dump_LDADD)

noinst_PROGRAMS += tests/rig/skin-diag
tests_rig_skin_diag_SOURCES = tests/rig/skin-diag.c
tests_rig_skin_diag_CPPFLAGS = $(tests_rig_rig_dump_CPPFLAGS)
tests_rig_skin_diag_LDADD = $(tests_rig_rig_dump_LDADD)

check_PROGRAMS += tests/rig/test_rig
TESTS += tests/rig/test_rig
tests_rig_test_rig_SOURCES = tests/rig/test_rig.c tests/rig/boxes.c tests/rig/boxes.h
tests_rig_test_rig_CPPFLAGS = $(tests_rig_rig_dump_CPPFLAGS)
tests_rig_test_rig_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_rig_test_rig_LDADD = sdk/formats/assimp/librigflow-assimp.la plugins/rig-general/librigauto.la \
	sdk/analysis/librigflow-analysis.la $(CMOCKA_LIBS) -lm

TESTS += tests/rig/test_rig_pipeline.sh
EXTRA_DIST += tests/rig/test_rig_pipeline.sh
TESTS += tests/rig/test_rig_fit.sh
EXTRA_DIST += tests/rig/test_rig_fit.sh
TESTS += tests/rig/test_rig_all.sh
EXTRA_DIST += tests/rig/test_rig_all.sh
TESTS += tests/rig/test_rig_boxes.sh
EXTRA_DIST += tests/rig/test_rig_boxes.sh
TESTS += tests/rig/test_rig_looks.sh
EXTRA_DIST += tests/rig/test_rig_looks.sh
TESTS += tests/rig/test_rig_invariance.sh
EXTRA_DIST += tests/rig/test_rig_invariance.sh
TESTS += tests/rig/test_rig_tpl_facing.sh
EXTRA_DIST += tests/rig/test_rig_tpl_facing.sh
TESTS += tests/rig/test_rig_bench_look.sh
EXTRA_DIST += tests/rig/test_rig_bench_look.sh
TESTS += tests/rig/test_rig_scan_up.sh
EXTRA_DIST += tests/rig/test_rig_scan_up.sh
# ... and when memory runs out at each of its allocations in turn (malloc and calloc wrapped)
check_PROGRAMS += tests/rig/test_rig_up_oom
TESTS += tests/rig/test_rig_up_oom
tests_rig_test_rig_up_oom_SOURCES = tests/rig/test_rig_up_oom.c tests/rig/boxes.c tests/rig/boxes.h \
	tests/alloc-fail.h
tests_rig_test_rig_up_oom_CPPFLAGS = $(tests_rig_rig_dump_CPPFLAGS)
tests_rig_test_rig_up_oom_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_rig_test_rig_up_oom_LDFLAGS = -Wl,--wrap=malloc,--wrap=calloc
tests_rig_test_rig_up_oom_LDADD = plugins/rig-general/librigauto.la sdk/analysis/librigflow-analysis.la \
	$(CMOCKA_LIBS) -lm
# rig-up: the up the rigger finds from a body whose file declares none, on models turned lying
noinst_PROGRAMS += tests/rig/rig-up
tests_rig_rig_up_SOURCES = tests/rig/rig-up.c
tests_rig_rig_up_CPPFLAGS = $(tests_rig_rig_dump_CPPFLAGS)
tests_rig_rig_up_LDADD = $(tests_rig_rig_dump_LDADD)
TESTS += tests/rig/test_rig_up.sh
EXTRA_DIST += tests/rig/test_rig_up.sh

# creature: a random creature mesh skinned to a generated skeleton (tests/match/gen.c), the
# random set of test_rig_creatures.sh and bench/creatures.sh (doc/autorig.md, "Random creatures")
noinst_PROGRAMS += tests/rig/creature
tests_rig_creature_SOURCES = tests/rig/creature.c tests/match/gen.c tests/match/gen.h
tests_rig_creature_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/tests/match
tests_rig_creature_LDADD = sdk/formats/gltf/librigflow-gltf.la -lm
TESTS += tests/rig/test_rig_creatures.sh
EXTRA_DIST += tests/rig/test_rig_creatures.sh

# rerig: a rigged model's skeleton laid out again in tests/match/gen.c's conventions (a ground
# root, IK helpers, long bones split, frames along the bones), its skin kept: test_rig_rerig.sh
noinst_PROGRAMS += tests/rig/rerig
tests_rig_rerig_SOURCES = tests/rig/rerig.c
tests_rig_rerig_LDADD = sdk/formats/assimp/librigflow-assimp.la sdk/formats/gltf/librigflow-gltf.la -lm
TESTS += tests/rig/test_rig_rerig.sh
EXTRA_DIST += tests/rig/test_rig_rerig.sh

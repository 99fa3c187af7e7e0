# BVH import/export benchmark: bench/bvh/bench_bvh, built only by `make bench-bvh`
# (or `make bench`), and bench/bvh/run.sh, which runs it beside the three.js and Assimp peers.
EXTRA_PROGRAMS += bench/bvh/bench_bvh
bench_bvh_bench_bvh_SOURCES = bench/bvh/bench_bvh.c
bench_bvh_bench_bvh_CPPFLAGS = $(AM_CPPFLAGS)
bench_bvh_bench_bvh_LDADD = sdk/formats/bvh/librigflow-bvh.la -lm
CLEANFILES += bench/bvh/bench_bvh$(EXEEXT)
EXTRA_DIST += bench/bvh/run.sh bench/bvh/ratios.mjs bench/README.md

# BENCH_BVH_ARGS: e.g. --quick or --full (see bench/bvh/run.sh).
bench-bvh: bench/bvh/bench_bvh$(EXEEXT) plugins/bvh.la
	$(SHELL) $(srcdir)/bench/bvh/run.sh '$(abs_top_builddir)' $(BENCH_BVH_ARGS)
bench: bench-bvh
.PHONY: bench bench-bvh

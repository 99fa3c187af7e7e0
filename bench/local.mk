# Benchmarks (run with `make bench`).
EXTRA_DIST += bench/lib.sh # sourced by bench/bvh/run.sh and bench/retarget/run.sh
# IK solvers beside three.js and closed-chain-ik: bench/ik/run.sh [BUILDDIR] [--quick].
EXTRA_DIST += bench/ik/run.sh bench/ik/ratios.mjs
# BVH import beside three.js and Assimp: `make bench-bvh` runs bench/bvh/run.sh.
include bench/bvh/local.mk
# report.html opening time in chromium: `make bench-report` runs bench/report/run.sh.
EXTRA_DIST += bench/report/run.sh bench/report/open.mjs
bench-report: all
	$(SHELL) $(srcdir)/bench/report/run.sh '$(abs_top_builddir)'
bench: bench-report
.PHONY: bench-report
# rigflow batch: -j 1, -j 2, one process per job and a local Slurm: `make bench-batch`.
EXTRA_DIST += bench/batch/run.sh
bench-batch: all
	$(SHELL) $(srcdir)/bench/batch/run.sh '$(abs_top_builddir)' $(BENCH_BATCH_ARGS)
bench: bench-batch
.PHONY: bench-batch
# Random creatures (tests/rig/creature) through both riggers, rig-bench --look and
# scan-to-animation: `make bench-creatures` (BENCH_CREATURES_ARGS: seeds per plan, first seed).
EXTRA_DIST += bench/creatures.sh
bench-creatures: all
	RF_DATA_DIR='$(RF_DATA_DIR)' RF_NPM_DIR='$(RF_NPM_DIR)' \
		$(SHELL) $(srcdir)/bench/creatures.sh '$(abs_top_builddir)' $(BENCH_CREATURES_ARGS)
bench: bench-creatures
.PHONY: bench-creatures

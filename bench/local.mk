# Benchmarks (run with `make bench`).
# IK solvers beside three.js and closed-chain-ik: bench/ik/run.sh [BUILDDIR] [--quick].
EXTRA_DIST += bench/ik/run.sh bench/ik/ratios.mjs
# BVH import beside three.js and Assimp: `make bench-bvh` runs bench/bvh/run.sh.
include bench/bvh/local.mk

# Benchmarks (run with `make bench`).
# IK solvers beside three.js and closed-chain-ik: bench/ik/run.sh [BUILDDIR] [--quick] (issue 6).
EXTRA_DIST += bench/ik/run.sh bench/ik/ratios.mjs
# BVH import beside three.js and Assimp: `make bench-bvh` runs bench/bvh/run.sh (issue 2).
include bench/bvh/local.mk

#!/bin/bash
# IK solvers beside their peers, measured in one run:
#   rigflow ik-bench        our CCD, FABRIK, DLS, ... on the peers' workloads
#   run_three.sh            three.js CCDIKSolver (chains of 2/5/10/30 links)
#   run_dls.sh              closed-chain-ik damped least squares (chains of 2/5/10, 2-effector tree)
# and prints the ratios against the goals: CCD and FABRIK >= 20x faster per solve than three's CCD
# on the same workload, DLS >= 50x faster than closed-chain-ik, FABRIK converging on >= 95% of the
# 10-link targets within 50 iterations.
#
#   bench/ik/run.sh [BUILDDIR] [--quick]
#
# Our side runs three times (before, between and after the peers; the ratio uses the median),
# since times on these shared machines drift by +-30% over a run and one of two runs caught by a
# burst of load would move the mean of two by half of it. --quick runs only the CCD part of
# three's benchmark (bench_three.mjs --ccd-only, what run_three.sh runs for CCD) instead of the
# whole run_three.sh (which also parses and retargets BVH files for minutes).
# The peers need `npm install`: it happens once in a scratch copy ($IK_PEERS_DIR, default
# BUILDDIR/ik-peers), never in ../shared. Output files go to BUILDDIR/ik-bench-out.
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=$top/_build
quick=0
for arg in "$@"; do
    case $arg in
    --quick) quick=1 ;;
    *) build=$(cd "$arg" && pwd) ;;
    esac
done
shared=$top/../shared
rigflow=$build/rigflow
for tool in node npm "$rigflow"; do
    command -v "$tool" >/dev/null || { echo "bench/ik: $tool not found: skipped"; exit 0; }
done
[ -f "$shared/peers/run_three.sh" ] || { echo "bench/ik: $shared/peers not found: skipped"; exit 0; }
export RIGFLOW_PLUGIN_PATH=$build/plugins RF_DATA_DIR=$shared/data
out=$build/ik-bench-out
scratch=${IK_PEERS_DIR:-$build/ik-peers}
peers=$scratch/peers
mkdir -p "$out" "$peers"
rm -f "$out"/*.txt "$out"/*.csv

# A scratch copy of the peers (their scripts install into their own folder) beside a link to the
# shared data, which run_three.sh reads as ../data.
for f in "$shared"/peers/*; do
    case $(basename "$f") in node_modules | out) ;; *) cp -r "$f" "$peers/" ;; esac
done
ln -sfn "$shared/data" "$scratch/data"

workloads=()
for w in chain2-it10 chain2-it50 chain5-it10 chain5-it50 chain10-it10 chain10-it50 chain30-it10 \
    chain30-it50 tree2-it10 tree2-it50; do
    workloads+=(-w "$w")
done
ours() {
    "$rigflow" ik-bench -s ccd -s fabrik -s dls "${workloads[@]}" --min-time 0.3 --reps 3 \
        2>/dev/null >"$out/ours$1.csv"
}
echo "bench/ik: rigflow ik-bench (1/3)" >&2
ours 1
if [ $quick = 1 ]; then
    echo "bench/ik: three.js CCDIKSolver (bench_three.mjs --ccd-only, 3 processes)" >&2
    (cd "$peers" && { [ -d node_modules/three ] || npm install --no-audit --no-fund --silent; } &&
        for i in 1 2 3; do node bench_three.mjs --ccd-only 5 >"$out/three_run$i.txt" 2>&1; done)
else
    echo "bench/ik: three.js (run_three.sh)" >&2
    (cd "$peers" && ./run_three.sh "$out" >/dev/null)
fi
echo "bench/ik: rigflow ik-bench (2/3)" >&2
ours 2
echo "bench/ik: closed-chain-ik (run_dls.sh)" >&2
(cd "$peers" && ./run_dls.sh "$out" >/dev/null)
echo "bench/ik: rigflow ik-bench (3/3)" >&2
ours 3
node "$top/bench/ik/ratios.mjs" "$out"/ours[123].csv -- "$out"/three_run*.txt "$out"/dls_run*.txt

#!/usr/bin/env bash
# report.html opening time (doc/report.md): reports of the CMU walk onto the Fox, a 10,000-frame
# clip onto the Fox and the CMU walk onto a 200-joint skeleton, each opened 5 times in chromium.
# usage: bench/report/run.sh BUILDDIR [REPS]
set -euo pipefail
build=$(cd "${1:?usage: run.sh BUILDDIR [REPS]}" && pwd)
reps=${2:-5}
top=$(cd "$(dirname "$0")/../.." && pwd)
data=${RF_DATA_DIR:-$top/../shared/data}
peers=$top/../shared/peers
export RIGFLOW_PLUGIN_PATH="$build/plugins" RF_NPM_DIR="${RF_NPM_DIR:-$build/npm/node_modules}"
work="$build/bench/report"
mkdir -p "$work"
node "$peers/gen_bvh.mjs" 10000 120 "$work/long.bvh" >/dev/null
node "$top/tests/report/make-bvh.mjs" tail 200 >"$work/tail200.bvh"
page() { # NAME SOURCE TARGET
    "$build/rigflow" run "$top/pipelines/retarget.json" -q -p source.path="$2" -p target.path="$3" \
        -p export.path="$work/$1.glb" -p report.path="$work/$1.html" >/dev/null
    echo "$work/$1.html"
}
fox=$(page fox "$data/bvh/cmu_01_01.bvh" "$data/models/Fox.glb")
long=$(page long-fox "$work/long.bvh" "$data/models/Fox.glb")
tail=$(page tail200 "$data/bvh/cmu_01_01.bvh" "$work/tail200.bvh")
echo "# load average: $(cut -d' ' -f1-3 /proc/loadavg); chromium $(/usr/bin/chromium --version 2>/dev/null | awk '{print $2}')"
node "$top/bench/report/open.mjs" "$reps" "$fox" "$long" "$tail"

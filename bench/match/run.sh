#!/bin/sh
# Joint mapping speed: bench_match times rf_ms_match alone (files imported once) on
# real and synthetic pairs; then `rigflow map --repeat` times the matcher node through the
# engine on the real pairs. No peer does this job; the baseline is the thesis's Table 7
# (0.47 s for 27 bones, 3.1 s for 187).
#
# usage: bench/match/run.sh [BUILDDIR] [--quick]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build=.
quick=
for a in "$@"; do
    case $a in
    --quick) quick=--quick ;;
    -*) echo "usage: $0 [BUILDDIR] [--quick]" >&2; exit 2 ;;
    *) build=$a ;;
    esac
done
build=$(cd "$build" && pwd)
data=${RF_DATA_DIR:-$src/../shared/data}
[ -d "$data/bvh" ] || { echo "run.sh: $data/bvh not found (the shared test data)" >&2; exit 1; }
[ -x "$build/bench/match/bench_match" ] || make -C "$build" bench/match/bench_match >/dev/null

echo "# rf_ms_match alone (median of 7 batches)"
"$build/bench/match/bench_match" "$data" $quick
echo "# rigflow map --repeat (the matcher node through the engine, import excluded)"
export RIGFLOW_PLUGIN_PATH="$build/plugins/.libs"
n=2000
[ -n "$quick" ] && n=200
for pair in "bvh/cmu_01_01.bvh models/Fox.glb" \
    "bvh/cmu_01_01.bvh models/creatures/draconis_fire_dragon.b3d" \
    "models/creatures/draconis_fire_dragon.b3d models/creatures/draconis_jungle_wyvern.b3d"; do
    set -- $pair
    t=$("$build/rigflow" map --repeat $n "$data/$1" "$data/$2" 2>&1 >/dev/null |
        sed -n 's/^map_us_median=//p')
    echo "$(basename "$1") -> $(basename "$2"): map_us_median=$t"
done
echo "# load: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"

#!/bin/sh
# Retargeting beside three.js SkeletonUtils.retargetClip, in the same run:
#   speed    joint-frames per second of ours (no contact pass) and of three.js on the peers'
#            clips, each onto the peers' kind of target (a copy of the source skeleton rescaled
#            0.8-1.2x and rest-jittered), and the machine's memory bandwidth floor (32 bytes per
#            joint-frame, from ../shared/peers/membw);
#   quality  direction fidelity, foot skate and ground of ours (without and with the contact
#            pass) and of three.js, on CMU 01_01 onto human targets with other rest poses and
#            proportions, all measured by the same code (rf_retarget_measure).
#
# usage: bench/retarget/run.sh [BUILDDIR] [--quick]
#   BUILDDIR  a configured build tree (default: the current directory); bench_retarget is
#             built there
#   --quick   one process per tool and short timings (a smoke run, not for the record)
#
# Everything generated goes to $BUILDDIR/bench-retarget. The shared peers folder is read-only,
# so three.js is installed (npm, as pinned by the peers' package.json) into a copy of it there.
set -eu

here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build=.
quick=0
for a in "$@"; do
    case $a in
    --quick) quick=1 ;;
    -*) echo "usage: $0 [BUILDDIR] [--quick]" >&2; exit 2 ;;
    *) build=$a ;;
    esac
done
. "$src/bench/lib.sh"
bench_paths "$build" retarget

[ -d "$data/bvh" ] || { say "run.sh: $data/bvh not found (the shared test data)"; exit 1; }
bench=$build/bench/retarget/bench_retarget
if [ ! -x "$bench" ]; then
    say "building bench_retarget"
    make -C "$build" bench/retarget/bench_retarget >/dev/null
fi
if [ $quick = 1 ]; then procs=1 reps=3 minms=100; else procs=3 reps=5 minms=300; fi

synth=$work/synth_cmu31_10k.bvh
[ -f "$synth" ] || node "$peers/gen_bvh.mjs" 10000 120 "$synth" >&2
files="$data/bvh/cmu_01_01.bvh $data/bvh/boxing_toes.bvh $data/bvh/bandai_walk.bvh $synth"
out=$work/results
rm -rf "$out"
mkdir -p "$out"

# three.js, installed into a writable copy of the peers folder
bench_three

# --- speed: ours and three.js, alternating processes so both see the same machine load ---
i=1
while [ $i -le $procs ]; do
    say "== speed, round $i of $procs"
    # shellcheck disable=SC2086
    "$bench" speed --reps $reps --min-ms $minms $files | tee "$out/ours_run$i.txt" | grep -v RESULT >&2
    : >"$out/three_run$i.txt"
    for f in $files; do
        MIN_MS=$minms node "$tpeers/bench_three.mjs" "$f" $reps >>"$out/three_run$i.txt" 2>&1
    done
    grep -h '^retargetClip' "$out/three_run$i.txt" >&2 || true
    i=$((i + 1))
done

# --- the memory bandwidth floor ---
membw=$work/membw
if [ ! -x "$membw" ]; then
    ${CC:-cc} -O3 -march=native -fopenmp "$peers/membw/membw.c" -o "$membw" >&2 ||
        ${CC:-cc} -O3 -fopenmp "$peers/membw/membw.c" -o "$membw" >&2
fi
say "== memory bandwidth (membw)"
"$membw" 256 5 | tee "$out/membw.txt" >&2

# --- quality: ours and three.js on the same pairs ---
say "== quality (CMU 01_01 onto human targets)"
maps=$src/tests/retarget/maps
: >"$out/quality.txt"
for pair in "bvh/boxing_toes.bvh boxing_toes" "models/RiggedFigure.glb RiggedFigure" \
    "models/greenman.glb greenman" "models/BCN_Epileptic.X BCN_Epileptic" \
    "bvh/bandai_walk.bvh bandai"; do
    set -- $pair
    name=$2
    "$bench" export "$data/bvh/cmu_01_01.bvh" "$data/$1" "$maps/$name.txt" "$work/$name.json"
    NODE_PATH=$tpeers/node_modules node "$here/three_retarget.mjs" "$data/bvh/cmu_01_01.bvh" \
        "$work/$name.json" "$work/$name.three.bin" >&2
    "$bench" measure "$data/bvh/cmu_01_01.bvh" "$data/$1" "$maps/$name.txt" \
        "$work/$name.three.bin" | tee -a "$out/quality.txt" | grep -v RESULT >&2
done

node "$here/ratios.mjs" "$out"

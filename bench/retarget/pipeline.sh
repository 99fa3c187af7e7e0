#!/bin/sh
# The whole retarget pipeline beside three.js, on the 10,000-frame benchmark clip: the wall time
# of `rigflow run pipelines/retarget.json` (one process: import, matcher, retarget with the
# contact pass and the mesh floor, export, summary and the measures, mesh measures included)
# against three.js's BVHLoader.parse plus SkeletonUtils.retargetClip in one node process (the
# peers' bench_three.mjs, medians of its reps). Medians of 5 rigflow processes.
# The 10,000-frame clip is random motion: its feet never touch the floor, so the contact pass
# finds nothing to pin. A second line times the same on CMU 01_01 (a 2,752-frame walk, where
# the pass pins both feet in about 4,000 foot-frames) when ../shared/data has it: reported
# beside the first, not in its place.
#
# usage: bench/retarget/pipeline.sh [BUILDDIR] [TARGET]
#   BUILDDIR  a built tree (default: the current directory); three.js is looked for where
#             `make bench-retarget` installs it (BUILDDIR/bench-retarget/peers)
#   TARGET    the model retargeted onto (default: ../shared/data/models/RiggedFigure.glb)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build=$(cd "${1:-.}" && pwd)
shared=${RF_SHARED_DIR:-$src/../shared}
data=${RF_DATA_DIR:-$shared/data}
target=${2:-$data/models/RiggedFigure.glb}
work=$build/bench-retarget
mkdir -p "$work"
synth=$work/synth_cmu31_10k.bvh
[ -f "$synth" ] || node "$shared/peers/gen_bvh.mjs" 10000 120 "$synth" >&2
tpeers=${THREE_PEERS:-$work/peers}
[ -d "$tpeers/node_modules/three" ] || {
    echo "pipeline.sh: three.js not installed in $tpeers (run make bench-retarget once)" >&2
    exit 1
}
export RIGFLOW_PLUGIN_PATH="$build/plugins"
# The plugin index of this build alone: one shared with another build (the user's cache, which
# every build tree on the machine writes) is found stale whenever the other build ran last, and a
# run with a stale index opens every plugin to enter them again (the auto-rigger's Embree, TBB
# and CHOLMOD included): 9-22 ms for `rigflow validate` of the retarget pipeline here, against
# 2.3-4.2 ms with its index, time the run being timed does not otherwise spend.
export RIGFLOW_PLUGIN_INDEX="${RIGFLOW_PLUGIN_INDEX:-$work/plugin-index}"
# In a libtool build tree, $build/rigflow is a bash script that finds the real program in .libs
# and execs it with its library path set (forking sed and ls on the way): 10-20 ms that an
# installed rigflow never spends. The real program is timed, with that library path.
rigflow=$build/rigflow
if [ -x "$build/.libs/rigflow" ]; then
    rigflow=$build/.libs/rigflow
    LD_LIBRARY_PATH="$build/framework/.libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    export LD_LIBRARY_PATH
fi
load=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)
echo "load average before: $load"

# bench LABEL BVH: rigflow's median of 5 processes and three.js's in-process medians on one clip.
bench() {
    label=$1 clip=$2 times=""
    # Run 0 is not timed: it reads the files into the page cache and enters the plugins in the
    # plugin index, as any earlier run on the machine would have (three.js's medians are warm too).
    # Each run writes a new file: the previous run's output is removed before the clock starts.
    # Replacing a file makes ext4 free the old one's blocks inside the rename (1-6 ms here, on a
    # file system mounted with `discard`): the file system's work on the last run's output.
    for i in 0 1 2 3 4 5; do
        rm -f "$work/pipeline_out.glb"
        t0=$(date +%s%N)
        "$rigflow" -q run "$src/pipelines/retarget.json" -p "source.path=$clip" \
            -p "target.path=$target" -p "export.path=$work/pipeline_out.glb" >/dev/null
        t1=$(date +%s%N)
        [ "$i" = 0 ] || times="$times $(((t1 - t0) / 1000000))"
    done
    ours=$(printf '%s\n' $times | sort -n | sed -n 3p)
    three=$(cd "$tpeers" && MIN_MS=300 node bench_three.mjs "$clip" 3 2>/dev/null |
        awk '/^parse: median/ {p = $3} /^retargetClip: median/ {r = $3} END {print p + r}')
    echo "$label: rigflow pipeline (whole process, median of 5):$times -> $ours ms"
    echo "$label: three.js parse + retargetClip (in-process medians): $three ms"
    echo "$label: ratio: $(echo "$three $ours" | awk '{printf "%.1f", $1 / $2}')x"
}

bench "random 10k" "$synth"
walk=$data/bvh/cmu_01_01.bvh
if [ -f "$walk" ]; then
    bench "walk (CMU 01_01, contacts)" "$walk"
else
    echo "walk (CMU 01_01, contacts): skipped, $walk not found"
fi
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"

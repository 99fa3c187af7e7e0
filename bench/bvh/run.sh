#!/bin/sh
# BVH import throughput of libbvh beside three.js's BVHLoader and Assimp's BVH import, measured
# in the same run on the same files, with the ratios. (goal >= 20x three.js, >= 10x
# Assimp in MB/s, peak memory <= 2x the decoded data)
#
# usage: bench/bvh/run.sh [BUILDDIR] [--quick] [--full]
#   BUILDDIR  a configured build tree (default: the current directory); bench_bvh is built there
#   --quick   1 process per tool and shorter timings (a smoke run, not for the record)
#   --full    run the peers' own scripts unchanged (run_three.sh also times retargeting and CCD,
#             several minutes); by default three.js runs bench_three.mjs --no-retarget, the same
#             parse measurement without the unrelated ones
#
# Files: ../shared/data/bvh/{cmu_01_01,boxing_toes,bandai_walk}.bvh and a 10k-frame synthetic
# CMU-layout file from ../shared/peers/gen_bvh.mjs (as the peers' scripts use), plus a 100k-frame
# one for our memory figure only. Everything generated goes to $BUILDDIR/bench-bvh (never into
# the repository or ../shared). The shared peers folder is read-only, so three.js is installed
# (npm, pinned by the peers' package.json) into a copy of it there.
#
# Output: one line per tool and file, then RESULT lines and a ratio table (bench/bvh/ratios.mjs).
set -eu

here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build=.
quick=0
full=0
for a in "$@"; do
    case $a in
    --quick) quick=1 ;;
    --full) full=1 ;;
    -*) echo "usage: $0 [BUILDDIR] [--quick] [--full]" >&2; exit 2 ;;
    *) build=$a ;;
    esac
done
. "$src/bench/lib.sh"
bench_paths "$build" bvh

[ -d "$data/bvh" ] || { say "run.sh: $data/bvh not found (the shared test data)"; exit 1; }
bench=$build/bench/bvh/bench_bvh
if [ ! -x "$bench" ]; then
    say "building bench_bvh"
    make -C "$build" bench/bvh/bench_bvh >/dev/null
fi

if [ $quick = 1 ]; then procs=1 reps=3 minms=100 nassimp=3; else procs=3 reps=5 minms=300 nassimp=5; fi

synth=$work/synth_cmu31_10k.bvh
big=$work/synth_cmu31_100k.bvh
[ -f "$synth" ] || node "$peers/gen_bvh.mjs" 10000 120 "$synth" >&2
[ -f "$big" ] || node "$peers/gen_bvh.mjs" 100000 120 "$big" >&2
files="$data/bvh/cmu_01_01.bvh $data/bvh/boxing_toes.bvh $data/bvh/bandai_walk.bvh $synth"

out=$work/results
rm -rf "$out"
mkdir -p "$out"

# --- ours ---
say "== libbvh (bench_bvh, $procs processes)"
i=1
while [ $i -le $procs ]; do
    # shellcheck disable=SC2086
    "$bench" --reps $reps --min-ms $minms $files | tee "$out/ours_run$i.txt" >&2
    i=$((i + 1))
done
"$bench" --reps 1 --min-ms 0 --no-write "$big" | tee "$out/ours_big.txt" >&2

# --- three.js ---
say "== three.js BVHLoader ($procs processes)"
bench_three
if [ $full = 1 ]; then
    (cd "$tpeers" && ./run_three.sh "$out/three") >&2
    cp "$out"/three/three_run*.txt "$out/" 2>/dev/null || true
else
    i=1
    while [ $i -le $procs ]; do
        : >"$out/three_run$i.txt"
        for f in $files; do
            MIN_MS=$minms node "$tpeers/bench_three.mjs" "$f" $reps --no-retarget \
                >>"$out/three_run$i.txt" 2>&1
        done
        grep -h '^parse\|^BVH' "$out/three_run$i.txt" >&2 || true
        i=$((i + 1))
    done
fi

# --- Assimp ---
say "== Assimp (run_assimp.sh, median of $nassimp)"
if command -v assimp >/dev/null; then
    "$peers/run_assimp.sh" $nassimp "$work" | tee "$out/assimp.txt" >&2
else
    say "assimp not found (Debian assimp-utils): no Assimp figures"
    : >"$out/assimp.txt"
fi

# --- ours, timed like run_assimp.sh times Assimp: one import per process, wall clock ---
say "== libbvh, one import per process (bench_bvh --peak), median of $nassimp"
med() { sort -g | awk '{a[NR]=$1} END{ if(NR%2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2 }'; }
wall() { s=$(date +%s.%N); "$@" >/dev/null 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc; }
: >"$out/ours_process.txt"
for f in "$data/bvh/cmu_01_01.bvh" "$data/bvh/boxing_toes.bvh" "$synth"; do
    mb=$(stat -c %s "$f" | awk '{print $1/1e6}')
    i=1
    while [ $i -le $nassimp ]; do
        wall "$bench" --peak "$f"
        i=$((i + 1))
    done | med | awk -v f="$(basename "$f")" -v mb="$mb" '{printf "%s %s %s\n", f, mb, $1}' \
        | tee -a "$out/ours_process.txt" >&2
done

node "$here/ratios.mjs" "$out"

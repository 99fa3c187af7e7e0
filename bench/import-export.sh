#!/bin/bash
# Import and export time of a 10k-frame clip, rigflow beside Assimp's CLI.
#
#   bench/import-export.sh [BUILDDIR] [N=5]
#
# The clip is ../shared/peers/gen_bvh.mjs's synthetic 31-joint, 10000-frame, 120 fps BVH (the same
# one ../shared/peers/run_assimp.sh uses). Measured, median of N runs each, in this one run:
#   bvh->glb   rigflow run pipelines/convert.json (libbvh import, our glTF writer)
#              vs assimp export IN.bvh OUT.glb -fglb2
#   glb import rigflow inspect OUT.glb (assimp.import: Assimp read + resampling) vs assimp info -r
#   glb->glb   rigflow run pipelines/convert.json (Assimp import, our writer) vs assimp export
# Prints a table and RESULT {json} lines (../shared/peers/summarize.mjs reads them).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$top/_build}
n=${2:-5}
peers=$top/../shared/peers
rigflow=$build/rigflow
export RIGFLOW_PLUGIN_PATH=$build/plugins RIGFLOW_QUIET=1
for tool in node assimp "$rigflow"; do
    command -v "$tool" >/dev/null || { echo "bench: $tool not found: skipped"; exit 0; }
done
[ -f "$peers/gen_bvh.mjs" ] || { echo "bench: $peers/gen_bvh.mjs not found: skipped"; exit 0; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
node "$peers/gen_bvh.mjs" 10000 120 "$tmp/clip.bvh" >/dev/null

median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
timed() { # N runs of a command, median wall seconds
    for _ in $(seq "$n"); do
        local s e
        s=$(date +%s.%N)
        "$@" >/dev/null 2>&1 || { echo "bench: failed: $*" >&2; exit 1; }
        e=$(date +%s.%N)
        echo "$e - $s" | bc
    done | median
}
row() { # name, ours, peer
    printf '%-12s %10.4f %10.4f %8.2f\n' "$1" "$2" "$3" "$(echo "$3 / $2" | bc -l)"
    printf 'RESULT {"bench":"import-export","case":"%s","rigflow_s":%s,"assimp_s":%s}\n' "$1" "$2" "$3"
}
conv() { "$rigflow" run "$top/pipelines/convert.json" -p "source.path=$1" -p "export.path=$2"; }

conv "$tmp/clip.bvh" "$tmp/clip.glb"
printf '%-12s %10s %10s %8s\n' case rigflow_s assimp_s speedup
row bvh-to-glb "$(timed conv "$tmp/clip.bvh" "$tmp/ours.glb")" \
    "$(timed assimp export "$tmp/clip.bvh" "$tmp/theirs.glb" -fglb2)"
row glb-import "$(timed "$rigflow" inspect "$tmp/clip.glb")" \
    "$(timed assimp info "$tmp/clip.glb" -r)"
row glb-to-glb "$(timed conv "$tmp/clip.glb" "$tmp/ours2.glb")" \
    "$(timed assimp export "$tmp/clip.glb" "$tmp/theirs2.glb" -fglb2)"

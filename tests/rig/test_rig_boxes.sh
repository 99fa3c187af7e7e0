#!/bin/sh
# A box model rigged by the template rigger keeps its boxes whole as it walks: the animalia horse
# (22 overlapping boxes) rigged by pipelines/autorig-template.json, then the CMU walk retargeted
# onto it (pipelines/retarget.json). The measure line's stretch p99 (how much the 99th percentile
# of the mesh's edges stretch or shrink against their rest length, in %) stays under 60: bone
# heat's sharpened weights had sent a thigh box's top corners to the hips and its bottom ones
# to the knee and tore it into a wedge, stretch p99 79.0; with the part's plain blend 48.8.
rigflow="${RF_BUILDDIR:-.}/rigflow"
src="${RF_SRCDIR:-.}"
data="${RF_DATA_DIR:-}"
horse="$data/models/creatures/animala_horse.b3d"
walk="$data/bvh/cmu_01_01.bvh"
limit=60
if [ ! -f "$horse" ] || [ ! -f "$walk" ]; then
    echo "SKIP: RF_DATA_DIR ($data) lacks the animalia horse or the CMU walk"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if ! RIGFLOW_QUIET=1 "$rigflow" run "$src/pipelines/autorig-template.json" -p "mesh.path=$horse" \
    -p "export.path=$tmp/horse.glb" >"$tmp/out" 2>&1; then
    cat "$tmp/out"
    echo "FAIL: autorig-template on the animalia horse"
    exit 1
fi
if ! "$rigflow" --quiet run "$src/pipelines/retarget.json" -p "source.path=$walk" \
    -p "target.path=$tmp/horse.glb" -p retarget.last_frame=240 \
    -p "export.path=$tmp/walk.glb" >"$tmp/out" 2>&1; then
    cat "$tmp/out"
    echo "FAIL: retarget the CMU walk onto the rigged horse"
    exit 1
fi
stretch=$(sed -n 's/^measure: mesh .*stretch p99 \([0-9.]*\).*/\1/p' "$tmp/out")
if [ -z "$stretch" ]; then
    cat "$tmp/out"
    echo "FAIL: no stretch p99 in the measure line"
    exit 1
fi
echo "animalia horse, template rig, CMU walk: stretch p99 $stretch (limit $limit)"
if awk -v s="$stretch" -v l="$limit" 'BEGIN { exit !(s < l) }'; then
    echo "PASS"
else
    echo "FAIL: stretch p99 $stretch not under $limit: boxes torn into wedges"
    exit 1
fi

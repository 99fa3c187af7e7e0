#!/bin/sh
# Blender's own glTF importer (Debian's blender, headless) on rigflow's exports: the converted
# Fox, Wizard and RobotExpressive come in with their materials and image textures, a BVH clip
# as one armature with the clip's joints and length (cmu_01_01: 31 joints, 2752 frames at 120 fps
# = 22.925 s, from the data README), the Fox's three clips as three actions, three BVH clips
# retargeted onto the Wizard as three actions, and the BVH clip with export.bone_mesh as a mesh
# its armature moves and deforms (what lets a viewer that draws only meshes show a BVH). One Blender run for all (tests/gltf/blender_check.py); skipped without blender or data.
rigflow="${RF_BUILDDIR:-.}/rigflow"
src="${RF_SRCDIR:-.}"
data="${RF_DATA_DIR:-}"
blender="${RF_BLENDER:-blender}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { RIGFLOW_QUIET=1 "$rigflow" run "$@" >/dev/null; }

if [ ! -f "$data/models/Fox.glb" ]; then
    echo "RF_DATA_DIR not found (../shared/data): skipped"
    exit 77
fi
if ! command -v "$blender" >/dev/null 2>&1; then
    echo "blender not found (Debian package blender; ./quickstart.sh deps installs it): skipped"
    exit 77
fi
fail=0
for b in Fox Wizard RobotExpressive; do
    run "$src/pipelines/convert.json" -p "source.path=$data/models/$b.glb" -p "export.path=$tmp/$b.glb" ||
        { echo "FAIL: convert $b.glb"; fail=1; }
done
run "$src/pipelines/convert.json" -p "source.path=$data/bvh/cmu_01_01.bvh" -p "export.path=$tmp/cmu.glb" ||
    { echo "FAIL: convert cmu_01_01.bvh"; fail=1; }
run "$src/pipelines/convert.json" -p "source.path=$data/bvh/cmu_01_01.bvh" -p export.bone_mesh=true \
    -p "export.path=$tmp/cmu-bones.glb" || { echo "FAIL: convert cmu_01_01.bvh with bone_mesh"; fail=1; }
run "$src/pipelines/retarget-many.json" -p "target.path=$data/models/Wizard.glb" \
    -p "source_a.path=$data/bvh/cmu_01_01.bvh" -p "source_b.path=$data/bvh/bandai_walk.bvh" \
    -p "source_c.path=$data/bvh/bandai_kick.bvh" -p "export.path=$tmp/wizard3.glb" ||
    { echo "FAIL: retarget-many onto Wizard.glb"; fail=1; }
# materials and images as the sources have them (Khronos/Quaternius files: Fox 1 + 1, Wizard
# 2 + 2, RobotExpressive 3 materials without images)
"$blender" -b --factory-startup --python-exit-code 1 --python "$src/tests/gltf/blender_check.py" -- \
    look "$tmp/Fox.glb" 1 1 look "$tmp/Wizard.glb" 2 2 look "$tmp/RobotExpressive.glb" 3 0 \
    armature "$tmp/cmu.glb" 31 22.925 actions "$tmp/Fox.glb" Survey Walk Run \
    actions "$tmp/wizard3.glb" cmu_01_01 bandai_walk bandai_kick plays "$tmp/cmu-bones.glb" \
    >"$tmp/out" 2>&1
code=$?
grep -E "^(OK|FAIL)" "$tmp/out"
if [ "$code" -ne 0 ] || [ "$(grep -c '^OK' "$tmp/out")" -ne 7 ]; then
    grep -E "Error|Traceback" "$tmp/out" | head -20
    echo "FAIL: Blender (exit $code)"
    fail=1
fi
exit "$fail"

#!/bin/sh
# Every mesh of the shared data (models/, creatures and Ogre included) and Debian's two unrigged
# assimp-testmodels meshes through pipelines/scan-to-animation.json with its rig ignored and the
# CMU walk (its first second): each is rigged, or refused with a reason and nothing written. A
# refusal counts only for a flat mesh (a sheet: its reason gives the extents, one of them 0); any
# other refusal or failure is a regression. Each GLB must pass the Khronos glTF-Validator, and in
# one headless Blender run (tests/gltf/blender_check.py `plays`) import with its armature, its
# action and a skinned mesh that moves and deforms over the clip, every vertex finite.
rigflow="${RF_BUILDDIR:-.}/rigflow"
src="${RF_SRCDIR:-.}"
data="${RF_DATA_DIR:-}"
blender="${RF_BLENDER:-blender}"
testmodels=/usr/share/assimp/models/OBJ
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/tap.sh"
ko() { bad "$*"; }
. "$src/tests/gltf/valid.sh"

if [ ! -f "$data/models/Fox.glb" ] || [ ! -f "$data/bvh/cmu_01_01.bvh" ]; then
    echo "RF_DATA_DIR not found (../shared/data): skipped"
    exit 77
fi
if [ ! -f "$testmodels/WusonOBJ.obj" ]; then
    echo "assimp-testmodels not installed ($testmodels): skipped"
    exit 77
fi

meshes=$(find "$data/models" -type f \( -name '*.glb' -o -name '*.gltf' -o -name '*.fbx' -o \
    -name '*.X' -o -name '*.x' -o -name '*.b3d' -o -name '*.mesh' -o -name '*.obj' \) | sort)
rigged=0 refused=0 plays=""
for m in $meshes "$testmodels/WusonOBJ.obj" "$testmodels/spider.obj"; do
    name=$(basename "$m")
    out="$tmp/$rigged-$name.glb"
    RIGFLOW_QUIET=1 "$rigflow" run "$src/pipelines/scan-to-animation.json" -p "mesh.path=$m" \
        -p "motion.path=$data/bvh/cmu_01_01.bvh" -p "export.path=$out" \
        -p retarget.last_frame=120 >/dev/null 2>"$tmp/err"
    code=$?
    if [ "$code" -eq 0 ] && [ -s "$out" ]; then
        ok "$name rigged and walking"
        rigged=$((rigged + 1))
        gltf_valid "$out"
        plays="$plays plays $out"
    elif [ "$code" -eq 1 ] && [ ! -e "$out" ] &&
        grep -qE "node 'rig': .*cannot rig the mesh: the mesh is flat \(.*\b0\): " "$tmp/err"; then
        ok "$name refused: $(sed -n 's/.*cannot rig the mesh: //p' "$tmp/err" | head -1)"
        refused=$((refused + 1))
    else
        bad "$name: exit $code, $(test -e "$out" && echo "a file written" || echo "no file")"
    fi
done
echo "# $rigged rigged, $refused refused (flat)"
[ "$rigged" -gt 0 ] || bad "no mesh rigged"

if ! command -v "$blender" >/dev/null 2>&1; then
    echo "SKIP: blender not found (Debian package blender): the GLBs were not played"
    [ "$fail" -eq 0 ] || exit 1
    exit 77
fi
# shellcheck disable=SC2086 # $plays is a list of words
"$blender" -b --factory-startup --python-exit-code 1 --python "$src/tests/gltf/blender_check.py" -- \
    $plays >"$tmp/blender" 2>&1
code=$?
played=$(grep -c '^OK plays' "$tmp/blender")
grep -E '^FAIL' "$tmp/blender"
same "$played" "$rigged" "Blender plays every rigged GLB (exit $code)"
[ "$played" -eq "$rigged" ] || grep -E "Error|Traceback" "$tmp/blender" | head -20
gltf_exit "$fail"

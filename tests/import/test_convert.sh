#!/bin/sh
# pipelines/convert.json end to end: any supported input to GLB, glTF or BVH by the output's
# extension. Expected counts from ../shared/data/README.md (Fox 24 joints, cmu_01_01 31 joints,
# 2752 frames at 120 fps); GLB outputs go through the Khronos glTF-Validator when it is installed.
rigflow="${RF_BUILDDIR:-.}/rigflow"
pipeline="${RF_SRCDIR:-.}/pipelines/convert.json"
data="${RF_DATA_DIR:-}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
ko() { fail=$((fail + 1)); printf 'FAIL: %s\n' "$*"; }
convert() { RIGFLOW_QUIET=1 "$rigflow" run "$pipeline" -p "source.path=$1" -p "export.path=$2"; }
. "${RF_SRCDIR:-.}/tests/gltf/valid.sh"
inspect_has() { # file, pattern
    if "$rigflow" inspect "$1" 2>&1 | grep -q -- "$2"; then ok; else ko "inspect $1: no /$2/"; fi
}

if [ ! -f "$data/models/Fox.glb" ]; then
    echo "RF_DATA_DIR not found (../shared/data): skipped"
    echo "0 passed, 0 failed"
    exit 77
fi
if convert "$data/models/Fox.glb" "$tmp/fox.glb"; then ok; else ko "Fox.glb to GLB"; fi
gltf_valid "$tmp/fox.glb"
inspect_has "$tmp/fox.glb" "skeleton: 24 joints"
if convert "$data/bvh/cmu_01_01.bvh" "$tmp/cmu.glb"; then ok; else ko "cmu_01_01.bvh to GLB"; fi
gltf_valid "$tmp/cmu.glb"
inspect_has "$tmp/cmu.glb" "skeleton: 31 joints"
inspect_has "$tmp/cmu.glb" "2752 frames at 120"
if convert "$data/models/Fox.glb" "$tmp/fox.gltf"; then ok; else ko "Fox.glb to glTF"; fi
inspect_has "$tmp/fox.gltf" "skeleton: 24 joints"
if convert "$data/models/Fox.glb" "$tmp/fox.bvh"; then ok; else ko "Fox.glb to BVH"; fi
inspect_has "$tmp/fox.bvh" "skeleton: 24 joints"
if convert "$data/models/creatures/animalia_wolf.b3d" "$tmp/wolf.bvh"; then ok; else ko "B3D to BVH"; fi
# every clip is imported once: one line per clip (Fox has three), the selected one not resampled twice
"$rigflow" run "$pipeline" -p "source.path=$data/models/Fox.glb" -p "export.path=$tmp/fox2.glb" 2>"$tmp/log"
n=$(grep -c "resampled to" "$tmp/log")
if [ "$n" = 3 ] && [ "$(grep "resampled to" "$tmp/log" | sort -u | wc -l)" = 3 ]; then ok; else ko "Fox clips imported $n times, expected 3 once each"; fi
# refusals leave nothing behind
if convert "$data/models/spider.fbx" "$tmp/spider.glb" 2>"$tmp/err"; then ko "spider.fbx accepted"; else ok; fi
if grep -q "spider.fbx: no skeleton" "$tmp/err" && [ ! -e "$tmp/spider.glb" ]; then ok; else ko "spider message or leftover"; fi
if convert "$data/models/Fox.glb" "$tmp/fox.obj" 2>"$tmp/err"; then ko ".obj accepted"; else ok; fi
if grep -q "expected .glb, .gltf or .bvh" "$tmp/err" && [ ! -e "$tmp/fox.obj" ]; then ok; else ko ".obj message or leftover"; fi
# an Ogre mesh copied without the .skeleton it names: the error names the missing file
mkdir "$tmp/ogre" && cp "$data/models/ogre/fish.mesh" "$tmp/ogre/"
if convert "$tmp/ogre/fish.mesh" "$tmp/fish.glb" 2>"$tmp/err"; then ko "fish.mesh without its skeleton converted"; else ok; fi
if grep -q "not beside it: fish.skeleton" "$tmp/err" && [ ! -e "$tmp/fish.glb" ]; then ok; else ko "fish.mesh: missing skeleton not named"; cat "$tmp/err"; fi
echo "$pass passed, $fail failed"
gltf_exit "$fail"

#!/bin/sh
# What a GLB export keeps: every model in $RF_DATA_DIR converts (pipelines/convert.json) and has a
# BVH clip retargeted onto it (pipelines/retarget.json); each output must pass the Khronos
# glTF-Validator with no error and carry as many materials, images and texture coordinate sets as
# Assimp itself reads from the source (counted from `assimp dump`'s XML, not through rigflow).
# Round trips GLB -> rigflow -> GLB keep every image's bytes and every material's factors; three.js's
# GLTFLoader loads every export; clips: the Fox keeps its three, three BVH files retargeted onto the
# Wizard give three named animations, a one-frame BVH gives a valid file with a skin, a morph
# target survives (a fixture: none of the data's models has one), a BVH exported with
# export.bone_mesh carries a skinned mesh. Bad textures
# (missing, outside the model's folder, a link leading out, not an image) are left out with a
# warning naming them; one named by a path from another machine (C:\textures\good.png) is found
# by its file name beside the model, with a warning.
# Parts that need a tool (gltf-validator, three, assimp) say so; the test then ends as skipped
# (77) unless something failed.
rigflow="${RF_BUILDDIR:-.}/rigflow"
src="${RF_SRCDIR:-.}"
convert_p="$src/pipelines/convert.json"
retarget_p="$src/pipelines/retarget.json"
many_p="$src/pipelines/retarget-many.json"
validate="$src/tests/gltf/validate.js"
look="$src/tests/gltf/look.js"
data="${RF_DATA_DIR:-}"
node="${RF_NODE:-node}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
ko() { fail=$((fail + 1)); printf 'FAIL: %s\n' "$*"; }
. "$src/tests/gltf/valid.sh" # gltf_skipped and gltf_exit: a check a tool was missing for is a skip
run() { RIGFLOW_QUIET=1 "$rigflow" run "$@"; }

if [ ! -f "$data/models/Fox.glb" ]; then
    echo "RF_DATA_DIR not found (../shared/data): skipped"
    exit 77
fi
if ! command -v "$node" >/dev/null 2>&1; then
    echo "node not found: the exports cannot be read back: skipped"
    exit 77
fi

# ---- bad textures (no tool needed) ----
model="$tmp/model"
mkdir -p "$model"
cp "$src/tests/fixtures/textures/textured-sheet.gltf" "$model/"
png=iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==
printf '%s' "$png" | base64 -d >"$model/good.png"
printf '%s' "$png" | base64 -d >"$tmp/outside.png"
echo "this is not an image" >"$model/notimage.png"
ln -s ../outside.png "$model/link.png" # a link leading out of the folder
# not quiet: the textures left out are warnings
if "$rigflow" run "$convert_p" -p "source.path=$model/textured-sheet.gltf" -p "export.path=$tmp/sheet.glb" 2>"$tmp/err"; then
    ok
else
    ko "a model with bad textures did not convert: $(cat "$tmp/err")"
fi
for want in "texture 'missing.png' left out: not found beside the model" \
            "texture '../outside.png' left out: refused to read" \
            "outside the model's folder" \
            "texture 'notimage.png' is not a PNG or JPEG" \
            "texture 'link.png' left out: refused to read" \
            "its file name good.png was found beside the model and is used"; do
    if grep -q "$want" "$tmp/err"; then ok; else ko "no warning: $want"; cat "$tmp/err"; fi
done
if "$node" "$look" counts "$tmp/sheet.glb" | grep -q "materials=1 images=1 uvsets=1"; then ok; else
    ko "sheet.glb: expected 1 material, the one good image, 1 UV set"; "$node" "$look" counts "$tmp/sheet.glb"; fi
# its one morph target (the fixture's "lift": weight 0.25, the first vertex raised by 1)
if "$node" "$look" counts "$tmp/sheet.glb" | grep -q "^morph lift 0.250 1.000$"; then ok; else
    ko "sheet.glb: morph target 'lift' not kept"; "$node" "$look" counts "$tmp/sheet.glb"; fi
if grep -a -q '"baseColorFactor":\[0.25,0.5,0.75,1' "$tmp/sheet.glb" &&
   grep -a -q '"metallicFactor":0.125,"roughnessFactor":0.625' "$tmp/sheet.glb" &&
   grep -a -q '"emissiveTexture"' "$tmp/sheet.glb" && ! grep -a -q '"baseColorTexture"' "$tmp/sheet.glb"; then
    ok
else
    ko "sheet.glb: factors, or the good texture alone, not kept"
fi

# ---- every model: convert and retarget ----
clip="$data/bvh/dme_example_cmu.bvh"
outs=""
expect_look() { # source file -> "materials=M images=I uvsets=U" as Assimp reads it
    assimp dump "$1" "$tmp/dump.xml" >/dev/null 2>&1 || return 1
    # meshes with faces of three or more corners (rigflow triangulates polygons; points and
    # lines make no surface)
    m=$(grep -Eo '<Mesh types="[^"]*(triangles|polygons)[^"]*" material_index="[0-9]*"' "$tmp/dump.xml" |
        sed 's/.*material_index="//' | sort -u | wc -l)
    i=$(grep -c '<Texture [^>]*compressed="true"' "$tmp/dump.xml")
    u=$(grep -o '<TextureCoords [^>]*set="[0-9]*"' "$tmp/dump.xml" | sed 's/.*set="//; s/"//' |
        sort -n | tail -1)
    u=$([ -z "$u" ] && echo 0 || { [ "$u" -ge 1 ] && echo 2 || echo 1; })
    echo "materials=$m images=$i uvsets=$u"
}
have_assimp=yes
command -v assimp >/dev/null 2>&1 || {
    have_assimp=no; gltf_skipped=$((gltf_skipped + 1))
    echo "SKIP: assimp (assimp-utils) not found: counts not compared"
}
for f in "$data"/models/*.* "$data"/models/*/*.b3d "$data"/models/ogre/*.mesh; do
    case "$f" in *spider.fbx) continue ;; esac # no skeleton: refused, tested in test_convert.sh
    b=$(basename "$f"); b=${b%.*}
    if run "$convert_p" -p "source.path=$f" -p "export.path=$tmp/$b.glb" 2>"$tmp/err"; then ok; else
        ko "convert $f: $(cat "$tmp/err")"; continue; fi
    if run "$retarget_p" -p "source.path=$clip" -p "target.path=$f" -p "export.path=$tmp/rt-$b.glb" \
        >/dev/null 2>"$tmp/err"; then ok; else ko "retarget onto $f: $(cat "$tmp/err")"; fi
    outs="$outs $tmp/$b.glb $tmp/rt-$b.glb"
    [ "$have_assimp" = yes ] || continue
    want=$(expect_look "$f") || { ko "assimp dump $f failed"; continue; }
    for out in "$tmp/$b.glb" "$tmp/rt-$b.glb"; do
        got=$("$node" "$look" counts "$out" | head -1 | cut -d' ' -f1-3)
        if [ "$got" = "$want" ]; then ok; else ko "$b: $(basename "$out") has $got, Assimp reads $want"; fi
    done
done

# ---- clips ----
if "$node" "$look" counts "$tmp/Fox.glb" | grep -q "animations=3" &&
   "$node" "$look" counts "$tmp/Fox.glb" | grep -q "^animation Walk "; then ok; else
    ko "Fox.glb: expected its three clips"; fi
# one clip by name still gives that clip alone; BVH keeps the first of several, and says so
if run "$convert_p" -p "source.path=$data/models/Fox.glb" -p source.clip=Walk -p "export.path=$tmp/walk.glb" &&
   "$node" "$look" counts "$tmp/walk.glb" | grep -q "animations=1" &&
   "$node" "$look" counts "$tmp/walk.glb" | grep -q "^animation Walk "; then ok; else
    ko "Fox.glb with clip Walk: expected the Walk clip alone"; fi
if "$rigflow" run "$convert_p" -p "source.path=$data/models/Fox.glb" -p "export.path=$tmp/fox.bvh" 2>"$tmp/err" &&
   grep -q "BVH holds one clip; the first of 3 is written" "$tmp/err"; then ok; else
    ko "Fox.glb to BVH: no warning about the clips left out"; cat "$tmp/err"; fi
if run "$many_p" -p "target.path=$data/models/Wizard.glb" -p "source_a.path=$data/bvh/cmu_01_01.bvh" \
    -p "source_b.path=$data/bvh/bandai_walk.bvh" -p "source_c.path=$data/bvh/bandai_kick.bvh" \
    -p "export.path=$tmp/wizard3.glb" >/dev/null 2>"$tmp/err"; then ok; else ko "retarget-many: $(cat "$tmp/err")"; fi
# durations: frames - 1 over fps from the data README (2752 at 120, 195 and 358 at 30)
"$node" "$look" counts "$tmp/wizard3.glb" >"$tmp/w3"
for want in "materials=2 images=2 uvsets=1 animations=3" "animation cmu_01_01 22.925" \
            "animation bandai_walk 6.467" "animation bandai_kick 11.900"; do
    if grep -q "^$want" "$tmp/w3"; then ok; else ko "wizard3.glb: no '$want'"; cat "$tmp/w3"; fi
done
for b in cmu_01_01 dme_rest_cmu; do
    if run "$convert_p" -p "source.path=$data/bvh/$b.bvh" -p "export.path=$tmp/$b.glb"; then ok; else ko "convert $b.bvh"; fi
    outs="$outs $tmp/$b.glb"
done
if "$node" "$look" counts "$tmp/dme_rest_cmu.glb" | grep -q "animations=1 skins=1 meshes=0"; then ok; else
    ko "dme_rest_cmu.glb: expected a skin and its one-frame clip"; fi
# export.bone_mesh draws a BVH's bones of any length (20 of cmu_01_01's 31 joints end one) as
# one skinned mesh; the validator and three.js below read it
if run "$convert_p" -p "source.path=$data/bvh/cmu_01_01.bvh" -p export.bone_mesh=true \
    -p "export.path=$tmp/bones.glb" && "$node" "$look" counts "$tmp/bones.glb" |
    grep -q "animations=1 skins=1 meshes=1"; then ok; else ko "bone_mesh: expected a skinned mesh"; fi
# ... standing on the floor its clips stand on: a BVH hangs its rest from the origin, and drawn
# there the rest's lowest point (a viewer's or a contact sheet's floor) lay 73% of the body's
# height under the walking feet (CMU's own clip; the Bandai kick retargeted onto it 75%); now
# the CMU clip's toes stand 5% over it, the retargeted kick 6.5%
stands() { # FILE LABEL: the median frame's lowest joint within 15% of the height over the rest's
    m=$("$node" "$look" stand "$1" | awk '{ print $2 }')
    if awk -v m="$m" 'BEGIN { exit !(m >= -0.02 && m <= 0.15) }'; then ok; else
        ko "$2: lowest joint a median ${m:-?} of the height over the rest's floor, expected 0-0.15"; fi
}
stands "$tmp/bones.glb" "bone_mesh cmu_01_01"
# ... leaving out a bone whose child walks away from its joint: bandai_walk's root stays at the
# origin while its Hips carry the walk (position channels from z -407 on). Of its 21 joints with
# an offset (the file's JOINTs; End Sites have none), 20 bones of 6 vertices are drawn; with the
# root's bone, 21 stood at the origin as a spike while the body walked away
if run "$convert_p" -p "source.path=$data/bvh/bandai_walk.bvh" -p export.bone_mesh=true \
    -p "export.path=$tmp/bwalk.glb" && "$node" "$look" counts "$tmp/bwalk.glb" | grep -q "^mesh .* 120$"
then ok; else ko "bone_mesh bandai_walk: expected 20 bones (120 vertices), the root's left out"; fi
if run "$retarget_p" -p "source.path=$data/bvh/bandai_kick.bvh" -p "target.path=$data/bvh/cmu_01_01.bvh" \
    -p export.bone_mesh=true -p "export.path=$tmp/kick.glb"; then
    stands "$tmp/kick.glb" "bandai_kick onto cmu_01_01 with bone_mesh"
else ko "bandai_kick onto cmu_01_01"; fi
outs="$outs $tmp/wizard3.glb $tmp/sheet.glb $tmp/bones.glb $tmp/bwalk.glb $tmp/kick.glb"

# ---- round trips keep images and materials ----
for b in Fox Wizard RobotExpressive vrm_sample girl; do
    if "$node" "$look" same "$data/models/$b.glb" "$tmp/$b.glb"; then ok; else ko "round trip $b.glb"; fi
done

# ---- readers: the Khronos validator, three.js ----
# shellcheck disable=SC2086
"$node" "$validate" $outs >"$tmp/v" 2>&1
case $? in
0) ok ;;
77) gltf_skipped=$((gltf_skipped + 1)); echo "SKIP: glTF-Validator not installed: nothing validated" ;;
*) grep -B1 "error" "$tmp/v" | head -40; ko "validator errors (above)" ;;
esac
# shellcheck disable=SC2086
"$node" "$look" three $outs >"$tmp/t" 2>&1
case $? in
0) ok ;;
77) gltf_skipped=$((gltf_skipped + 1)); cat "$tmp/t" ;;
*) grep -v " clips$" "$tmp/t" | head -20; ko "three.js GLTFLoader (above)" ;;
esac
echo "$pass passed, $fail failed"
gltf_exit "$fail"

#!/usr/bin/env bash
# The GLB writer streams each animation channel's outputs into the file as it writes the binary
# chunk (sdk/formats/gltf/gltf-write.c); the .gltf writer puts the same bytes in its base64
# buffer. The two must agree byte for byte: a GLB's binary chunk equals the .gltf's decoded
# buffer, for a clip alone (the synthetic arm below, no mesh: a channel comes first) and, with
# the shared data, for models with a mesh and several clips. node reads both.
set -u
rigflow="${RF_RIGFLOW:-${RF_BUILDDIR:?}/rigflow}"
pipeline="${RF_SRCDIR:?}/pipelines/convert.json"
data="${RF_DATA_DIR:-}"
node="${RF_NODE:-node}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$RF_SRCDIR/tests/tap.sh"
if ! "$node" --version >/dev/null 2>&1; then
    echo "node not found: skipped"
    exit 77
fi
cat >"$tmp/compare.js" <<'JS'
const fs = require('fs');
const glb = fs.readFileSync(process.argv[2]);
const json = glb.readUInt32LE(12), bin = glb.subarray(20 + json + 8, 20 + json + 8 + glb.readUInt32LE(20 + json));
const gltf = JSON.parse(fs.readFileSync(process.argv[3], 'utf8'));
const buf = Buffer.from(gltf.buffers[0].uri.split(',')[1], 'base64');
const meta = JSON.parse(glb.subarray(20, 20 + json).toString('utf8'));
const same = buf.equals(bin.subarray(0, buf.length)) && bin.subarray(buf.length).every((b) => b === 0) &&
    meta.buffers[0].byteLength === buf.length && (meta.animations || []).length > 0;
console.log(same ? 'same' : `differ: ${bin.length} / ${buf.length} bytes`);
JS
# compare NAME FILE: FILE to GLB and to .gltf, the chunk against the buffer
compare() {
    local name=$1 file=$2
    RIGFLOW_QUIET=1 "$rigflow" run "$pipeline" -p "source.path=$file" -p "export.path=$tmp/$name.glb" &&
        RIGFLOW_QUIET=1 "$rigflow" run "$pipeline" -p "source.path=$file" -p "export.path=$tmp/$name.gltf" ||
        { bad "$name: not converted"; return; }
    same "$("$node" "$tmp/compare.js" "$tmp/$name.glb" "$tmp/$name.gltf" 2>&1)" "same" \
        "$name: the GLB's binary chunk is the .gltf's buffer"
}

cp "$RF_SRCDIR/tests/fixtures/arm.bvh" "$tmp/arm.bvh" # a root and an arm, 3 frames, turns past 180 degrees
compare arm "$tmp/arm.bvh"
# 9,000 frames of the arm turning slowly past a full turn: the writer makes a channel 8,192
# frames at a time, and the short way between frames (a quaternion's sign, here the negative
# hemisphere at frame 8,192, 410 degrees) carries across
sed -n '1,/^MOTION/p' "$tmp/arm.bvh" >"$tmp/long.bvh"
awk 'BEGIN {print "Frames: 9000"; print "Frame Time: 0.01";
    for (f = 0; f < 9000; f++) printf "%g 0 0 %g %g 0 %g 0 0\n", f / 100, f * 0.05, f * 0.013, f * 0.031}' \
    >>"$tmp/long.bvh"
compare long "$tmp/long.bvh"
if [ -f "$data/models/Fox.glb" ]; then
    compare fox "$data/models/Fox.glb"            # a mesh and three clips
    compare cmu "$data/bvh/cmu_01_01.bvh"
    compare wizard "$data/models/Wizard.glb"
else
    echo "# RF_DATA_DIR not found (../shared/data): the models are not compared"
fi
echo "1..$((pass + fail))"
[ "$fail" = 0 ]

#!/usr/bin/env bash
# The convert plugin loads its Assimp import (convert-assimp.mod, with libassimp) the first time a
# run imports something other than BVH: a BVH-only run never maps libassimp, a model import does,
# and a plugin folder missing the module fails such an import with an error naming it, while BVH
# still converts. glibc's loader log (LD_DEBUG=files) tells which libraries a run mapped.
set -u
rigflow="${RF_RIGFLOW:-${RF_BUILDDIR:?}/rigflow}"
pipeline="${RF_SRCDIR:?}/pipelines/convert.json"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$RF_SRCDIR/tests/tap.sh"

cp "$RF_SRCDIR/tests/fixtures/arm.bvh" "$tmp/arm.bvh"
run() { "$rigflow" -q run "$pipeline" -p "source.path=$1" -p "export.path=$2"; }

# a stale plugin index (a new build) makes the first run open every plugin, assimp.import's
# libassimp included, to enter them: that run is not the one looked at
run "$tmp/arm.bvh" "$tmp/arm.glb"
LD_DEBUG=files run "$tmp/arm.bvh" "$tmp/arm.glb" >"$tmp/out" 2>"$tmp/err"
same "$? $(grep -c 'file=libassimp.*needed by' "$tmp/err")" "0 0" "BVH to GLB: converted, libassimp never loaded"
LD_DEBUG=files run "$tmp/arm.glb" "$tmp/back.bvh" >"$tmp/out" 2>"$tmp/err"
same "$? $(grep -c 'file=libassimp.*needed by' "$tmp/err")" "0 1" "GLB to BVH: converted, libassimp loaded once"
contains "$tmp/back.bvh" "JOINT Arm" "the GLB read through the module has the arm"

# the convert plugin without its module beside it
plugins=$(dirname "$(find "$RF_BUILDDIR/plugins" -name convert-assimp.mod | head -1)")
mkdir -p "$tmp/alone" && cp "$plugins/convert.so" "$tmp/alone/"
export RIGFLOW_PLUGIN_PATH="$tmp/alone"
expect 1 "without the module, a model import fails" -- run "$tmp/arm.glb" "$tmp/fail.bvh"
contains "$tmp/err" "cannot load the Assimp import ($tmp/alone/convert-assimp.mod" \
    "the error names the missing module"
same "$(ls "$tmp" | grep -c '^fail\|^\.fail')" "0" "nothing written"
expect 0 "without the module, BVH still converts" -- run "$tmp/arm.bvh" "$tmp/again.glb"

echo "1..$((pass + fail))"
[ "$fail" = 0 ]

#!/bin/sh
# rigflow inspect: output and exit codes (0 ok, 2 usage, 1 failure). Expected counts from
# ../shared/data/README.md (Fox: 24 joints, clips Survey, Walk, Run; spider.fbx: no skeleton).
rigflow="${RF_BUILDDIR:-.}/rigflow"
data="${RF_DATA_DIR:-}/models"
pass=0 fail=0
check() { # description, expected exit code, grep pattern ('' for none), command...
    what=$1 code=$2 pattern=$3
    shift 3
    out=$("$@" 2>&1)
    rc=$?
    if [ "$rc" -eq "$code" ] && { [ -z "$pattern" ] || printf '%s\n' "$out" | grep -q -- "$pattern"; }; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        printf 'FAIL: %s (exit %s, expected %s; wanted /%s/)\n%s\n' "$what" "$rc" "$code" "$pattern" "$out"
    fi
}
check "help" 0 "FILE" "$rigflow" inspect --help
check "no file" 2 "expected one FILE" "$rigflow" inspect
check "missing file" 1 "nonexistent.glb" "$rigflow" inspect /nonexistent.glb
if [ -f "$data/Fox.glb" ]; then
    # the importer is the one whose rigflow.importer/1 extension fits the file, never a name
    check "glTF read by the importer reading anything" 0 "Fox.glb (read by assimp.import)" "$rigflow" inspect "$data/Fox.glb"
    check "BVH read by the importer naming .bvh" 0 "(read by bvh.import)" "$rigflow" inspect "${RF_DATA_DIR}/bvh/cmu_01_01.bvh"
    check "Fox joints" 0 "skeleton: 24 joints" "$rigflow" inspect "$data/Fox.glb"
    check "Fox tree" 0 "b_Tail02_013 *b_Tail01_012" "$rigflow" inspect "$data/Fox.glb"
    check "Fox clips" 0 "1  Walk" "$rigflow" inspect "$data/Fox.glb"
    check "Fox clip choice" 0 "Run .*\[imported\]" "$rigflow" inspect --clip Run "$data/Fox.glb"
    check "unknown clip" 1 "no clip 'Gallop'" "$rigflow" inspect --clip Gallop "$data/Fox.glb"
    check "spider meshes" 0 "skeleton: 0 joints" "$rigflow" inspect "$data/spider.fbx"
    check "BCN meshes" 0 "meshes: 3 merged" "$rigflow" inspect "$data/BCN_Epileptic.X"
else
    echo "RF_DATA_DIR/models not found (../shared/data): data checks skipped"
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

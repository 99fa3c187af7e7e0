#!/bin/sh
# The up of a body whose file declares none (rf_rig_body_up), on every model of the shared data
# and the two assimp-testmodels meshes, each unmoved, tipped over both ways, on its side and
# upside down (tests/rig/rig-up): the true up is known (the file's own, turned with the body).
# - Never a wrong axis: a body is rigged along the up found or, when none is, along +y with a
#   warning; a wrong up found would rig a standing body lying without saying so.
# - At least 80 of the 135 found (the up read from RobotExpressive stood on its back counts since
#   it was allowed, 79, 77 before; its readings under the bar that agree add up since they were
#   tallied, 80: laid on its side), so a change that finds fewer shows.
rigup="${RF_BUILDDIR:-.}/tests/rig/rig-up"
data="${RF_DATA_DIR:-}"
testmodels=/usr/share/assimp/models/OBJ
if [ -z "$data" ] || [ ! -f "$data/models/Fox.glb" ] || [ ! -f "$testmodels/WusonOBJ.obj" ]; then
    echo "shared data (RF_DATA_DIR) or assimp-testmodels not found: skipped"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
set -- "$data"/models/*.glb "$data"/models/*.X "$data"/models/*.fbx "$data"/models/creatures/*.b3d \
    "$data"/models/ogre/*.mesh "$testmodels/WusonOBJ.obj" "$testmodels/spider.obj"
"$rigup" "$@" >"$tmp/out" 2>"$tmp/err" || { cat "$tmp/err"; echo "FAIL: rig-up failed"; exit 1; }
grep -v "found ok$" "$tmp/out"
summary=$(sed -n 's/^runs //p' "$tmp/out")
echo "runs $summary"
echo "$summary" | awk '{
    for (i = 1; i <= NF; i++) {
        if ($i == "right") right = $(i + 1) + 0
        if ($i == "wrong" && $(i - 1) == "a") wrong = $(i + 2) + 0
    }
    runs = $1 + 0
}
END {
    bad = 0
    if (runs != 135) { print "FAIL: " runs " runs for 135 (27 models, 5 turns)"; bad = 1 }
    if (wrong != 0) { print "FAIL: " wrong " turned to a wrong axis"; bad = 1 }
    if (right < 80) { print "FAIL: " right " found right, under 80"; bad = 1 }
    exit bad
}'

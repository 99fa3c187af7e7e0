#!/bin/sh
# A four-legged character under a two-legged walk walks on four legs (the matcher's gait rule,
# doc/matching.md "Forelegs under a two-legged source"): CMU 01_01's walk (frames 200-1200)
# onto the Khronos Fox through pipelines/retarget.json, measured by tests/retarget/gait-feet on the
# skinned mesh, against the same run with -p map.forelegs=arms (the forelegs on the arms, as
# before the rule). The source's own feet stand within 3% of its height of its floor in 82% of
# its frames and its legs tilt 16 degrees from down at p90: the Fox's forefeet must be within 3%
# of the floor in at least a quarter of the frames and its forelegs tilt at most 45 degrees at
# p90 (on the arms: 4-12% of the frames, 52-57 degrees: folded forward under the chest); the whole
# walk on the floor as tests/retarget/sweep.mjs judges it. While down, the forefeet must not slide:
# their soles at most 20% of the height a second on the mesh (the source's own feet 11; the
# forefeet kept their source's contacts half a cycle later and slid 59-67, now 4), and
# retarget.measure's skate of each forefoot at most 0.8 leg/s (1.02-1.18 before, over their
# source's contacts half a cycle later; now 0.57-0.62 over their own; the hind feet 0.35-0.40
# when the measure read the walk from frame 0, not from the clip's frame 200: 0.003 since).
# Skips without ../shared/data.
rigflow="${RF_BUILDDIR:-.}/rigflow"
feet="${RF_BUILDDIR:-.}/tests/retarget/gait-feet"
pipeline="${RF_SRCDIR:-.}/pipelines/retarget.json"
data="${RF_DATA_DIR:-}"
if [ ! -f "$data/bvh/cmu_01_01.bvh" ] || [ ! -f "$data/models/Fox.glb" ]; then
    echo "RF_DATA_DIR not found (../shared/data): skipped"
    exit 77
fi
if ! "$rigflow" describe skeletal-similarity >/dev/null 2>&1; then
    echo "the skeletal-similarity matcher is not installed: skipped"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
ko() { fail=$((fail + 1)); printf 'FAIL: %s\n' "$*"; }

# $1 name; extra -p arguments follow.
walk() {
    name=$1
    shift
    if ! "$rigflow" run "$pipeline" -p "source.path=$data/bvh/cmu_01_01.bvh" \
        -p "target.path=$data/models/Fox.glb" -p retarget.first_frame=200 \
        -p retarget.last_frame=1200 -p "export.path=$tmp/$name.glb" \
        -p "measure.path=$tmp/$name.json" "$@" >"$tmp/$name.log" 2>&1; then
        ko "$name: the run failed"
        cat "$tmp/$name.log"
        return
    fi
    "$feet" "$tmp/$name.glb" >"$tmp/$name.feet" || ko "$name: gait-feet failed"
    echo "$name:"
    grep -E "^measure|forelegs|contact pass" "$tmp/$name.log"
    cat "$tmp/$name.feet"
}

# The forelegs' worst figures: "SHARE TILT SLIDE" (least share of frames near the floor, largest
# p90 tilt, fastest sliding while down, rounded up) over the lines of FILE for the Fox's forelegs
# (their first joints, read off the file).
fore() {
    awk '/\(b_(Left|Right)UpperArm_/ { s = $0; sub(/.* in /, "", s); sub(/%.*/, "", s);
                    t = $0; sub(/.*p90 /, "", t); sub(/\).*/, "", t);
                    v = $0; sub(/.*sliding while down /, "", v); sub(/%.*/, "", v);
                    n++; if (n == 1 || s + 0 < share) share = s + 0; if (t + 0 > tilt) tilt = t + 0
                    if (v + 0 > slide) slide = v + 0 }
         END { if (n != 2) print "none"; else print share, tilt, int(slide) + 1 }' "$1"
}

# The fastest skate (leg/s) of the Fox's forefeet in retarget.measure's JSON FILE ("feet": the
# effectors at its hands), or "none".
fore_skate() {
    tr '{' '\n' <"$1" | awk '/"name": "b_(Left|Right)Hand_/ { v = $0; sub(/.*"skate": */, "", v);
                                 sub(/,.*/, "", v); n++; if (v + 0 > most) most = v + 0 }
                               END { if (n != 2) print "none"; else print most }'
}

walk gait
walk arms -p map.forelegs=arms
grep -q "forelegs on the floor driven by the source's legs" "$tmp/gait.log" ||
    ko "the gait rule was not applied (no info line)"
set -- $(fore "$tmp/gait.feet")
if [ "$1" = none ]; then
    ko "gait: two forelegs expected"
else
    [ "$1" -ge 25 ] || ko "gait: a forefoot within 3% of the floor in $1% of frames (at least 25)"
    [ "$2" -le 45 ] || ko "gait: a foreleg tilts $2 degrees at p90 (at most 45)"
    [ "$3" -le 20 ] || ko "gait: a forefoot slides $3% of the height a second while down (at most 20)"
fi
skate=$(fore_skate "$tmp/gait.json")
if [ "$skate" = none ]; then
    ko "gait: no skate for two forefeet in the measure"
else
    echo "gait: forefeet skate at most $skate leg/s"
    awk -v v="$skate" 'BEGIN { exit !(v <= 0.8) }' ||
        ko "gait: a forefoot skates $skate leg/s (at most 0.8)"
fi
set -- $(fore "$tmp/arms.feet")
if [ "$1" != none ] && [ "$1" -ge 25 ] && [ "$2" -le 45 ]; then
    ko "arms: the check passes on the forelegs driven by the arms too, so it tells nothing"
fi
# the floor as the sweep judges it: median within 3% of the height, p95 within 10%
awk 'BEGIN { RS = "" } { if (!match($0, /"floor_median": *-?[0-9.e+-]+/)) exit 1;
     m = substr($0, RSTART, RLENGTH); sub(/.*: */, "", m);
     if (!match($0, /"floor_p95": *[0-9.e+-]+/)) exit 1;
     p = substr($0, RSTART, RLENGTH); sub(/.*: */, "", p);
     m += 0; p += 0; exit (m < -0.03 || m > 0.03 || p > 0.10) }' "$tmp/gait.json" ||
    ko "gait: the walk leaves the floor (floor median or p95 past 3% / 10%)"
[ "$fail" -eq 0 ] || exit 1
echo "ok"

#!/bin/sh
# rig-bench --look: the CMU walk played on each auto-rig and judged on the mesh (doc/autorig.md,
# "rig-bench"). On RiggedFigure and the Fox (the general rigger, the walk's first 60 frames):
# - the look columns are there, after the old ones, finite, and their status ok;
# - they agree with the measure line of `rigflow run pipelines/scan-to-animation.json` on the same
#   model and frames, run as a user runs it with the bench's 120 measured frames (the line
#   rounds to a tenth or a hundredth: within 0.051 or 0.0051), so the bench's graph is the
#   pipeline's and reads the figures it prints; the direction fidelity (mean, p95) as that
#   line prints it and the feet as the retarget's contact pass logs them;
# - the old columns are what rig-bench gives without --look (the seconds aside), whose look
#   columns read nan with the status "off".
# Then look bars, the CMU walk's frames 0-119 on RobotExpressive,
# RiggedFigure and the Fox with each rigger, each of which looks right on its rendered sheet
# (doc/autorig.md, "The look"); below, with the broken figures that set them. Then the floor
# p95 of the winged creatures whose wings are laid as arms (under 10% of the height), the fire
# dragon's wings whole (stretch p99 under 25), and over the whole walk (rig-bench's default) the
# parts of both winged creatures over the floor in all but 2% of the frames and their floor p95
# under 5 (not floating in the jumps). Then legs that swing the wrong way: the four-legged
# animalia auto-rigs on 4 feet and the walk's directions within 50 degrees mean (75 for the general
# rigger's cat, whose legs are single bones as its artist's), and the bull
# frog's splayed leg boxes facing as its artist's rig. Then the bodies
# without legs: the Ogre fish and the angelfish on their skin in every frame, greenman's arms
# hanging as the walk's, huesitos' stem moving with it. Then a motion that cannot be read: the
# rig's row is still there and ok, the look's status
# says the motion failed, exit 0; a missing motion file, --look-frames without --look or under
# 2 are usage errors (exit 2).
rigflow="${RF_BUILDDIR:-.}/rigflow"
src="${RF_SRCDIR:-.}"
data="${RF_DATA_DIR:-}"
walk="$data/bvh/cmu_01_01.bvh"
if [ ! -f "$data/models/RiggedFigure.glb" ] || [ ! -f "$data/models/Fox.glb" ] ||
    [ ! -f "$walk" ]; then
    echo "SKIP: RF_DATA_DIR ($data) lacks RiggedFigure, the Fox or the CMU walk"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
ko() {
    echo "FAIL: $*"
    fail=1
}
models="$data/models/RiggedFigure.glb $data/models/Fox.glb"
# shellcheck disable=SC2086
if ! "$rigflow" rig-bench -r general --look "$walk" --look-frames 60 $models \
    >"$tmp/look.csv" 2>"$tmp/err"; then
    cat "$tmp/err"
    ko "rig-bench --look exit $?"
fi
# shellcheck disable=SC2086
"$rigflow" rig-bench -r general $models >"$tmp/plain.csv" 2>>"$tmp/err" || ko "rig-bench exit $?"
cat "$tmp/look.csv"

# A column by its header name (the model's row: rigger and model names hold no comma).
cell() { # file, model, column
    awk -F, -v m="\"$2\"" -v c="$3" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        $2 == m { print $(col[c]) }' "$1"
}
header=$(head -1 "$tmp/look.csv")
case "$header" in
*,seconds,status,look_stretch_p99,look_worst_part,look_worst_joint,look_torn_p99,look_floor_median,look_floor_p95,look_parts_below,look_fidelity_mean,look_fidelity_p95,look_feet,look_source_feet,look_volume_off,look_status)
    echo "PASS: the look columns follow the old ones" ;;
*) ko "header: $header" ;;
esac
[ "$(head -1 "$tmp/plain.csv")" = "$header" ] || ko "the header changes with --look"

# near a b tolerance
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(d <= t && d >= -t) }'; }
# animate FILE: pipelines/scan-to-animation.json on FILE over the walk's first 60 frames, run as
# a user runs it; its measure line on the mesh into $line and its figures into l_torn, l_median,
# l_p95, l_stretch, l_part and l_joint (false, the run's output shown, when the run fails)
animate() {
    if ! "$rigflow" run "$src/pipelines/scan-to-animation.json" \
        -p "mesh.path=$1" -p "motion.path=$walk" -p retarget.last_frame=59 \
        -p measure.mesh_frames=120 -p "export.path=$tmp/out.glb" >"$tmp/run" 2>&1; then
        cat "$tmp/run"
        return 1
    fi
    line=$(grep '^measure: mesh' "$tmp/run")
    l_torn=$(echo "$line" | sed -n 's/.*torn p99 \([0-9.]*\);.*/\1/p')
    l_median=$(echo "$line" | sed -n 's/.*; floor median \([-+0-9.]*\) p95.*/\1/p')
    l_p95=$(echo "$line" | sed -n 's/.*; floor median [-+0-9.]* p95 \([0-9.]*\) .*/\1/p')
    l_stretch=$(echo "$line" | sed -n 's/.*; stretch p99 \([0-9.]*\);.*/\1/p')
    l_part=$(echo "$line" | sed -n "s/.*; worst part \([0-9.]*\) (joint '\([^']*\)'.*/\1/p")
    l_joint=$(echo "$line" | sed -n "s/.*; worst part [0-9.]* (joint '\([^']*\)'.*/\1/p")
    l_fid=$(sed -n 's/^measure: direction fidelity \([0-9.]*\) deg mean (p95 \([0-9.]*\),.*/\1 \2/p' \
        "$tmp/run")
    l_feet=$(sed -n 's/.*contact pass ([a-z.]*): \([0-9]*\) feet.*/\1/p' "$tmp/run")
}
for name in RiggedFigure.glb Fox.glb; do
    stretch=$(cell "$tmp/look.csv" "$name" look_stretch_p99)
    part=$(cell "$tmp/look.csv" "$name" look_worst_part)
    joint=$(cell "$tmp/look.csv" "$name" look_worst_joint)
    torn=$(cell "$tmp/look.csv" "$name" look_torn_p99)
    median=$(cell "$tmp/look.csv" "$name" look_floor_median)
    p95=$(cell "$tmp/look.csv" "$name" look_floor_p95)
    status=$(cell "$tmp/look.csv" "$name" look_status)
    if [ "$status" != '"ok"' ]; then
        ko "$name: look status $status"
        continue
    fi
    for v in "$stretch" "$part" "$torn" "$median" "$p95"; do
        awk -v v="$v" 'BEGIN { exit !(v ~ /^[-+]?[0-9]+\.[0-9]+$/) }' ||
            ko "$name: a look figure is not a finite number: '$v'"
    done
    # the same model and frames as a user runs the pipeline
    if ! animate "$data/models/$name"; then
        ko "scan-to-animation on $name"
        continue
    fi
    if [ -z "$l_torn" ] || [ -z "$l_median" ] || [ -z "$l_p95" ] || [ -z "$l_stretch" ] ||
        [ -z "$l_part" ]; then
        echo "$line"
        ko "$name: the measure line does not read"
    elif near "$stretch" "$l_stretch" 0.051 && near "$part" "$l_part" 0.051 &&
        near "$torn" "$l_torn" 0.0051 && near "$median" "$l_median" 0.051 &&
        near "$p95" "$l_p95" 0.051 && [ "$joint" = "\"$l_joint\"" ]; then
        echo "PASS: $name: look $stretch / $part ($joint) / torn $torn / floor $median, $p95" \
            "as the pipeline's line: $l_stretch / $l_part / $l_torn / $l_median, $l_p95"
    else
        echo "$line"
        ko "$name: look $stretch / $part ($joint) / $torn / $median / $p95, the pipeline's line" \
            "$l_stretch / $l_part ($l_joint) / $l_torn / $l_median / $l_p95"
    fi
    # the direction fidelity as the measure line prints it, the feet as the contact pass logs them
    fid="$(cell "$tmp/look.csv" "$name" look_fidelity_mean) $(cell "$tmp/look.csv" "$name" \
        look_fidelity_p95)"
    feet=$(cell "$tmp/look.csv" "$name" look_feet)
    # shellcheck disable=SC2086
    if [ -n "$l_fid" ] && [ -n "$l_feet" ] && [ "$fid" = "$l_fid" ] && [ "$feet" = "$l_feet" ]; then
        echo "PASS: $name: look fidelity $fid, $feet feet as the pipeline's lines"
    else
        ko "$name: look fidelity $fid, $feet feet; the pipeline's lines: $l_fid, ${l_feet:-no} feet"
    fi
    # the old columns as without --look (all but the seconds), the look's nan and "off"
    a=$(grep -F ",\"$name\"," "$tmp/look.csv" | cut -d, -f1-19,21)
    b=$(grep -F ",\"$name\"," "$tmp/plain.csv" | cut -d, -f1-19,21)
    [ -n "$a" ] && [ "$a" = "$b" ] || ko "$name: the old columns differ with --look: $a / $b"
    off=$(grep -F ",\"$name\"," "$tmp/plain.csv" | cut -d, -f22-)
    [ "$off" = 'nan,nan,"",nan,nan,nan,nan,nan,nan,nan,nan,nan,"off"' ] || ko "$name: without --look the look reads $off"
done

# The look plays on the model that was rigged. Turned 30 degrees about its up (its declared axes
# with it), RiggedFigure and the Fox are rigged as unmoved, turned, and the walk must look the
# same on them: each figure measured and within 1 (stretch, worst part) or 0.1 (torn, floor) of
# the unmoved row's (equal now, to the last digit). Laid on its side (a quarter turn about x,
# the declared up kept: a model saved lying in a format whose axes are fixed), each model's look
# must be the measure line of scan-to-animation.json run as a user runs it on the same model
# written lying by a transform and an export: the Fox's stretch p99 reads 150.4 there and 56.1
# unmoved (RiggedFigure 60.5 and 29.4), the unmoved figure being what the bench gave before it
# played the motion on the moved model.
# shellcheck disable=SC2086
"$rigflow" rig-bench -r general --turn 30 --look "$walk" --look-frames 60 $models \
    >"$tmp/turned.csv" 2>"$tmp/err" || ko "rig-bench --turn 30 --look exit $?"
# shellcheck disable=SC2086
"$rigflow" rig-bench -r general --axis 1,0,0 --turn 90 --fixed-axes --look "$walk" \
    --look-frames 60 $models >"$tmp/lying.csv" 2>"$tmp/err" || ko "rig-bench lying exit $?"
cat >"$tmp/lay.json" <<'JSON'
{"format": "rigflow.pipeline", "version": 1, "nodes": [
 {"id": "in", "type": "import", "params": {"require_skeleton": false, "ignore_rig": true}},
 {"id": "lay", "type": "transform", "inputs": {"skeleton": "in.skeleton", "mesh": "in.mesh"},
  "params": {"turn": 90, "axis": "1,0,0", "turn_axes": false}},
 {"id": "export", "type": "export", "inputs": {"skeleton": "lay.skeleton", "mesh": "lay.mesh"}}]}
JSON
for name in RiggedFigure.glb Fox.glb; do
    bad=""
    for c in look_stretch_p99:1 look_worst_part:1 look_torn_p99:0.1 look_floor_median:0.1 \
        look_floor_p95:0.1; do
        col=${c%:*} bar=${c#*:}
        a=$(cell "$tmp/look.csv" "$name" "$col") b=$(cell "$tmp/turned.csv" "$name" "$col")
        awk -v v="$b" 'BEGIN { exit !(v ~ /^[-+]?[0-9]+\.[0-9]+$/) }' && near "$a" "$b" "$bar" ||
            bad="$bad $col $a -> $b"
    done
    if [ -z "$bad" ] && [ "$(cell "$tmp/turned.csv" "$name" look_status)" = '"ok"' ]; then
        echo "PASS: $name turned 30 degrees looks as unmoved:" \
            "$(cell "$tmp/turned.csv" "$name" look_stretch_p99) /" \
            "$(cell "$tmp/turned.csv" "$name" look_worst_part)"
    else
        ko "$name turned 30 degrees: status $(cell "$tmp/turned.csv" "$name" look_status),$bad"
    fi
    if ! RIGFLOW_QUIET=1 "$rigflow" run "$tmp/lay.json" -p "in.path=$data/models/$name" \
        -p "export.path=$tmp/lying-$name" >"$tmp/run" 2>&1; then
        cat "$tmp/run"
        ko "$name written lying"
        continue
    fi
    if ! animate "$tmp/lying-$name"; then
        ko "scan-to-animation on $name written lying"
        continue
    fi
    stretch=$(cell "$tmp/lying.csv" "$name" look_stretch_p99)
    part=$(cell "$tmp/lying.csv" "$name" look_worst_part)
    plain=$(cell "$tmp/look.csv" "$name" look_stretch_p99)
    if [ -n "$l_stretch" ] && near "$stretch" "$l_stretch" 0.051 && near "$part" "$l_part" 0.051
    then
        echo "PASS: $name lying: look $stretch / $part as the pipeline's line on it written" \
            "lying, $l_stretch / $l_part (unmoved $plain)"
    else
        echo "$line"
        ko "$name lying: look $stretch / $part, the pipeline's line on it $l_stretch / $l_part"
    fi
done

# Look bars. Each sits between the figures of the sound rigs (general / template, now: the
# robot 28.3 / 30.7 and 56.6 / 68.6, RiggedFigure 31.7 / 29.9 and 49.1 / 49.1, the Fox
# 66.7 / 62.6 and 86.0 / 82.0) and of a case seen broken on its rendered sheet:
# - stretch p99 of the whole mesh under 100: RobotExpressive read 323.2 on the template rigger
#   with its Head in the middle of its head box (the box's rim drawn down, the arms folded over
#   the body) and 309.9 on the general rigger without its head-piece rule (the box tipped and
#   sheared);
# - the worst part under 150: the same two read 282.5 (RightForeArm) and 498.0 (arm_r0_1);
# - the floor median within 3% of the height (the retarget sweep's rule): spider.obj read
#   +10.8, walking in the air over its feet pinned to the pose's dip (test_rig_looks).
# Testwuson (general / template now 49.5 / 51.3 and 76.2 / 76.5) read 52.7 / 867.4 on the
# general rigger while bone heat's front test ran on its tail tuft's strands, which enclose no
# bone: the strands flew off the tail's tip (worst part tail_c0_1).
# Each bar was checked to fail on those builds; the recorded broken rows are run through the
# same bars below, so a bar loosened past them fails here.
bars() { # stretch, worst part, floor median: the broken bars, one per line
    awk -v s="$1" -v p="$2" -v f="$3" 'BEGIN {
        if (!(s < 100)) print "stretch p99 " s " (bar 100)";
        if (!(p < 150)) print "worst part " p " (bar 150)";
        if (!(f <= 3 && f >= -3)) print "floor median " f " (bar 3)" }'
}
# each broken row (stretch, worst part, floor) with the number of bars it breaks: the robot's
# two both, spider.obj's (81.1 / 111.8 then) the floor's alone, Testwuson's the worst part's
for broken in "323.24 282.50 0.00 2" "309.94 497.99 0.00 2" "81.1 111.8 10.8 1" \
    "52.71 867.39 0.01 1"; do
    # shellcheck disable=SC2086
    set -- $broken
    [ "$(bars "$1" "$2" "$3" | wc -l)" -eq "$4" ] || ko "the look bars on a broken case: $broken"
done
for rigger in general template; do
    # shellcheck disable=SC2086
    if ! "$rigflow" rig-bench -r "$rigger" --look "$walk" --look-frames 120 \
        "$data/models/RobotExpressive.glb" "$data/models/Testwuson.X" $models >"$tmp/bars.csv" \
        2>"$tmp/err"; then
        cat "$tmp/err"
        ko "rig-bench -r $rigger --look exit $?"
        continue
    fi
    for name in RobotExpressive.glb Testwuson.X RiggedFigure.glb Fox.glb; do
        stretch=$(cell "$tmp/bars.csv" "$name" look_stretch_p99)
        part=$(cell "$tmp/bars.csv" "$name" look_worst_part)
        median=$(cell "$tmp/bars.csv" "$name" look_floor_median)
        status=$(cell "$tmp/bars.csv" "$name" look_status)
        broken=$(bars "$stretch" "$part" "$median")
        if [ "$status" != '"ok"' ] || [ -n "$broken" ]; then
            ko "$rigger on $name: look $status: $broken"
        else
            echo "PASS: $rigger on $name: stretch $stretch, worst part $part, floor $median"
        fi
    done
done

# A leg swinging the wrong way: four-legged auto-rigs walk on four feet, and the motion's
# directions come through as on the artists' rigs. The mesh's figures cannot see it: the low-poly
# box rule reverted in 82f9759 (doc/autorig-log.md, "Low-poly boxes ... Reverted") left the cat's
# and the horse's foreleg joints below the box's joint without skin, the retarget found 2 feet,
# the forelegs took the human's arms (rendered: crossed in front of the body, the body twisted),
# and the cat's stretch p99 fell 46.3 -> 19.3. Re-applied on a scratch build (CMU walk, frames
# 0-119): the cat 4 -> 2 feet and direction fidelity 41.8 -> 73.5 degrees mean, the horse 4 -> 2
# feet (fidelity 19.4 -> 18.6: its forelegs follow the arms' directions faithfully, so only the
# feet see it). The fidelity bar, 50 degrees mean, is over the artists' own rigs under the same
# walk (pipelines/retarget.json: the cat 42.0, the wolf 34.6, the animalia fox 30.9, the horse
# 27.7; the cat's rendered walking on four legs), as are the general rigger's auto-rigs now (41.8,
# 39.4, 26.0, 19.4; the cat's, the horse's and the wolf's rendered walking on four legs with their
# legs under the body); the template rigger's read 29.8, 21.8, 40.6, 23.0, each on 4 feet.
# The fidelity bar is 75 for the general rigger's cat since leg boxes move with one joint and the
# joints inside them are dropped (doc/autorig-log.md, "Leg boxes moved by one joint, landed"): the cat's auto-rig then
# has one-bone legs as the artist's, and reads 70.3 over 7 mapped bones (13 before). The artist's
# cat reads 43.8 under the same walk over 4 bones, its legs alone; the auto-rig's mean also
# counts its spine and neck, level where the human's stand (near a right angle whatever the
# rig does). Rendered (scan-to-animation, frames 0-119), that cat walks on four rigid leg boxes
# under a level body, on 4 feet, where before the boxes sheared into wedges. A leg swinging the
# wrong way is still caught by the feet (the broken cat read 2); the horse, the wolf and the fox
# read 18.6, 39.4 and 26.0 and keep the bar of 50, as every template rig does (their legs keep
# their joints).
legs() { # feet, fidelity mean, fidelity bar: the broken bars, one per line
    awk -v n="$1" -v d="$2" -v bar="$3" 'BEGIN {
        if (n != 4) print n " feet (bar 4)";
        if (!(d < bar)) print "fidelity " d " deg (bar " bar ")" }'
}
# the broken rows above with their bar and the number of bars each breaks: the cat's feet (its
# 73.52 degrees under the bar of 75), the horse the feet's; made-up rows over both, and over 50
for broken in "2 73.52 75 1" "2 18.57 50 1" "2 80 75 2" "4 51 50 1"; do
    # shellcheck disable=SC2086
    set -- $broken
    [ "$(legs "$1" "$2" "$3" | wc -l)" -eq "$4" ] || ko "the leg bars on a broken case: $broken"
done
four=""
for m in animalia_cat animala_horse animalia_wolf animalia_fox; do
    [ -f "$data/models/creatures/$m.b3d" ] && four="$four $data/models/creatures/$m.b3d"
done
# the bench's rows of the four-legged, the rows' feet and fidelity against the bars
legs_check() { # rigger
    # shellcheck disable=SC2086
    if ! "$rigflow" rig-bench -r "$1" --look "$walk" --look-frames 120 $four \
        >"$tmp/legs.csv" 2>"$tmp/err"; then
        cat "$tmp/err"
        ko "rig-bench -r $1 --look on the four-legged exit $?"
        return
    fi
    for f in $four; do
        name=$(basename "$f")
        feet=$(cell "$tmp/legs.csv" "$name" look_feet)
        fid=$(cell "$tmp/legs.csv" "$name" look_fidelity_mean)
        source=$(cell "$tmp/legs.csv" "$name" look_source_feet)
        bar=50
        [ "$1/$name" = general/animalia_cat.b3d ] && bar=75
        broken=$(legs "$feet" "$fid" "$bar")
        if [ -n "$broken" ]; then
            ko "$1 on $name: $(echo "$broken" | tr '\n' ';')"
        else
            echo "PASS: $1 on $name: $feet feet (following the walk's $source), direction" \
                "fidelity $fid deg mean"
        fi
    done
}
if [ -z "$four" ]; then
    echo "SKIP: RF_DATA_DIR ($data) lacks the animalia creatures: their feet not checked"
else
    legs_check general
    legs_check template
fi
# Leg boxes lying splayed on the floor keep their joints and feet: the animalia bull frog's,
# moved by one joint each with the joints inside dropped, became one-bone legs whose bones the
# skeleton analysis took for feet pointing back; the rig read facing backwards (forward_agree
# -1, after the matcher 0 / 0), and with those bones casting no feet vote still lost (.654 /
# .692 against .676 / .759). Its facing must agree and its skinning after the matcher hold.
frog="$data/models/creatures/animalia_bull_frog.b3d"
if [ -f "$frog" ]; then
    "$rigflow" rig-bench -r general --joint-map matcher "$frog" >"$tmp/frog.csv" 2>"$tmp/err" ||
        ko "rig-bench on the bull frog exit $?"
    fa=$(cell "$tmp/frog.csv" animalia_bull_frog.b3d forward_agree)
    fp=$(cell "$tmp/frog.csv" animalia_bull_frog.b3d precision)
    fr=$(cell "$tmp/frog.csv" animalia_bull_frog.b3d recall)
    if awk -v a="$fa" -v p="$fp" -v r="$fr" 'BEGIN { exit !(a > 0.99 && p >= 0.67 && r >= 0.75) }'
    then
        echo "PASS: the bull frog faces as its artist's rig ($fa), after the matcher $fp / $fr"
    else
        ko "the bull frog: forward_agree $fa (bar 1), after the matcher $fp / $fr (bars 0.67 / 0.75)"
    fi
fi

# Wings laid as arms stay over the floor. The general rigger lays the fire dragon's and the
# jungle wyvern's wings as arms (the template rigger the wyvern's); the CMU walk's arms hang
# them down through the floor unless the retarget's parts pass turns them up (doc/retargeting.md,
# "Parts that are not feet"). Floor p95 (the lowest vertex over the rest floor, either way, % of
# the height) under 10: one turn per part and frame left the membranes' other edges through the
# floor, the dragon 35.8 (its feet in the air, the clip raised over its wings), the wyvern 17.7
# and 11.7 on the template rigger; now 5.1, 5.9 and 2.6 (rendered: on its feet, the wings on
# the floor). The bat (general rigger, 5.1 -> 1.8) is not barred. These bars read the walk's
# first 120 frames; over the whole walk the jumps lift the dragon off the floor further than the
# walk's own lowest point is lifted (floor p95 14.6, floating).
# Over the whole walk, the crouches before its jumps swing the wings down, and a wing held whole
# from its shoulder (doc/retargeting.md, "Limbs that cannot hang") was no part the parts pass
# could lift: the general rigger's dragon had parts (vertices high at rest) under the floor in
# 14.2% of the frames, 30% of its height deep. Both riggers' dragon and the general rigger's
# wyvern: parts under the floor in under 2% of the whole walk's frames. The template rigger's
# wyvern reads 35% before and after: that rig skins vertices high at rest to the legs (the left
# shin's reach 6.2 units against a leg of 2.0), which the feet's chains carry through the floor;
# not barred.
# In the walk's jumps the hips rise by the source's rise scaled by the legs, while legs of
# another build posed with the human's turns do not reach down as far: the dragon and the wyvern
# floated, floor p95 over the whole walk 14.6 and 8.4 (general rigger), 12.8 (template's
# dragon). The retarget now lowers any frame that stands higher than the source over its floor
# (doc/retargeting.md, "Holding the floor"): 1.5, 2.8 and 1.5. Bar 5, on the same rows (the
# template rigger's wyvern, whose feet carry high vertices through the floor, not barred).
dragon="$data/models/creatures/draconis_fire_dragon.b3d"
wyvern="$data/models/creatures/draconis_jungle_wyvern.b3d"
if [ -f "$dragon" ] && [ -f "$wyvern" ]; then
    for rigger in general template; do
        if ! "$rigflow" rig-bench -r "$rigger" --look "$walk" "$dragon" "$wyvern" \
            >"$tmp/whole.csv" 2>"$tmp/err"; then
            cat "$tmp/err"
            ko "rig-bench -r $rigger --look on the winged creatures, the whole walk, exit $?"
        fi
        for name in draconis_fire_dragon.b3d draconis_jungle_wyvern.b3d; do
            [ "$rigger" = template ] && [ "$name" = draconis_jungle_wyvern.b3d ] && continue
            grep -F ",\"$name\"," "$tmp/whole.csv" | grep -q ',"not run: no rig"$' && continue
            below=$(cell "$tmp/whole.csv" "$name" look_parts_below)
            status=$(cell "$tmp/whole.csv" "$name" look_status)
            if [ "$status" = '"ok"' ] && awk -v v="$below" 'BEGIN { exit !(v < 2) }'; then
                echo "PASS: $rigger on $name, the whole walk: parts under the floor in $below%" \
                    "of the frames (bar 2)"
            else
                ko "$rigger on $name, the whole walk: look $status, parts under the floor in" \
                    "$below% of the frames (bar 2)"
            fi
            p95=$(cell "$tmp/whole.csv" "$name" look_floor_p95)
            if awk -v v="$p95" 'BEGIN { exit !(v < 5) }'; then
                echo "PASS: $rigger on $name, the whole walk: floor p95 $p95 (bar 5)"
            else
                ko "$rigger on $name, the whole walk: floor p95 $p95 (bar 5), floating in the jumps"
            fi
        done
        if ! "$rigflow" rig-bench -r "$rigger" --look "$walk" --look-frames 120 "$dragon" \
            "$wyvern" >"$tmp/wings.csv" 2>"$tmp/err"; then
            cat "$tmp/err"
            ko "rig-bench -r $rigger --look on the winged creatures exit $?"
            continue
        fi
        for name in draconis_fire_dragon.b3d draconis_jungle_wyvern.b3d; do
            p95=$(cell "$tmp/wings.csv" "$name" look_floor_p95)
            status=$(cell "$tmp/wings.csv" "$name" look_status)
            # the template rigger refuses the dragon (no rig to play the walk on; its refusal
            # holds commas, so the row is read whole): not barred
            if [ "$rigger" = template ] &&
                grep -F ",\"$name\"," "$tmp/wings.csv" | grep -q ',"not run: no rig"$'; then
                echo "PASS: $rigger refuses $name: nothing to look at"
                continue
            fi
            if [ "$status" = '"ok"' ] && awk -v v="$p95" 'BEGIN { exit !(v < 10) }'; then
                echo "PASS: $rigger on $name: floor p95 $p95 (bar 10)"
            else
                ko "$rigger on $name: look $status, floor p95 $p95 (bar 10)"
            fi
            # The fire dragon's wings move whole from the shoulder (doc/retargeting.md, "Limbs
            # that cannot hang"): bent at CMU's elbows and wrists and lifted off the floor they
            # fanned their membranes into shards, stretch p99 45.7 (general) and 45.6
            # (template); now 11.9 and 11.5. Bar 25.
            stretch=$(cell "$tmp/wings.csv" "$name" look_stretch_p99)
            if [ "$name" = draconis_fire_dragon.b3d ]; then
                if awk -v v="$stretch" 'BEGIN { exit !(v < 25) }'; then
                    echo "PASS: $rigger on $name: wings whole, stretch p99 $stretch (bar 25)"
                else
                    ko "$rigger on $name: stretch p99 $stretch (bar 25)"
                fi
            fi
        done
    done
else
    echo "SKIP (part): the fire dragon or the jungle wyvern is not in $data/models/creatures"
fi

# Bodies without legs stand on their skin (doc/retargeting.md, "Bodies without legs"). Under
# the CMU walk (frames 0-119, the general rigger):
# - a fish lying on its fins and the angelfish take the walk's lean (eased) and kept their lowest
#   vertex on the floor only in the median frame: floor p95 10.7 and 13.5% of the height, the
#   fish's nose and fins through the floor in the frames the walk leans furthest; now every frame
#   stands on the skin (0.3 and 0.6, 24 of the 120 frames measured): bar 3, now read over the
#   whole walk (1.0 and 1.7; every one of the first 120 frames measured, the angelfish reads 3.5);
# - greenman's auto-rig (a bottom joint, a chest, two arms) was read with its hips at the chest:
#   legs 0.018 units (the artist's rig of the same body reads 0.59), the floor for parts that are
#   not feet at the hands' height, so the parts pass held both arms up in 119 of 120 frames and
#   the one whose shoulder lies high in the body swung through the top of it (rendered);
#   retarget.measure's direction fidelity 36.1 degrees mean over its 7 bones. Now legs 0.52 from
#   the two bodies' heights, the arms hang as the walk's do (16.5 degrees, all but the left
#   clavicle, whose bone points another way than CMU's, within a few): legs 0.3 to 1.0 and the
#   fidelity under 25;
# - huesitos' auto-rig stands on a stem above its hips in the tree that nothing drives: with its
#   legs measured to the stem's foot, root motion left the stem behind (stretch p99 52.3); the
#   stem now moves with the body (12.3): bar 30, frames 0-119 (the whole walk reads 76.8).
fish="$data/models/ogre/fish.mesh"
angel="$data/models/creatures/animalia_angelfish.b3d"
if [ -f "$fish" ] && [ -f "$angel" ] && [ -f "$data/models/greenman.glb" ] &&
    [ -f "$data/models/huesitos.fbx" ]; then
    if "$rigflow" rig-bench -r general --look "$walk" "$fish" "$angel" >"$tmp/legless.csv" \
        2>"$tmp/err" && "$rigflow" rig-bench -r general --look "$walk" --look-frames 120 \
        "$data/models/huesitos.fbx" >"$tmp/stem.csv" 2>>"$tmp/err"; then
        for name in fish.mesh animalia_angelfish.b3d; do
            p95=$(cell "$tmp/legless.csv" "$name" look_floor_p95)
            if [ "$(cell "$tmp/legless.csv" "$name" look_status)" = '"ok"' ] &&
                awk -v v="$p95" 'BEGIN { exit !(v < 3) }'; then
                echo "PASS: $name stands on its skin: floor p95 $p95 (bar 3)"
            else
                ko "$name: floor p95 $p95 (bar 3)"
            fi
        done
        stretch=$(cell "$tmp/stem.csv" huesitos.fbx look_stretch_p99)
        if awk -v v="$stretch" 'BEGIN { exit !(v < 30) }'; then
            echo "PASS: huesitos' stem moves with its body: stretch p99 $stretch (bar 30)"
        else
            ko "huesitos: stretch p99 $stretch (bar 30)"
        fi
    else
        cat "$tmp/err"
        ko "rig-bench --look on the legless bodies exit $?"
    fi
    if "$rigflow" run "$src/pipelines/scan-to-animation.json" \
        -p "mesh.path=$data/models/greenman.glb" -p "motion.path=$walk" \
        -p retarget.last_frame=119 -p "export.path=$tmp/out.glb" >"$tmp/run" 2>&1; then
        legs=$(sed -n "s/.*node 'retarget': info: .*; legs [0-9.]* -> \([0-9.e+-]*\) .*/\1/p" \
            "$tmp/run")
        fid=$(sed -n 's/^measure: direction fidelity \([0-9.]*\) deg mean.*/\1/p' "$tmp/run")
        if awk -v l="$legs" -v f="$fid" 'BEGIN { exit !(l >= 0.3 && l <= 1 && f != "" && f < 25) }'
        then
            echo "PASS: greenman's arms hang from its chest: legs $legs, fidelity $fid degrees"
        else
            grep -E "legs|^measure" "$tmp/run"
            ko "greenman: legs $legs (bar 0.3 to 1), direction fidelity $fid (bar 25)"
        fi
    else
        cat "$tmp/run"
        ko "scan-to-animation on greenman"
    fi
else
    echo "SKIP (part): the fish, the angelfish, greenman or huesitos is not in $data/models"
fi

# A motion that moves no bone of the rig is not a look: the CMU walk with every offset zero
# (each joint at the root: the matcher maps the root alone, retarget.measure reads 0 bones and
# every mesh figure 0) read 0.00 everywhere and "ok", the best look of any row.
sed 's/OFFSET.*/OFFSET 0 0 0/' "$walk" >"$tmp/collapsed.bvh"
"$rigflow" rig-bench -r general --look "$tmp/collapsed.bvh" --look-frames 2 \
    "$data/models/Fox.glb" >"$tmp/none.csv" 2>"$tmp/err"
code=$?
row=$(tail -n +2 "$tmp/none.csv")
if [ "$code" = 0 ] && echo "$row" | grep -q ',"ok",nan,nan,"",nan,nan,nan,nan,nan,nan,nan,nan,nan,"not measured: .*no bone'; then
    echo "PASS: a motion that moves no bone is the look's status: $(echo "$row" | cut -d, -f29-)"
else
    ko "a motion that moves no bone: exit $code, row $row"
fi

# A motion that cannot be read fails the look, not the row.
printf 'HIERARCHY\nROOT Hips\n{\n' >"$tmp/cut.bvh"
"$rigflow" rig-bench -r general --look "$tmp/cut.bvh" "$data/models/RiggedFigure.glb" \
    >"$tmp/bad.csv" 2>"$tmp/err"
code=$?
row=$(tail -n +2 "$tmp/bad.csv")
if [ "$code" != 0 ]; then
    cat "$tmp/err"
    ko "a motion that cannot be read: exit $code, expected 0"
elif ! echo "$row" | grep -q ',"ok",nan,nan,"",nan,nan,nan,nan,nan,nan,nan,nan,nan,"failed: .*motion'; then
    ko "a motion that cannot be read: row $row"
else
    echo "PASS: a motion that cannot be read is the look's status: $(echo "$row" | cut -d, -f29-)"
fi
"$rigflow" rig-bench -r general --look "$tmp/none.bvh" "$data/models/RiggedFigure.glb" \
    >"$tmp/out" 2>"$tmp/err"
code=$?
if [ "$code" = 2 ] && grep -q "none.bvh: no such file" "$tmp/err" && [ ! -s "$tmp/out" ]; then
    echo "PASS: a missing motion file is a usage error"
else
    ko "a missing motion file: exit $code, $(cat "$tmp/err")"
fi
for args in "--look-frames 60" "--look $walk --look-frames 1"; do
    # shellcheck disable=SC2086
    "$rigflow" rig-bench -r general $args "$data/models/RiggedFigure.glb" >"$tmp/out" 2>"$tmp/err"
    code=$?
    if [ "$code" = 2 ] && grep -q -- "--look-frames: " "$tmp/err" && [ ! -s "$tmp/out" ]; then
        echo "PASS: rig-bench $args is a usage error: $(cat "$tmp/err")"
    else
        ko "rig-bench $args: exit $code, $(cat "$tmp/err")"
    fi
done
# A low-poly body box blended among its trunk and its legs' roots: the bull frog's, dragged flat
# by its legs under the walk (rendered), read neither torn nor much stretched (stretch p99 55.6%
# of its height), but its volume went: the worst closed solid part's strayed 91.7% from its rest
# volume (p95 over the frames; the body box itself). Moved by the trunk alone (rf_rig_body_box_keep)
# the body box keeps it, and the worst solid is a foot box at 59.4%: the bar is 80.
if "$rigflow" rig-bench -r general --look "$walk" --look-frames 120 \
    "$data/models/creatures/animalia_bull_frog.b3d" >"$tmp/frog.csv" 2>"$tmp/err"; then
    off=$(cell "$tmp/frog.csv" animalia_bull_frog.b3d look_volume_off)
    status=$(cell "$tmp/frog.csv" animalia_bull_frog.b3d look_status)
    if [ "$status" = '"ok"' ] && awk -v v="$off" 'BEGIN { exit !(v + 0 == v && v < 80) }'; then
        echo "PASS: the bull frog's worst solid part off its volume by $off%"
    else
        ko "the bull frog's worst solid part off its volume by $off% (status $status)"
    fi
else
    cat "$tmp/err"
    ko "rig-bench --look bull frog exit $?"
fi
exit $fail

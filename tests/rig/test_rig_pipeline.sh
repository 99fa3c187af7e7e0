#!/bin/sh
# The auto-rigging pipelines end to end and rig-bench's regression thresholds.
# - pipelines/autorig.json on Debian's WusonOBJ.obj and spider.obj turned into STL: skinned GLBs
#   the Khronos glTF-Validator accepts; a flat mesh is refused with a reason and leaves no file.
# - pipelines/scan-to-animation.json: spider.obj (eight legs, no rig) walks the CMU walk; the GLB
#   validates and holds the clip.
# - rigflow rig-bench on eight rigged models with their rigs ignored: every vertex weighted, skinning
#   (after the matcher, and on the artist skeleton, with its L1 below a ceiling) above floors,
#   both rigs read the same way up and facing, and CD-J2J (fraction of the longest bounding-box
#   edge) below the thresholds
#   doc/autorig.md records; a worse rigger fails here.
# - the template rigger (pipelines/autorig-template.json, rig-bench -r template): WusonOBJ.obj gets
#   the standard names; a sphere (no legs) and spider.obj (eight legs) are refused with the reason
#   and leave no file; RiggedFigure, the Fox, Testwuson and the animalia wolf under CD-J2J and
#   skinning limits.
rigflow="${RF_BUILDDIR:-.}/rigflow"
src="${RF_SRCDIR:-.}"
data="${RF_DATA_DIR:-}"
models=/usr/share/assimp/models/OBJ
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
ko() { fail=$((fail + 1)); printf 'FAIL: %s\n' "$*"; }
. "$src/tests/gltf/valid.sh"
valid() { gltf_valid "$1"; }
inspect_has() { # file, pattern
    if "$rigflow" inspect "$1" 2>&1 | grep -q -- "$2"; then ok; else ko "inspect $1: no /$2/"; fi
}

if [ ! -f "$models/WusonOBJ.obj" ]; then
    echo "assimp-testmodels not installed ($models): skipped"
    exit 77
fi
autorig() { RIGFLOW_QUIET=1 "$rigflow" run "$src/pipelines/autorig.json" -p "mesh.path=$1" -p "export.path=$2"; }
if autorig "$models/WusonOBJ.obj" "$tmp/wuson.glb"; then ok; else ko "autorig WusonOBJ.obj"; fi
valid "$tmp/wuson.glb"
inspect_has "$tmp/wuson.glb" "skinned (4 weights per vertex)"
inspect_has "$tmp/wuson.glb" "leg_"
# STL keeps no shared vertices (every triangle its own three): welding makes it one body again
if command -v assimp >/dev/null && assimp export "$models/spider.obj" "$tmp/spider.stl" >/dev/null 2>&1; then
    if autorig "$tmp/spider.stl" "$tmp/spider.glb" 2>"$tmp/err"; then ok; else cat "$tmp/err"; ko "autorig spider.stl"; fi
    valid "$tmp/spider.glb"
else
    echo "assimp command (assimp-utils) not found: the STL case skipped"
fi

# the template rigger: standard names, or a refusal naming what the body lacks
tautorig() { RIGFLOW_QUIET=1 "$rigflow" run "$src/pipelines/autorig-template.json" -p "mesh.path=$1" -p "export.path=$2"; }
if tautorig "$models/WusonOBJ.obj" "$tmp/wuson-t.glb"; then ok; else ko "autorig-template WusonOBJ.obj"; fi
valid "$tmp/wuson-t.glb"
inspect_has "$tmp/wuson-t.glb" "LeftUpLeg"
inspect_has "$tmp/wuson-t.glb" "RightForeArm"
sphere=/usr/share/assimp/models/STL/sphereWithHole.stl
if tautorig "$sphere" "$tmp/sphere.glb" 2>"$tmp/err"; then ko "a sphere rigged with a template"; else ok; fi
if grep -q "node 'rig'.*fits no template.*0 left, 0 right" "$tmp/err" && [ ! -e "$tmp/sphere.glb" ]; then ok; else cat "$tmp/err"; ko "sphere: message or leftover"; fi
if tautorig "$models/spider.obj" "$tmp/spider-t.glb" 2>"$tmp/err"; then ko "a spider rigged with a template"; else ok; fi
if grep -q "fits no template.*4 left, 4 right" "$tmp/err" && [ ! -e "$tmp/spider-t.glb" ]; then ok; else cat "$tmp/err"; ko "spider: message or leftover"; fi

if [ ! -f "$data/bvh/cmu_01_01.bvh" ]; then
    echo "SKIP: RF_DATA_DIR not found (../shared/data): the rest not run"
    echo "$pass passed, $fail failed"
    [ "$fail" -eq 0 ] && exit 77
    exit 1
fi
if RIGFLOW_QUIET=1 "$rigflow" run "$src/pipelines/scan-to-animation.json" -p "mesh.path=$models/spider.obj" \
    -p "motion.path=$data/bvh/cmu_01_01.bvh" -p retarget.last_frame=240 \
    -p "export.path=$tmp/spider-walk.glb" >"$tmp/out" 2>&1; then ok; else cat "$tmp/out"; ko "scan-to-animation spider.obj"; fi
valid "$tmp/spider-walk.glb"
# greenman's blob body, rooted at the joint at its bottom, keeps its shape under the CMU walk:
# hung from the old root in the body's middle, that joint took the walk's hips and turned the body
# over (parts under the floor in a quarter of the frames, stretch p99 84.3); rooted there, no part
# under the floor in more than 5% of the frames (0%), and retarget.measure's stretch p99 (% of the
# edges' rest length) no more than the artist's own rig gives under the same walk (171.5: its
# stub arms swing down to its sides). Since the analysis reads the rig's two arms as a pair they
# swing too (64.7; 20.3 when they were read as the spine and the walk moved none of them).
if autorig "$data/models/greenman.glb" "$tmp/greenman.glb" &&
    "$rigflow" --quiet run "$src/pipelines/retarget.json" -p "source.path=$data/bvh/cmu_01_01.bvh" \
        -p "target.path=$tmp/greenman.glb" -p retarget.last_frame=240 \
        -p "export.path=$tmp/greenman-walk.glb" >"$tmp/out" 2>&1 &&
    "$rigflow" --quiet run "$src/pipelines/retarget.json" -p "source.path=$data/bvh/cmu_01_01.bvh" \
        -p "target.path=$data/models/greenman.glb" -p retarget.last_frame=240 \
        -p "export.path=$tmp/greenman-artist-walk.glb" >"$tmp/artist" 2>&1; then
    stretch=$(sed -n 's/^measure: mesh .*stretch p99 \([0-9.]*\).*/\1/p' "$tmp/out")
    under=$(sed -n 's/^measure: mesh .*parts under the floor \([0-9.]*\)% of frames.*/\1/p' "$tmp/out")
    artist=$(sed -n 's/^measure: mesh .*stretch p99 \([0-9.]*\).*/\1/p' "$tmp/artist")
    if [ -n "$stretch" ] && [ -n "$under" ] && [ -n "$artist" ] &&
        awk -v s="$stretch" -v u="$under" -v a="$artist" 'BEGIN { exit !(s <= a && u <= 5) }'; then ok
    else
        cat "$tmp/out" "$tmp/artist"
        ko "greenman under the CMU walk: stretch p99 $stretch (the artist's rig $artist), parts under the floor in $under% of frames (limit 5)"
    fi
else
    cat "$tmp/out" "$tmp/artist" 2>/dev/null; ko "greenman: autorig and retarget"
fi
inspect_has "$tmp/spider-walk.glb" "241 frames"

# refusals leave nothing behind
if autorig "$data/models/simple_skin.gltf" "$tmp/flat.glb" 2>"$tmp/err"; then ko "a flat strip rigged"; else ok; fi
if grep -q "node 'rig'.*flat" "$tmp/err" && [ ! -e "$tmp/flat.glb" ]; then ok; else cat "$tmp/err"; ko "flat: message or leftover"; fi

# rig-bench thresholds (doc/autorig.md), per model: CD-J2J, the skinning after the matcher and on
# the skeleton of the artist, no vertex unweighted, the analysis reading both rigs the same way up
# and facing (the animalia wolf, a .b3d file that declares no forward, is read facing forward
# only with its rig rooted at the hips); the CD-J2J limits of the Fox, RiggedFigure and the wolf
# fail if the limbs go back to bones of even length (0.047, 0.038, 0.069). RiggedFigure's
# skinning after the matcher needs its box head's curve, leaning a little to one side, read as
# the head (an unpaired arm before) and its thigh joints, which win no vertex, kept as body
# joints, not helpers (the matcher counted them as links and shifted each leg by a joint): 53% /
# 36% without both; the Wizard's needs its spine read along the declared up with the staff in
# the right hand, the plane re-centred once upright (2% / 1% when the spine ran through the arm
# into the staff); the animalia bird's needs its two-joint head mapped to the artist's one (29% /
# 29% when neither head joint was mapped); the animalia fox's needs its one-bone ears read as
# appendages, not arms making a girdle of its head (13% / 13%). The animalia rigs' one-joint legs
# (no end site in the file) end where the skin they carry ends, at the ground: with a length
# guessed from the hip offset the owl's, bird's and fox's floors here fail (.64/.66, .40/.46,
# .25/.31), and the wolf's and the fox's on the skeleton of the artist were .91/.91/.18 and
# .74/.84/.52 (bone heat, tuned on the guessed leaves, reads the measured ones less well there).
# On the skeleton of the artist the owl's and the cat's limits fail if closed parts enclosing no
# bone go back to bone heat's blend (.76/.88/.41, .85/.90/.30); two pieces of the animalia
# fox's head, which bone heat gives mostly to the neck, move with it since (.70/.82/.61 ->
# .66/.74/.70); its neck box, blended between the bones inside it, keeps bone heat's plain
# rows, not sharpened ones, since (a box model's parts are not torn into wedges): .66/.74/.70
# -> .64/.72/.74 on the skeleton of the artist, .58/.61 -> .60/.65 after the matcher. A one-joint
# leg that has an end (from the skin) still owns the bone from the torso joint it hangs from: the
# wolf's and the fox's limits on the skeleton of the artist fail without (.835/.851/.338,
# .64/.72/.74). A box model's body box moves with the joint holding seven tenths of the bones
# inside it when bone heat gives that joint most of the box: the owl's and the bird's limits on
# the skeleton of the artist fail without (.813/.937/.331, .761/.820/.453). After the matcher
# the wolf's and the Wizard's limits need the artist's skull given to the joint where the curve
# skeleton's head chain enters the head, not its snout or hat tip (.61/.80, .28/.28 without), the
# fox's and the cat's a one-joint leg driving the longer leg's first joint, its hip offset
# included (.60/.65, .51/.58 without; doc/matching.md, "An eighth round"). The cat's, the animalia
# fox's, the wolf's, the owl's and the Wizard's limits after the matcher need the curve skeleton's
# girdle joint, whose bone runs from where the forelimbs leave into the neck, mapped to the
# artist's neck (or one-joint head), not its chest (rig-bench maps with girdle=neck; without it
# .56/.58, .65/.71, .65/.84, .74/.81, .33/.35; doc/matching.md, "A ninth round"); Testwuson's
# its head chain's joints past the artist's skull pivot (at the head's base) given the skull
# (.49/.53 without); the Wizard's its girdle joint, whose bone runs into its big head past the
# artist's skull pivot in the bodies' frames, given the head (.50/.54 with the neck; doc/matching.md,
# "An eleventh round"); Testwuson's its hips, where the rig roots its trunk, given the artist's
# Pelvis at the end of the reverse spine its back runs from a root mid-back and the rest of its
# spine placed along the forward one (.53/.54 with the root's nearest joint, the tail's first;
# .568/.566 with the rest as aligned from the root); the Fox's its trunk, rooted at the shoulders with a
# reverse spine to the hips, placed along the artist's spine, rooted at the hips (.68/.67 with
# the root given the artist's b_Hip_01 and the reverse spine nothing; doc/matching.md, "A twelfth
# round"). A low-poly box holding more joints' bones than it has rings to bend at moves with one
# joint, the one pivoting in it where its bones split in half: without, the cat's and the wolf's
# limits after the matcher fail (.846/.865, .750/.909: the cat's leg boxes, blended between the
# hips and four leg bones, sheared into wedges). The joints such a box leaves bending nothing
# are dropped, its joint given their reach as its bone's tip: the cat's and the wolf's CD-J2J
# limits fail with them kept (0.087, 0.062)
"$rigflow" rig-bench -r general "$data/models/Fox.glb" "$data/models/RiggedFigure.glb" \
    "$data/models/Testwuson.X" "$data/models/creatures/animalia_wolf.b3d" \
    "$data/models/Wizard.glb" "$data/models/creatures/animalia_owl.b3d" \
    "$data/models/creatures/animalia_bird.b3d" "$data/models/creatures/animalia_fox.b3d" \
    "$data/models/creatures/animalia_cat.b3d" >"$tmp/bench.csv" 2>"$tmp/err" ||
    ko "rig-bench exit $?"
cat "$tmp/bench.csv"
rows=$(tail -n +2 "$tmp/bench.csv" | wc -l)
[ "$rows" -eq 9 ] && ok || ko "rig-bench: $rows rows, expected 9"
# columns by their header names; the status is quoted text and may hold commas. Limits:
# what the rigger reaches (in the comments: CD-J2J, skinning P / R after the matcher, P / R / L1
# on the skeleton of the artist) with room for another machine's rounding
awk -F, 'function limits(m, cd, p, r, gp, gr, gl) {
                 cdmax[m] = cd; pmin[m] = p; rmin[m] = r; gpmin[m] = gp; grmin[m] = gr; glmax[m] = gl }
    BEGIN {
        limits("\"Fox.glb\"", 0.045, 0.75, 0.76, 0.80, 0.82, 0.50)         # 0.040 .764/.771 .86/.87/.45
        # RiggedFigure: legs laid from where the trunk closes over them (.837/.590 before); its
        # ankle no longer moved up with the raised hips, 0.115 -> 0.026 of the longest edge (the
        # artist ankle 0.059): CD-J2J 0.029 -> 0.027, the CMU walk ground error 0.131 -> 0.022 leg
        # and stretch p99 50.3 -> 33.8, skinning after the matcher .892/.673 -> .833/.609
        limits("\"RiggedFigure.glb\"", 0.0285, 0.82, 0.60, 0.88, 0.78, 0.32) # 0.027 .833/.609 .95/.84/.27
        limits("\"Testwuson.X\"", 0.047, 0.57, 0.57, 0.74, 0.78, 0.53)      # 0.043 .578/.580 .79/.83/.50
        limits("\"animalia_wolf.b3d\"", 0.061, 0.80, 0.90, 0.88, 0.88, 0.24) # 0.059 .83/.93 .909/.909/.182
        limits("\"Wizard.glb\"", 0.066, 0.60, 0.60, 0.68, 0.72, 0.60)       # 0.060 .67/.66 .72/.78/.56
        # the owl and the bird: the elbow and wrist of each wing where wings have them (the hand in
        # the outer wing before: 0.082 and 0.049, after the matcher .880/.926 and .855/.876)
        limits("\"animalia_owl.b3d\"", 0.080, 0.80, 0.85, 0.825, 0.90, 0.315) # 0.074 .869/.880 .836/.948/.295
        limits("\"animalia_bird.b3d\"", 0.048, 0.77, 0.80, 0.78, 0.80, 0.42) # 0.044 .796/.828 .802/.844/.378
        limits("\"animalia_fox.b3d\"", 0.085, 0.80, 0.83, 0.65, 0.70, 0.72)  # 0.077 .85/.86 .665/.717/.693
        limits("\"animalia_cat.b3d\"", 0.086, 0.92, 0.93, 0.88, 0.88, 0.20)  # 0.084 .95/.96 .92/.92/.15
    }
    NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    {
        m = $col["model"]
        if (!(m in cdmax)) { print "FAIL: " m ": no limits"; next }
        if (!($col["cd_j2j"] < cdmax[m])) print "FAIL: " m ": cd_j2j " $col["cd_j2j"] " >= " cdmax[m]
        if (!($col["precision"] >= pmin[m] && $col["recall"] >= rmin[m]))
            print "FAIL: " m ": skinning after the matcher " $col["precision"] " / " $col["recall"]
        if (!($col["given_precision"] >= gpmin[m] && $col["given_recall"] >= grmin[m] &&
              $col["given_l1"] <= glmax[m]))
            print "FAIL: " m ": skinning on the skeleton of the artist " $col["given_precision"] \
                " / " $col["given_recall"] " / L1 " $col["given_l1"]
        if (!($col["up_agree"] > 0.9 && $col["forward_agree"] > 0.9))
            print "FAIL: " m ": read another way up or facing: " $col["up_agree"] " / " \
                $col["forward_agree"]
        if ($col["unweighted"] != 0) print "FAIL: " m ": " $col["unweighted"] " vertices without weights"
        if ($col["status"] != "\"ok\"") print "FAIL: " m ": " $col["status"]
    }' "$tmp/bench.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench thresholds"; else ok; fi
# --joint-map skin: each rigger joint stands for the artist joint whose weights overlap its own
# most, the artist's skin read back; on the Wizard and RiggedFigure it reaches more than the
# matcher (93% / 91% and 89% / 67% against 69% / 67% and 84% / 59%; the Fox's 79% / 77% is
# within 3 points of the matcher's 76% / 77% since its trunk is placed along the artist's): a
# mapping that read the overlap wrong (a joint's least overlap, or the artist's first joint for
# every one) falls below it. --joints gives each rigger joint the artist joint the skinning
# columns count it as (`mapped`), the one its skin overlaps most (`skin_mapped`) and its weight:
# under --joint-map skin the two are the same joint on every weighted row, and the weights of a
# model's rows sum to its vertex count (5413 and 370, as `rigflow inspect` counts them; every
# vertex's weights sum to 1)
"$rigflow" rig-bench -r general --joint-map skin --joints "$tmp/kjoints.csv" \
    "$data/models/Wizard.glb" "$data/models/RiggedFigure.glb" >"$tmp/kbench.csv" 2>"$tmp/err" ||
    ko "rig-bench skin exit $?"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["rig"] == "rigger" { w[$c["model"]] += $c["weight"]
        if ($c["weight"] > 0 && ($c["mapped"] == "\"\"" || $c["mapped"] != $c["skin_mapped"]))
            print "FAIL: " $c["model"] " " $c["joint"] ": mapped " $c["mapped"] ", skin " $c["skin_mapped"] }
    $c["rig"] == "artist" && $c["mapped"] != "\"\"" { print "FAIL: artist row mapped: " $0 }
    END { want["\"Wizard.glb\""] = 5413; want["\"RiggedFigure.glb\""] = 370
          for (m in want) if (!(w[m] > want[m] - 0.5 && w[m] < want[m] + 0.5))
              print "FAIL: " m ": weights sum to " w[m] ", expected " want[m] }' \
    "$tmp/kjoints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench --joints mapped columns"; else ok; fi
awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    NR == FNR { p[$c["model"]] = $c["precision"]; r[$c["model"]] = $c["recall"]; next }
    { n++; m = $c["model"]
      if (!($c["precision"] > p[m] + 0.03 && $c["recall"] > r[m] + 0.03))
          print "FAIL: " m ": --joint-map skin " $c["precision"] " / " $c["recall"] \
              ", the matcher " p[m] " / " r[m] }
    END { if (n != 2) print "FAIL: --joint-map skin: " n " rows, expected 2" }' \
    "$tmp/bench.csv" "$tmp/kbench.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench --joint-map skin"; else ok; fi
if "$rigflow" rig-bench --joint-map best "$data/models/Fox.glb" >/dev/null 2>"$tmp/err"; then
    ko "rig-bench --joint-map best: accepted"
elif [ $? -eq 2 ] && grep -q "expected matcher, nearest or skin" "$tmp/err"; then ok
else ko "rig-bench --joint-map best: $(cat "$tmp/err")"; fi
# short thick limbs are limbs, not bumps (a branch's thickness is its outer half's): the animalia
# bull frog keeps its left hind leg (the artist's Foot.L 0.095 from the nearest rigger joint, 0.51
# with the whole chain's mean thickness; CD-J2J 0.158, 0.191) and huesitos its arm (CD-J2J 0.058,
# 0.090); the frog is read facing 0.74 (a quarter turn and more off before), so no facing check.
# A hand on a hip is a contact, not tissue: BCN_Epileptic's arms reached through its shoulders
# (CD-J2J 0.0446, skinning after the matcher precision 24%; with the volume's loop through the
# hand 0.0480, 11%); its neck and head, three voxels off the mirror plane, are moved onto it and
# read as a head, not an unpaired arm (CD-J2J 0.0435, after the matcher 40% / 47%; 25% / 25%
# left off the plane); its head, one loose part holding the bones of the neck, jaw, lips, eyes and
# ponytail, bends with them on the skeleton of the artist (.740/.780/.646; .731/.744/.671 with
# the head moved by the neck alone), its face joints fanning from the neck keeping bone heat's
# sharpened rows (.719/.807/.651 with the plain rows a chain of joints in a loose part takes). The fire dragon's wing membranes, whose corners at the wrist
# (where the forearm's bone ends and four fingers' start) its artist gave to the forearm, take
# the forearm's heat there, not two fingers' (.694/.719/.601 on the skeleton of the artist;
# .675/.719/.634 with the two first in the sort). Its short box legs, under a thick body and a
# wingspan that sets the bone length, are legs the body stands on, not bumps (rf_rig_stands_on),
# and the limbs are read with the declared up: read up and facing as its artist rig is, its
# artist's Foot.L 0.011 from a rigger joint, CD-J2J 0.051, precision after the matcher 33%
# (without: legs pruned, wings read as legs, up and facing a quarter turn off, 0.131, 0.074, 8%).
# Mirrored twigs are pruned as pairs, the frog's
# second pass grown from its mirror plane (its thickest point lies off to one side of its box
# body): every joint of its rig lies within 0.05 of another's mirror image across x = 0 (the
# plane of the artist's Torso, Head and Jaw; 0.018 reached, 0.235 with one eye and one
# forefoot's corners kept), CD-J2J 0.127 (0.159). Greenman's blob body gets a joint at its
# bottom, where its artist puts one: CD-J2J 0.096 (0.122 when the skeleton stopped in the
# body's middle). Huesitos, a bent tube standing on one free end, is rooted at that end, its
# lowest joint, as its artist roots it (0.003 of the longest edge above the artist's lowest
# joint); rooted at its fork, its stem hung down as an appendage and took the artist's upper
# branch: skinning precision after the matcher 57% (29%); 69% since the analysis's root chain
# stops where nothing under it reaches the ground (doc/matching.md, the tenth round). Greenman's
# curve skeleton, whose left arm leaves the chest by a detour up the body, is read with a pair of
# arms, its root as body and its chest taking the artist's head: after the matcher 55% / 52%
# (35% / 15% with no sides read and the root a placement helper). The legs of BCN_Epileptic's and
# the ninja's curve skeletons start at the knee, with no offset at either socket, and the ninja's
# arms, lying against its body, at an offset by the elbow: the matcher counts their bones from the
# artist's shin and forearm (doc/matching.md, "An eleventh round"), after the matcher 43.8% /
# 50.4% and 35.8% / 47.4% (40.1% / 46.8% and 29.3% / 38.4% counted from the thigh and upper arm,
# the ninja 33.1% / 42.8% with its legs alone counted from the shin). With BCN_Epileptic's arms
# laid from the shoulder the trunk's width finds (joint placement round nine) it reads 42.7% /
# 47.9%, 46.6% / 50.7% with its root, in the crotch, given the artist's B_LowerPelvis, the
# reverse spine below its pelvis root, and 48.0% / 51.9% with its spine's other joints placed
# along the artist's forward spine (doc/matching.md, "A twelfth round"): its bar is that, less
# most of a point.
# A match to an artist joint that carries no skin gives way to the joint holding the skin there
# (doc/matching.md, "A thirteenth round"): RobotExpressive's trunk took its unweighted Body and
# Torso and its chest's skin was counted as the Head's, 62.7% / 66.0% / 0.77 after the matcher
# (78.5% / 80.5% / 0.44 now); huesitos 68.5% / 63.8% (74.7% / 70.1%).
# A biped's hips go no lower than 0.58 of its shoulders' height over its feet (doc/autorig.md,
# "What the rigger does"): the ninja's hakama closes 0.35 of its height up, and its hips were laid
# there, 0.65 of the artist's hip height (Joint18, Joint23); now 0.88, after the matcher 41.8% /
# 54.3% -> 49.0% / 63.5%; BCN_Epileptic, its ankle no longer moved up with the raised hips,
# CD-J2J 0.038 -> 0.035, 50.7% / 55.9% -> 52.2% / 57.4%. The bull frog's hind legs hung from
# a stalk its curve skeleton ran down inside its body; they hang from the spine joint above it
# now (rf_rig_stalks_cut): after the matcher 67.6% / 75.9% -> 71.6% / 81.6%; and its hind pair
# is the one behind along its forward (the analysis's places along the body, counted from its
# root at the front girdle, gave the forelegs the hind layout): 73.6% / 84.6%.
"$rigflow" rig-bench -r general --joints "$tmp/sjoints.csv" \
    "$data/models/creatures/animalia_bull_frog.b3d" "$data/models/huesitos.fbx" \
    "$data/models/BCN_Epileptic.X" "$data/models/creatures/draconis_fire_dragon.b3d" \
    "$data/models/greenman.glb" "$data/models/ogre/ninja.mesh" \
    "$data/models/RobotExpressive.glb" >"$tmp/sbench.csv" 2>"$tmp/err" ||
    ko "rig-bench short limbs exit $?"
cat "$tmp/sbench.csv"
awk -F, 'NR == FNR { if (FNR == 1) for (i = 1; i <= NF; i++) c[$i] = i
                     else { n++; cd[$c["model"]] = $c["cd_j2j"]; p[$c["model"]] = $c["precision"]
                            r[$c["model"]] = $c["recall"]; l1[$c["model"]] = $c["l1"]
                            gp[$c["model"]] = $c["given_precision"]
                            gr[$c["model"]] = $c["given_recall"]; gl[$c["model"]] = $c["given_l1"]
                            ua[$c["model"]] = $c["up_agree"]; fa[$c["model"]] = $c["forward_agree"]
                            uw += $c["unweighted"] }; next }
    FNR == 1 { for (i = 1; i <= NF; i++) j[$i] = i; next }
    $j["rig"] == "artist" && $j["joint"] == "\"Foot.L\"" { foot[$j["model"]] = $j["distance"] }
    $j["model"] == "\"huesitos.fbx\"" && $j["rig"] == "rigger" && !hroot++ { hy = $j["y"] }
    $j["model"] == "\"huesitos.fbx\"" && (ylow[$j["rig"]] == "" || $j["y"] < ylow[$j["rig"]]) {
        ylow[$j["rig"]] = $j["y"] }
    $j["model"] == "\"ninja.mesh\"" && $j["rig"] == "rigger" && $j["joint"] ~ /^"leg_[lr]0_0"$/ {
        nh += $j["y"]; nhn++ }
    $j["model"] == "\"ninja.mesh\"" && $j["rig"] == "artist" &&
        ($j["joint"] == "\"Joint18\"" || $j["joint"] == "\"Joint23\"") { ah += $j["y"]; ahn++ }
    $j["rig"] == "rigger" && $j["model"] == "\"animalia_bull_frog.b3d\"" {
        fn++; fx[fn] = $j["x"]; fy[fn] = $j["y"]; fz[fn] = $j["z"]; fname[fn] = $j["joint"] }
    END {
        if (n != 7) print "FAIL: short limbs: " n " rows, expected 7"
        dragon = "\"draconis_fire_dragon.b3d\""
        if (!(gp[dragon] >= 0.685 && gl[dragon] <= 0.615))
            print "FAIL: fire dragon on the skeleton of the artist: precision " gp[dragon] ", L1 " gl[dragon]
        if (!(ua[dragon] > 0.9 && fa[dragon] > 0.9 && cd[dragon] < 0.056 && p[dragon] >= 0.28 &&
              foot[dragon] != "" && foot[dragon] < 0.03))
            print "FAIL: fire dragon: up " ua[dragon] ", forward " fa[dragon] ", cd_j2j " cd[dragon] \
                ", precision " p[dragon] ", Foot.L " foot[dragon] " from the nearest joint"
        if (!(cd["\"BCN_Epileptic.X\""] < 0.0365 && p["\"BCN_Epileptic.X\""] >= 0.512 &&
              r["\"BCN_Epileptic.X\""] >= 0.564))
            print "FAIL: BCN_Epileptic cd_j2j " cd["\"BCN_Epileptic.X\""] ", precision " \
                p["\"BCN_Epileptic.X\""] ", recall " r["\"BCN_Epileptic.X\""]
        if (!(gp["\"BCN_Epileptic.X\""] >= 0.73 && gr["\"BCN_Epileptic.X\""] >= 0.765 &&
              gl["\"BCN_Epileptic.X\""] <= 0.66))
            print "FAIL: BCN_Epileptic on the skeleton of the artist: precision " \
                gp["\"BCN_Epileptic.X\""] ", recall " gr["\"BCN_Epileptic.X\""] ", L1 " gl["\"BCN_Epileptic.X\""]
        if (!(cd["\"animalia_bull_frog.b3d\""] < 0.14)) print "FAIL: bull frog cd_j2j " cd["\"animalia_bull_frog.b3d\""]
        if (!(p["\"animalia_bull_frog.b3d\""] >= 0.725 && r["\"animalia_bull_frog.b3d\""] >= 0.83))
            print "FAIL: bull frog after the matcher: precision " p["\"animalia_bull_frog.b3d\""] \
                ", recall " r["\"animalia_bull_frog.b3d\""]
        if (!(cd["\"huesitos.fbx\""] < 0.065)) print "FAIL: huesitos cd_j2j " cd["\"huesitos.fbx\""]
        if (!(p["\"huesitos.fbx\""] >= 0.73 && r["\"huesitos.fbx\""] >= 0.69))
            print "FAIL: huesitos precision " p["\"huesitos.fbx\""] ", recall " r["\"huesitos.fbx\""]
        robot = "\"RobotExpressive.glb\""
        if (!(p[robot] >= 0.77 && r[robot] >= 0.79 && l1[robot] <= 0.46))
            print "FAIL: RobotExpressive after the matcher: " p[robot] " / " r[robot] " / " l1[robot]
        if (!(p["\"greenman.glb\""] >= 0.5 && r["\"greenman.glb\""] >= 0.45))
            print "FAIL: greenman after the matcher: precision " p["\"greenman.glb\""] ", recall " r["\"greenman.glb\""]
        if (!(hy != "" && hy == ylow["rigger"] && hy - ylow["artist"] < 0.02))
            print "FAIL: huesitos: its root at y " hy ", its lowest joint " ylow["rigger"] \
                ", the artist rig lowest " ylow["artist"]
        if (!(cd["\"greenman.glb\""] < 0.105)) print "FAIL: greenman cd_j2j " cd["\"greenman.glb\""]
        if (!(nhn == 2 && ahn == 2 && nh / 2 >= 0.8 * ah / 2))
            print "FAIL: ninja: hips at y " nh / 2 " (" nhn " legs), the artist hips at " ah / 2
        if (!(p["\"ninja.mesh\""] >= 0.47 && r["\"ninja.mesh\""] >= 0.61))
            print "FAIL: ninja after the matcher: precision " p["\"ninja.mesh\""] ", recall " r["\"ninja.mesh\""]
        frog = "\"animalia_bull_frog.b3d\""
        if (!(foot[frog] != "" && foot[frog] < 0.15))
            print "FAIL: bull frog: Foot.L " foot[frog] " from the nearest joint"
        if (uw) print "FAIL: short limbs: " uw " vertices without weights"
        if (!fn) print "FAIL: bull frog: no rigger joints in --joints"
        for (a = 1; a <= fn; a++) {
            best = 1e9
            for (b = 1; b <= fn; b++) {
                d = (fx[a] + fx[b]) ^ 2 + (fy[a] - fy[b]) ^ 2 + (fz[a] - fz[b]) ^ 2
                best = d < best ? d : best
            }
            if (best > 0.05 ^ 2) print "FAIL: bull frog: " fname[a] " " sqrt(best) " from any mirror image"
        }
    }' "$tmp/sbench.csv" "$tmp/sjoints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench short limbs"; else ok; fi
# Huesitos as a scan gives it (no axes): its frame then follows its own axis, 22.5 degrees from
# the file's, and its curve skeleton roots at the top of its stem, above the fork; the one low
# end is taken as the root when the root stands a quarter of the height above the fork too
# (rf_rig_free_end), as the artist roots it: at the stem's last joint, 0.048 of the longest edge
# up (0.70 before). After the matcher 15.1% / 13.8% -> 56.6% / 58.3%.
"$rigflow" rig-bench -r general --no-axes --joints "$tmp/hjoints.csv" "$data/models/huesitos.fbx" \
    >"$tmp/hbench.csv" 2>"$tmp/err" || ko "rig-bench --no-axes huesitos exit $?"
awk -F, 'NR == FNR { if (FNR == 1) for (i = 1; i <= NF; i++) c[$i] = i
                     else { p = $c["precision"]; r = $c["recall"] }; next }
    FNR == 1 { for (i = 1; i <= NF; i++) j[$i] = i; next }
    $j["rig"] == "rigger" && !n++ { root = $j["y"] }
    low[$j["rig"]] == "" || $j["y"] < low[$j["rig"]] { low[$j["rig"]] = $j["y"] }
    END {
        if (!(root != "" && root == low["rigger"] && root - low["artist"] < 0.06))
            print "FAIL: huesitos, no axes: its root at y " root ", its lowest joint " \
                low["rigger"] ", the artist rig lowest " low["artist"]
        if (!(p >= 0.55 && r >= 0.55))
            print "FAIL: huesitos, no axes, after the matcher: " p " / " r
    }' "$tmp/hbench.csv" "$tmp/hjoints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench --no-axes huesitos"; else ok; fi
# Which pair of a four-legged body's legs is hind is read from where their girdles lie along its
# facing: the forward the file declares, or for a scan the facing the rigger reads from its
# skeletons on the grid turned every quarter way (rf_rig_pooled_facing). The Fox with no axes
# is rooted at its shoulders, and the girdle nearer the root, taken as hind before, gave each
# pair the other's layout: after the matcher 68.5% / 70.4% with no axes against 76.4% / 77.1%
# with its file's; now 76.4% / 77.1% both ways.
"$rigflow" rig-bench -r general --no-axes "$data/models/Fox.glb" >"$tmp/fbench.csv" 2>"$tmp/err" ||
    ko "rig-bench --no-axes Fox exit $?"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { n++; p = $c["precision"]; r = $c["recall"] }
    END { if (!(n == 1 && p >= 0.74 && r >= 0.74)) print "FAIL: Fox, no axes, after the matcher: " p " / " r }' \
    "$tmp/fbench.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench --no-axes Fox"; else ok; fi
# A hand holding a prop: the Wizard's staff and the ninja's sword run on from the right hand's
# curve, which reached 1.75 and 1.93 times as far as the left's, and laid along the whole curve
# the right arm's last joint went into the prop and its elbow to the wrist. Laid only as far as
# the left arm reaches, the right arm mirrors the left: the Wizard's artist LowerArm.R (at x
# -0.231, its LowerArm.L at +0.231) within 0.06 of a rigger joint (0.042 reached, 0.103 before),
# none of the rigger's arm joints farther than 0.1 from an artist joint (0.069; 0.238 before, in
# the staff), and no joint of the ninja's farther than 0.15 from one (0.118, a knee under its
# wide trousers; 0.266 before, in the sword). Skinning after the matcher: the Wizard 52.4%, the
# ninja 32.0% (49.9% and 29.3% before). The Wizard's legs, raised to its hips under the robe,
# keep a knee found at a bend of the curve as found: its right knee had fallen out of the knee's
# range on the raised curve and gone to the layout's place, above the robe's leg part, which
# then moved whole with the shin, and the ankle and toe, moving nothing, were dropped: the legs
# have as many joints each (4 and 4; 4 and 2 before) and the artist's Foot.R lies within 0.07 of
# a rigger joint (0.053; 0.160 before, the left foot's joint the nearest).
"$rigflow" rig-bench -r general --joints "$tmp/pjoints.csv" "$data/models/Wizard.glb" \
    "$data/models/ogre/ninja.mesh" >"$tmp/pbench.csv" 2>"$tmp/err" || ko "rig-bench props exit $?"
awk -F, 'NR == FNR { if (FNR == 1) for (i = 1; i <= NF; i++) c[$i] = i
                     else { n++; p[$c["model"]] = $c["precision"] }; next }
    FNR == 1 { for (i = 1; i <= NF; i++) j[$i] = i; next }
    $j["rig"] == "artist" && $j["joint"] == "\"LowerArm.R\"" { elbow = $j["distance"] }
    $j["rig"] == "rigger" && $j["model"] == "\"Wizard.glb\"" && $j["joint"] ~ /^"arm_/ &&
        $j["distance"] > warm { warm = $j["distance"] }
    $j["rig"] == "rigger" && $j["model"] == "\"ninja.mesh\"" && $j["distance"] > nall {
        nall = $j["distance"] }
    $j["rig"] == "rigger" && $j["model"] == "\"Wizard.glb\"" && $j["joint"] ~ /^"leg_[lr]0_/ {
        legs[substr($j["joint"], 6, 1)]++ }
    $j["rig"] == "artist" && $j["joint"] == "\"Foot.R\"" { wfoot = $j["distance"] }
    END {
        if (n != 2) print "FAIL: props: " n " rows, expected 2"
        if (!(legs["l"] == 4 && legs["r"] == 4))
            print "FAIL: Wizard: legs of " legs["l"] " and " legs["r"] " joints"
        if (!(wfoot != "" && wfoot < 0.07)) print "FAIL: Wizard: Foot.R " wfoot " from any joint"
        if (!(elbow != "" && elbow < 0.06)) print "FAIL: Wizard: LowerArm.R " elbow " from any joint"
        if (!(warm != "" && warm < 0.1)) print "FAIL: Wizard: an arm joint " warm " from the artist rig"
        if (!(nall != "" && nall < 0.15)) print "FAIL: ninja: a joint " nall " from the artist rig"
        if (!(p["\"Wizard.glb\""] >= 0.51)) print "FAIL: Wizard precision " p["\"Wizard.glb\""]
        if (!(p["\"ninja.mesh\""] >= 0.31)) print "FAIL: ninja precision " p["\"ninja.mesh\""]
    }' "$tmp/pbench.csv" "$tmp/pjoints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench props"; else ok; fi
# Arms hanging beside the trunk leave it below the armpit, where the bands first part arm from
# chest, 0.11 (BCN_Epileptic) and 0.21 (the ninja) of the longest edge under the artist's
# shoulder, and the layout put clavicle and upper arm there; the trunk's width by rays (the
# arms joining it above the armpit, the neck above the shoulders) puts the upper arm joint at
# the shoulder: BCN_Epileptic's artist B_UpperArm_Left and _Right within 0.03 of a rigger joint
# (0.014 and 0.015 reached, 0.115 before), the ninja's Joint10 and Joint15 within 0.09 (0.069,
# 0.063; 0.122, 0.125 before), precision after the matcher at least 41.5% and 39% (42.7% and
# 40.1% reached; 40.1% and 32.0% before). The arms then hang from a trunk joint at their
# clavicles' height, not from the joint under the armpit where the curve left them: a chest
# joint on the trunk bone there (BCN_Epileptic's artist B_Spine4, under its clavicles, within
# 0.04 of a rigger joint: 0.023; 0.064 before), or the bone's upper joint when the clavicles
# stand past it (the ninja's arms hang from a joint 0.040 of its height under them; 0.175
# before, rig-dump). Arms 37 degrees under level hang too: the girl's artist UpperArm.L and .R
# within 0.045 of a rigger joint (0.021 and 0.022 reached; 0.081 and 0.094 when only arms
# steeper than 45 degrees were asked), her LowerArm.L and .R within 0.045 (0.024, 0.023; 0.072,
# 0.067), the elbow laid halfway on from the shoulder found. Legs laid again from a raised start
# take no knee at the bend where that start meets the curve: BCN_Epileptic's artist B_Knee_Left
# and _Right within 0.03 of a rigger joint (0.020 and 0.010 reached; 0.075 and 0.047 before,
# the knees a fifth of the way down the leg).
"$rigflow" rig-bench -r general --joints "$tmp/hjoints.csv" "$data/models/BCN_Epileptic.X" \
    "$data/models/ogre/ninja.mesh" "$data/models/girl.glb" >"$tmp/hbench.csv" 2>"$tmp/err" ||
    ko "rig-bench hanging arms exit $?"
awk -F, 'NR == FNR { if (FNR == 1) for (i = 1; i <= NF; i++) c[$i] = i
                     else { n++; p[$c["model"]] = $c["precision"] }; next }
    FNR == 1 { for (i = 1; i <= NF; i++) j[$i] = i; next }
    $j["rig"] == "artist" { d[$j["model"] " " $j["joint"]] = $j["distance"] }
    END {
        if (n != 3) print "FAIL: hanging arms: " n " rows, expected 3"
        split("\"B_UpperArm_Left\" \"B_UpperArm_Right\" \"B_Knee_Left\" \"B_Knee_Right\"", bcn, " ")
        for (i in bcn) {
            k = "\"BCN_Epileptic.X\" " bcn[i]
            if (!(d[k] != "" && d[k] < 0.03)) print "FAIL: BCN_Epileptic: " bcn[i] " " d[k] " from any joint"
        }
        split("\"Joint10\" \"Joint15\"", nin, " ")
        for (i in nin) {
            k = "\"ninja.mesh\" " nin[i]
            if (!(d[k] != "" && d[k] < 0.09)) print "FAIL: ninja: " nin[i] " " d[k] " from any joint"
        }
        split("\"UpperArm.L\" \"UpperArm.R\" \"LowerArm.L\" \"LowerArm.R\"", girl, " ")
        for (i in girl) {
            k = "\"girl.glb\" " girl[i]
            if (!(d[k] != "" && d[k] < 0.045)) print "FAIL: girl: " girl[i] " " d[k] " from any joint"
        }
        k = "\"BCN_Epileptic.X\" \"B_Spine4\""
        if (!(d[k] != "" && d[k] < 0.04)) print "FAIL: BCN_Epileptic: B_Spine4 " d[k] " from any joint"
        if (!(p["\"BCN_Epileptic.X\""] >= 0.415)) print "FAIL: BCN_Epileptic precision " p["\"BCN_Epileptic.X\""]
        if (!(p["\"ninja.mesh\""] >= 0.39)) print "FAIL: ninja precision " p["\"ninja.mesh\""]
    }' "$tmp/hbench.csv" "$tmp/hjoints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench hanging arms"; else ok; fi
"${RF_BUILDDIR:-.}/tests/rig/rig-dump" "$data/models/ogre/ninja.mesh" >"$tmp/ninja.dump" \
    2>"$tmp/err" || ko "rig-dump ninja exit $?"
awk '$1 == "V" { if (lo == "" || $3 < lo) lo = $3; if (hi == "" || $3 > hi) hi = $3 }
    $1 == "J" { y[$2] = $5; up[$2] = $3; if ($7 ~ /^arm_[lr]0_0$/) arm[++na] = $2 }
    END {
        if (na != 2 || !(hi > lo)) { print "FAIL: ninja dump: " na " arms"; exit }
        for (a = 1; a <= na; a++) {
            gap = (y[arm[a]] - y[up[arm[a]]]) / (hi - lo)
            if (!(gap < 0.06)) print "FAIL: ninja: an arm hangs from a joint " gap " under it"
        }
    }' "$tmp/ninja.dump" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "ninja arms hung"; else ok; fi
# Wings' bones run along the leading edge, the membrane or feathers trailing behind them; the
# curve skeleton of a flat wing runs mid-chord. Laid towards the leading edge, the wing joints
# past the clavicle meet the artists': the owl's Wing.2.L and .R within 0.045 of a rigger joint
# (0.040 reached, 0.080 before), the animalia bird's LowerWing.L and .R within 0.07 (0.056;
# 0.055), the fire dragon's LowerArm.L and .R within 0.036 (0.019; 0.042) and Finger.1.L and .R
# within 0.07 (0.055; 0.112); the dragon's precision after the matcher at least 37% (38.5%
# reached, 35.8% before). The bat's wings are sheets of no thickness, whose rays along them meet
# nothing: their reach is walked in the sheet, its Wing.Lower.L and .R within 0.06 (0.034;
# 0.121). A wing's elbow and wrist are laid where wings have them (0.22 and 0.43 of the way out),
# not at an arm's fractions: every rigger joint of the four wings within 0.08 of an artist joint
# (0.058 at most; 0.17 to 0.27, the hand in the outer wing, with an arm's).
"$rigflow" rig-bench -r general --joints "$tmp/wjoints.csv" \
    "$data/models/creatures/animalia_owl.b3d" "$data/models/creatures/animalia_bird.b3d" \
    "$data/models/creatures/draconis_fire_dragon.b3d" "$data/models/creatures/animalia_bat.b3d" \
    >"$tmp/wbench.csv" 2>"$tmp/err" ||
    ko "rig-bench wings exit $?"
awk -F, 'NR == FNR { if (FNR == 1) for (i = 1; i <= NF; i++) c[$i] = i
                     else { n++; p[$c["model"]] = $c["precision"] }; next }
    FNR == 1 { for (i = 1; i <= NF; i++) j[$i] = i; next }
    $j["rig"] == "artist" { d[$j["model"] " " $j["joint"]] = $j["distance"] }
    $j["rig"] == "rigger" && $j["joint"] ~ /^"arm_/ && !($j["distance"] < 0.08) {
        print "FAIL: wings: " $j["model"] " " $j["joint"] " " $j["distance"] " from any artist joint"
    }
    END {
        if (n != 4) print "FAIL: wings: " n " rows, expected 4"
        lim["\"animalia_owl.b3d\" \"Wing.2.L\""] = 0.045
        lim["\"animalia_owl.b3d\" \"Wing.2.R\""] = 0.045
        lim["\"animalia_bird.b3d\" \"LowerWing.L\""] = 0.07
        lim["\"animalia_bird.b3d\" \"LowerWing.R\""] = 0.07
        lim["\"draconis_fire_dragon.b3d\" \"LowerArm.L\""] = 0.036
        lim["\"draconis_fire_dragon.b3d\" \"LowerArm.R\""] = 0.036
        lim["\"draconis_fire_dragon.b3d\" \"Finger.1.L\""] = 0.07
        lim["\"draconis_fire_dragon.b3d\" \"Finger.1.R\""] = 0.07
        lim["\"animalia_bat.b3d\" \"Wing.Lower.L\""] = 0.06
        lim["\"animalia_bat.b3d\" \"Wing.Lower.R\""] = 0.06
        for (k in lim)
            if (!(d[k] != "" && d[k] < lim[k])) print "FAIL: wings: " k " " d[k] " from any joint"
        k = "\"draconis_fire_dragon.b3d\""
        if (!(p[k] >= 0.37)) print "FAIL: fire dragon precision " p[k]
    }' "$tmp/wbench.csv" "$tmp/wjoints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench wings"; else ok; fi
# the template rigger on seven bodies (doc/autorig.md): limits a little beyond what it reaches (in
# the comments: CD-J2J, skinning P / R after the matcher); the CD-J2J limits fail if the joints
# go back to where the layouts before their fit to artist rigs put them (0.0296, 0.039, 0.051,
# 0.078). Testwuson's skinning after the matcher has two readings for joints a few thousandths
# apart (42% / 60% and 22% / 28% at CD-J2J 0.040: doc/autorig-log.md, "The template's layouts
# fitted to the artist rigs"): its floor only guards against a rig the matcher cannot read at
# all, so another machine's rounding cannot fail it. The animalia
# bird's limits need its head looked for as the highest leaf beyond the wings, not the farthest
# (its tail, which took the template's neck and head: 0.053, 29% / 29%), and the owl's and the
# bird's their legs' length from the skin (.75/.77 and .47/.51 with it guessed). RobotExpressive's
# need its arms laid from the trunk at their shoulders' height, not from the curve skeleton's
# girdle a third of the trunk lower (0.0478, .60/.63 without; 0.0496, .57/.64 with its Head in
# the middle of the head box too). The Wizard's, the ninja's and BCN_Epileptic's need the general
# rigger's limb rules: an arm reaching far past its twin (a staff, a sword) laid only as far as
# the twin (Wizard 0.0487, ninja 0.0560 .31/.39 without), and an arm hanging beside the trunk
# given its shoulder where the trunk's width says (ninja 0.0493 .33/.46, BCN_Epileptic 0.0503
# without)
"$rigflow" rig-bench -r template --joints "$tmp/joints.csv" "$data/models/Fox.glb" \
    "$data/models/RiggedFigure.glb" "$data/models/Testwuson.X" \
    "$data/models/creatures/animalia_wolf.b3d" "$data/models/creatures/animalia_owl.b3d" \
    "$data/models/creatures/animalia_bird.b3d" "$data/models/RobotExpressive.glb" \
    "$data/models/Wizard.glb" "$data/models/ogre/ninja.mesh" "$data/models/BCN_Epileptic.X" \
    >"$tmp/tbench.csv" 2>"$tmp/err" ||
    ko "rig-bench -r template exit $?"
cat "$tmp/tbench.csv"
# --joints: per model, the mean distance of the rigger's joints and of the artist's to the other
# rig's nearest joint, halved, is CD-J2J as the bench printed it (the same chamfer, summed back
# from its parts); every template joint is there
awk -F, 'NR == FNR { if (FNR == 1) for (i = 1; i <= NF; i++) c[$i] = i
                     else cd[$c["model"]] = $c["cd_j2j"]; next }
    FNR == 1 { for (i = 1; i <= NF; i++) j[$i] = i; next }
    { s[$j["model"], $j["rig"]] += $j["distance"]; n[$j["model"], $j["rig"]]++
      if ($j["rig"] == "rigger" && $j["joint"] == "\"LeftUpLeg\"") legs++ }
    END {
        for (m in cd) {
            if (!n[m, "rigger"] || !n[m, "artist"]) { print "FAIL: --joints: no rows for " m; continue }
            got = 0.5 * (s[m, "rigger"] / n[m, "rigger"] + s[m, "artist"] / n[m, "artist"])
            if (got - cd[m] > 0.0002 || cd[m] - got > 0.0002)
                print "FAIL: --joints: " m " gives CD-J2J " got ", the bench " cd[m]
        }
        if (legs != 10) print "FAIL: --joints: " legs " LeftUpLeg rows, expected 10"
    }' "$tmp/tbench.csv" "$tmp/joints.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench --joints"; else ok; fi
awk -F, 'function limits(m, cd, p, r) { cdmax[m] = cd; pmin[m] = p; rmin[m] = r }
    BEGIN {
        limits("\"Fox.glb\"", 0.037, 0.68, 0.68)                # 0.034 .74/.73
        limits("\"RiggedFigure.glb\"", 0.0292, 0.76, 0.53)      # 0.0265 .79/.55 (.85/.62 before the
        # head at the base of its bulk, the arms from the chest and the front rule together)
        limits("\"Testwuson.X\"", 0.041, 0.18, 0.24)            # 0.038 .57/.56 (below)
        limits("\"animalia_wolf.b3d\"", 0.063, 0.68, 0.74)      # 0.059 .75/.80
        limits("\"animalia_owl.b3d\"", 0.076, 0.80, 0.84)       # 0.072 .85/.89 (.37/.39: head unmapped)
        # the bird: its wings laid with the elbow and wrist of a wing (0.041 .81/.81 laid as arms)
        limits("\"animalia_bird.b3d\"", 0.038, 0.73, 0.74)      # 0.033 .747/.758 (0.053 .29/.29: tail as head)
        limits("\"RobotExpressive.glb\"", 0.044, 0.66, 0.69)  # 0.0408 .70/.73
        limits("\"Wizard.glb\"", 0.046, 0.40, 0.45)           # 0.0426 .44/.50
        limits("\"ninja.mesh\"", 0.051, 0.40, 0.50)           # 0.0474 .44/.56
        limits("\"BCN_Epileptic.X\"", 0.048, 0.48, 0.43)      # 0.0451 .53/.47
    }
    NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    {
        m = $col["model"]; n++
        if (!(m in cdmax)) { print "FAIL: " m ": no limits"; next }
        if (!($col["cd_j2j"] < cdmax[m])) print "FAIL: template " m ": cd_j2j " $col["cd_j2j"] " >= " cdmax[m]
        if (!($col["precision"] >= pmin[m] && $col["recall"] >= rmin[m]))
            print "FAIL: template " m ": skinning after the matcher " $col["precision"] " / " $col["recall"]
        if (!($col["up_agree"] > 0.9 && $col["forward_agree"] > 0.9))
            print "FAIL: template " m ": read another way up or facing"
        if ($col["unweighted"] != 0) print "FAIL: template " m ": vertices without weights"
        if ($col["status"] != "\"ok\"") print "FAIL: template " m ": " $col["status"]
    }
    END { if (n != 10) print "FAIL: template rig-bench: " n " rows, expected 10" }' "$tmp/tbench.csv" >"$tmp/fails"
if [ -s "$tmp/fails" ]; then cat "$tmp/fails"; ko "rig-bench template thresholds"; else ok; fi
# the rigger timed alone runs with the axes its pipeline node had: the template rigger on the
# Wizard (a file that declares up) fits only with them, and the seconds were "nan" without
"$rigflow" rig-bench -r template "$data/models/Wizard.glb" >"$tmp/wbench.csv" 2>"$tmp/err"
secs=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next } { print $col["seconds"] }' "$tmp/wbench.csv")
case $secs in [0-9]*) ok ;; *) ko "rig-bench -r template Wizard.glb: seconds '$secs'" ;; esac
# a model that is not there is an error (exit 1, named on stderr), not a refused row
if "$rigflow" rig-bench -r general "$tmp/none.glb" >"$tmp/none.csv" 2>"$tmp/err"; then
    ko "rig-bench on a missing file exits 0"
elif grep -q "none.glb: no such file" "$tmp/err"; then ok; else cat "$tmp/err"; ko "rig-bench: missing file not named"; fi
echo "$pass passed, $fail failed"
gltf_exit "$fail"

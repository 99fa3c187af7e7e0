#!/bin/sh
# The general rigger under a turned, scaled and moved model (rigflow rig-bench --turn, --scale,
# --offset: the artist's rig moved with the mesh, so CD-J2J compares like with like). Each moved
# run's CD-J2J must stay within a bar of the unmoved run's, its joint count the same, and a sheet
# stays refused at any facing. doc/autorig.md, "Any facing, scale and position".
#
# The bars, from rig-bench over the 23 shared models at turns 0, 30, 45, 90 and 137 degrees:
# rigged in its own frame (plugins/rig-general/rig-frame.c) each rig below is the unmoved rig
# turned, up to the rounding of the turned positions to floats, so the change measured is
# 0.0000 on every one; the largest change from rounding alone over the 23 models (a scale of
# 0.01 or 100, which no threshold reads) is 0.001 (0.007 on the bull frog, whose curve skeleton
# swings with a voxel boundary, before joint placement's round six). The bar, 0.005, sits
# between that and what the same turns did before the rigger had a frame of its own, rigged
# along the file's axes (each fails here then):
#   greenman.glb, declares its forward, turned 45 and 137 degrees: 0.0405, 0.0143;
#   animalia_bird.b3d, declares none (so the body's own axis sets the frame), 30 degrees: 0.0415;
#   animalia_wolf.b3d, declares none, 30 degrees: 0.0173;
#   animalia_bird.b3d tipped over (a quarter turn about x, its declared up with it): 0.0156;
# and simple_skin.gltf, a flat strip, was rigged once turned 30 degrees (its box no longer flat
# along the file's axes). Scale and offset: 0.0000 and 0.0001 before and after on these three.
rigflow="${RF_BUILDDIR:-.}/rigflow"
data="${RF_DATA_DIR:-}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
ko() { fail=$((fail + 1)); printf 'FAIL: %s\n' "$*"; }

models="$data/models"
if [ -z "$data" ] || [ ! -f "$models/greenman.glb" ] || [ ! -f "$models/creatures/animalia_wolf.b3d" ]; then
    echo "shared models not found (RF_DATA_DIR=$data): skipped"
    exit 77
fi
green="$models/greenman.glb" bird="$models/creatures/animalia_bird.b3d"
wolf="$models/creatures/animalia_wolf.b3d"

# bench NAME OPTIONS... MODEL...: rig-bench's CSV into $tmp/NAME.csv
bench() {
    name=$1
    shift
    if RIGFLOW_QUIET=1 "$rigflow" rig-bench -r general "$@" >"$tmp/$name.csv" 2>"$tmp/$name.err"
    then ok; else cat "$tmp/$name.err"; ko "rig-bench $name: exit $?"; fi
}
# same NAME BAR: every model of $tmp/NAME.csv rigged, with as many joints as unmoved and CD-J2J
# within BAR of the unmoved run's (columns read by their header names)
same() {
    if awk -F, -v bar="$2" -v name="$1" '
        FNR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        FILENAME ~ /base.csv$/ { cd[$2] = $col["cd_j2j"]; nj[$2] = $col["joints"]; next }
        { seen++
          if (!($2 in cd)) { printf "%s: %s not in the unmoved run\n", name, $2; bad = 1; next }
          d = $col["cd_j2j"] - cd[$2]; if (d < 0) d = -d
          printf "%s %s: CD-J2J %s (unmoved %s, change %.4f), %s joints (%s)\n", name, $2,
                 $col["cd_j2j"], cd[$2], d, $col["joints"], nj[$2]
          if (!(d <= bar) || $col["joints"] != nj[$2]) bad = 1 }
        END { exit bad || !seen }' "$tmp/base.csv" "$tmp/$1.csv"
    then ok; else ko "$1: CD-J2J moved more than $2 or the joints changed"; fi
}

bench base "$green" "$bird" "$wolf"
bench green45 --turn=45 "$green"
bench green137 --turn=137 "$green"
bench turn30 --turn=30 "$bird" "$wolf"
bench tilt --axis=1,0,0 --turn=90 "$bird"
bench small --scale=0.01 "$wolf"
bench large --scale=100 --offset=1000,500,-2000 "$wolf"
same green45 0.005
same green137 0.005
same turn30 0.005
same tilt 0.005
same small 0.005
same large 0.005

# the artist's rig moves with the mesh, as computed by hand: turned 90 degrees about +y (the
# wolf's declared up) a joint at (x, y, z) lies at (z, y, -x); scaled by 100 and moved by
# (1000, 500, -2000) it lies at 100 (x, y, z) + that offset, the columns being fractions of the
# longest edge times 100
bench joints0 --joints="$tmp/j0.csv" "$wolf"
bench joints90 --turn=90 --joints="$tmp/j90.csv" "$wolf"
bench jointsL --scale=100 --offset=1000,500,-2000 --joints="$tmp/jL.csv" "$wolf"
if awk -F, '
    FNR == 1 { next }
    $3 != "artist" { next }
    FILENAME ~ /j0.csv$/ { x[$4] = $5; y[$4] = $6; z[$4] = $7; n++; next }
    FILENAME ~ /j90.csv$/ { d = ($5 - z[$4]) ^ 2 + ($6 - y[$4]) ^ 2 + ($7 + x[$4]) ^ 2
                            if (d > 1e-8) { print "turned:", $4, $5, $6, $7; bad = 1 }; m++; next }
    END { exit bad || !n || m != n }' "$tmp/j0.csv" "$tmp/j90.csv"
then ok; else ko "the artist's joints turned 90 degrees are not where a turn puts them"; fi
# scaled and moved: the same fractions of the scaled edge, less one joint's (the offset in
# fractions needs the edge's length, which the CSV does not give)
if awk -F, '
    FNR == 1 { next }
    $3 != "artist" { next }
    FILENAME ~ /j0.csv$/ { if (!n++) { x0 = $5; y0 = $6; z0 = $7 }
                           x[$4] = $5 - x0; y[$4] = $6 - y0; z[$4] = $7 - z0; next }
    { if (!m++) { x1 = $5; y1 = $6; z1 = $7 }
      d = ($5 - x1 - x[$4]) ^ 2 + ($6 - y1 - y[$4]) ^ 2 + ($7 - z1 - z[$4]) ^ 2
      if (d > 1e-8) { print "scaled:", $4, $5, $6, $7; bad = 1 } }
    END { exit bad || !n || m != n }' "$tmp/j0.csv" "$tmp/jL.csv"
then ok; else ko "the artist's joints scaled and moved are not where the scale puts them"; fi
# a model tipped over in a file that still declares +y up (--fixed-axes) is rigged, not refused
bench fixed --axis=1,0,0 --turn=90 --fixed-axes "$wolf"
if awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
           $col["status"] == "\"ok\"" { rigged++ } END { exit !rigged }' "$tmp/fixed.csv"
then ok; else cat "$tmp/fixed.csv"; ko "--fixed-axes: no rig"; fi

# the fire dragon (a wingspan its longest edge, short box legs) turned 137 degrees: its first
# pass keeps its legs but is read lying on its side, so its girdles are looked for along the
# declared up, and it is read up and facing as its artist rig is (after the matcher 35.7% / 36.9%;
# 11.0% / 11.2% with the girdles along the first pass's reading, as unturned before)
dragon="$models/creatures/draconis_fire_dragon.b3d"
if [ -f "$dragon" ]; then
    bench dragon137 --turn=137 "$dragon"
    if awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { seen++; if (!($col["up_agree"] > 0.9 && $col["forward_agree"] > 0.9 &&
                        $col["precision"] >= 0.3 && $col["recall"] >= 0.3)) bad = 1 }
        END { exit bad || !seen }' "$tmp/dragon137.csv"
    then ok; else cat "$tmp/dragon137.csv"; ko "the fire dragon turned 137 degrees read otherwise"; fi
else
    echo "SKIP: $dragon not found: the fire dragon turned not measured"
fi

# the horse and the wolf (files declaring no forward, rigged in a frame turned half round at 137
# degrees) turned 137 degrees: both riggers root them at the hips as unmoved, so they are read
# facing as their artist rigs are, and the matcher maps them as unmoved (after the matcher, P:
# general 0.585 and 0.750, template 0.683 and 0.803, the unmoved figures since the first pass
# is grown from both ends of its thickest ridge; 0.635 / 0.784, 0.704 / 0.784 before).
# With the hips taken as the girdle farthest from the thickest point, which the grid's scan order
# picks among equally thick voxels, the horse read facing back under both riggers (P 0.096,
# 0.096) and the wolf under the template (0.023).
horse="$models/creatures/animala_horse.b3d"
if [ -f "$horse" ]; then
    bench quad137 -r template --turn=137 "$horse" "$wolf"
    if awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { seen++; printf "turned 137: %s %s forward %s, P %s R %s\n", $1, $2,
                  $col["forward_agree"], $col["precision"], $col["recall"]
          if (!($col["forward_agree"] > 0.9 && $col["precision"] >= 0.5)) bad = 1 }
        END { exit bad || seen != 4 }' "$tmp/quad137.csv"
    then ok; else cat "$tmp/quad137.csv"; ko "the horse or the wolf turned 137 degrees read facing back"; fi
else
    echo "SKIP: $horse not found: the horse turned not measured"
fi

# the animalia bird and bull frog (files declaring no forward) turned 137 degrees: the first
# pass is grown from both ends of its thickest voxels' ridge and the root nearer the middle of
# the body kept, so they are rigged as unmoved and read facing as their artist rigs (after the
# matcher P 0.855 and 0.676, as unmoved; the template 0.806 for the bird and 0.520 for the frog,
# as unmoved, since it reads the body's facing as the general rigger does). Grown from the end
# the grid's scan met first, they read facing back (P 0.352 and 0.053; template 0.382).
frog="$models/creatures/animalia_bull_frog.b3d"
if [ -f "$frog" ]; then
    bench ridge137 -r template --turn=137 "$bird" "$frog"
    # four rows: the template rigs the frog as a quadruped (refused before its facing was read)
    if awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        $col["status"] != "\"ok\"" { next }
        { seen++; printf "turned 137: %s %s forward %s, P %s R %s\n", $1, $2,
                  $col["forward_agree"], $col["precision"], $col["recall"]
          if (!($col["forward_agree"] > 0.9 && $col["precision"] >= 0.5)) bad = 1 }
        END { exit bad || seen != 4 }' "$tmp/ridge137.csv"
    then ok; else ko "the bird or the bull frog turned 137 degrees read facing back"; fi
else
    echo "SKIP: $frog not found: the bull frog turned not measured"
fi

# the bull frog and BCN_Epileptic (files declaring no forward) turned a quarter way: rigged on
# the grid turned by that quarter turn, whose voxel boundaries lie elsewhere on the body, and
# their rigs read by the skeleton analysis. Named facing the way their skeletons on the grid
# turned each quarter way read, pooled, both are read facing as their artist rigs at 90 and 270
# degrees (after the matcher P at 90: 0.355 and 0.280). Named facing the way the one grid's
# skeleton reads, the frog read facing back at 90 and 270 degrees (P 0.059, 0.044) and
# BCN_Epileptic at 90 (P 0.034): its feet point forward, its knees back by a hair more.
bcn="$models/BCN_Epileptic.X"
if [ -f "$frog" ] && [ -f "$bcn" ]; then
    bench quarter90 --turn=90 "$frog" "$bcn"
    bench quarter270 --turn=270 "$frog" "$bcn"
    if awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { seen++; printf "%s: %s forward %s, P %s\n", FILENAME ~ /90.csv$/ ? "90" : "270", $2,
                  $col["forward_agree"], $col["precision"]
          if (!($col["forward_agree"] > 0.9 && $col["precision"] >= 0.2)) bad = 1 }
        END { exit bad || seen != 4 }' "$tmp/quarter90.csv" "$tmp/quarter270.csv"
    then ok; else ko "the bull frog or BCN_Epileptic turned a quarter way read facing back"; fi
else
    echo "SKIP: $frog or $bcn not found: the quarter turns not measured"
fi

# a sheet has no volume at any facing: refused turned as unturned
bench sheet --turn=30 "$models/simple_skin.gltf"
if grep -q 'refused:.*flat' "$tmp/sheet.csv"; then ok; else cat "$tmp/sheet.csv"; ko "a flat strip turned 30 degrees was not refused as flat"; fi

# bad values are a usage error (exit 2) naming the option
for bad in --turn=abc --turn=nan --scale=0 --scale=-1 --offset=1,2 --offset=1,2,x --axis=0,0,0; do
    "$rigflow" rig-bench -r general "$bad" "$wolf" >/dev/null 2>"$tmp/usage"
    code=$?
    opt=${bad%%=*}
    if [ "$code" -eq 2 ] && grep -q -- "$opt" "$tmp/usage"; then ok; else
        cat "$tmp/usage"; ko "rig-bench $bad: exit $code, expected 2 and a message naming $opt"; fi
done

# the transform node refuses a malformed offset or axis by name before anything runs
cat >"$tmp/moved.json" <<EOF
{"format": "rigflow.pipeline", "version": 1, "nodes": [
 {"id": "a", "type": "import", "params": {"path": "$wolf"}},
 {"id": "t", "type": "transform", "inputs": {"skeleton": "a.skeleton", "mesh": "a.mesh"}},
 {"id": "out", "type": "export", "inputs": {"skeleton": "t.skeleton", "mesh": "t.mesh"},
  "params": {"path": "$tmp/moved.glb"}}]}
EOF
for bad in offset=1,2 axis=0,0,0 axis=sideways; do
    RIGFLOW_QUIET=1 "$rigflow" run "$tmp/moved.json" -p "t.$bad" 2>"$tmp/err"
    code=$?
    if [ "$code" -ne 0 ] && grep -q "node 't'.*${bad%%=*}: expected" "$tmp/err" &&
        [ ! -e "$tmp/moved.glb" ]; then ok; else
        cat "$tmp/err"; ko "transform -p t.$bad: exit $code, no message naming the node and parameter"; fi
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

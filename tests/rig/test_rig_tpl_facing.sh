#!/bin/sh
# The template rigger's facing on bodies whose files declare no forward, or whose axes are not
# given at all (rigflow rig-bench -r template --turn, --no-axes): its rig must face as the
# artist's does. Checked against the artist's rig by what neither rig's code decides:
#   sides: every template joint named Left... or Right... whose nearest artist joint carries a
#     side in its name (Left, Right, .L, _R...) lies on the artist's side of the same name;
#   front and back: the template's Head is not nearest an artist's tail, nor its Hips nearest an
#     artist's neck (a head may be: the animalia bird's artist rig has its Head joint low in the
#     body, nearer the template's Hips than any other);
#   facing: the skeleton analysis reads the template's rig facing as the artist's
#     (rig-bench's forward_agree over 0.9; -1 is facing back).
# The template reads its facing the way the general rigger names its rig: pooled over the
# body's skeletons on the grid turned each quarter way (rf_rig_pooled_facing; doc/autorig-log.md).
# Read from the one grid's curve skeleton, each case below failed (main at 46d2449):
#   BCN_Epileptic.X turned 90 degrees: forward_agree -1 (after the matcher P 0.32, 0.56 unturned);
#   animalia_bird.b3d turned 90 and 270 degrees: forward_agree -1 (P 0.40, 0.81 unturned);
#   Fox.glb with no axes: Head nearest the artist's tail, Hips its neck, Left on the artist's
#     Right, forward_agree -1 (P 0.02, 0.77 with its axes).
rigflow="${RF_BUILDDIR:-.}/rigflow"
data="${RF_DATA_DIR:-}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
ko() { fail=$((fail + 1)); printf 'FAIL: %s\n' "$*"; }

models="$data/models"
bcn="$models/BCN_Epileptic.X" bird="$models/creatures/animalia_bird.b3d" fox="$models/Fox.glb"
if [ -z "$data" ] || [ ! -f "$bcn" ] || [ ! -f "$bird" ] || [ ! -f "$fox" ]; then
    echo "shared models not found (RF_DATA_DIR=$data): skipped"
    exit 77
fi

# faces NAME OPTIONS... MODEL...: the template's rigs of the models moved by the options face as
# their artists' rigs, by the three checks above
faces() {
    name=$1
    shift
    if ! RIGFLOW_QUIET=1 "$rigflow" rig-bench -r template --joints="$tmp/$name.joints" "$@" \
        >"$tmp/$name.csv" 2>"$tmp/$name.err"; then
        cat "$tmp/$name.err"
        ko "rig-bench $name: exit $?"
        return
    fi
    if awk -F, -v name="$name" '
        # the side a joint name carries: L, R, or "" for none
        function side(n) {
            if (n ~ /Left/ || n ~ /(^|[^A-Za-z])[Ll]([^A-Za-z]|$)/) return "L"
            if (n ~ /Right/ || n ~ /(^|[^A-Za-z])[Rr]([^A-Za-z]|$)/) return "R"
            return ""
        }
        FNR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        FILENAME ~ /\.csv$/ {
            m = $2; rows++
            if ($col["status"] != "\"ok\"") { printf "%s %s: %s\n", name, m, $col["status"]; bad = 1; next }
            printf "%s %s: forward_agree %s, after the matcher P %s\n", name, m,
                   $col["forward_agree"], $col["precision"]
            if (!($col["forward_agree"] > 0.9)) bad = 1
            next
        }
        $3 != "rigger" { next }
        {
            m = $2; j = $4; n = $8; gsub(/"/, "", j); gsub(/"/, "", n)
            s = j ~ /^Left/ ? "L" : j ~ /^Right/ ? "R" : ""
            a = side(n)
            if (s != "" && a != "") { sided[m]++; nsided++; if (s != a) { wrong[m]++
                printf "%s %s: %s nearest the artist'\''s %s\n", name, m, j, n } }
            if ((j == "Head" && n ~ /[Tt]ail/) || (j == "Hips" && n ~ /[Nn]eck/)) {
                printf "%s %s: %s nearest the artist'\''s %s\n", name, m, j, n; bad = 1 }
        }
        END {
            for (m in sided) if (wrong[m] > 0) bad = 1
            exit bad || !rows || !nsided
        }' "$tmp/$name.csv" "$tmp/$name.joints"
    then ok; else ko "$name: a template rig faces otherwise than its artist's"; fi
}

faces turn90 --turn=90 "$bcn" "$bird"
faces turn270 --turn=270 "$bird"
faces noaxes --no-axes "$fox"
# the same rigs unmoved, where the file's axes or the one grid's reading already did it: the
# checks themselves hold on a rig known to face right
faces unmoved "$bcn" "$bird" "$fox"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

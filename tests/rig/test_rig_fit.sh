#!/bin/sh
# rig-fit, the fitting of the template rigger's layouts (doc/autorig.md), on two shared models:
# it prints a row per model and the per-template mean, every score a number, and the layout
# fitted on all models scores no worse on their mean than the built-in one it starts from (the
# descent keeps only steps that lower that mean); the fitted depth of a quadruped's spine stays
# inside the body. With --general (and --prefit) the general rigger's two columns come too.
fit="${RF_BUILDDIR:-.}/tests/rig/rig-fit"
data="${RF_DATA_DIR:-}"
if [ ! -f "$data/models/Fox.glb" ]; then
    echo "SKIP: RF_DATA_DIR not found (../shared/data)"
    exit 77
fi
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$fit" --params dorsal,upleg "$data/models/Fox.glb" "$data/models/creatures/animalia_wolf.b3d" \
    >"$out" 2>&1 || { cat "$out"; echo "FAIL: rig-fit exit $?"; exit 1; }
cat "$out"
awk -F, '
    NR == 1 { if ($0 != "model,template,artist_joints,builtin,leave_one_out,all") print "FAIL: header " $0; next }
    /^mean quadruped/ { mean++; if (!(NF == 4 && $4 + 0 <= $2 + 1e-4)) print "FAIL: fitted mean " $4 " above the built-in " $2; next }
    /^(humanoid|quadruped) fitted on all/ {
        if ($0 ~ /^quadruped/) { split($0, kv, "dorsal="); d = kv[2] + 0
            if (!(d > 0 && d < 1)) print "FAIL: dorsal " kv[2] }
        next }
    { rows++; for (i = 4; i <= 6; i++) if (!($i > 0 && $i < 1)) print "FAIL: " $1 " column " i ": " $i
      if ($2 != "quadruped") print "FAIL: " $1 " fitted as " $2 }
    END { if (rows != 2) print "FAIL: " rows " model rows, expected 2"; if (mean != 1) print "FAIL: no quadruped mean" }
' "$out" | grep FAIL && exit 1
# --general adds the general rigger's CD-J2J with the built-in layouts and with the leave-one-out
# one, every score a number; --prefit starts the fits from the layouts before their fit
"$fit" --prefit --general --params upleg "$data/models/Fox.glb" \
    "$data/models/creatures/animalia_wolf.b3d" >"$out" 2>&1 || { cat "$out"; echo "FAIL: rig-fit --general exit $?"; exit 1; }
cat "$out"
awk -F, '
    NR == 1 { if ($0 != "model,template,artist_joints,builtin,leave_one_out,all,general_builtin,general_leave_one_out") print "FAIL: header " $0; next }
    /^mean quadruped/ { mean++; if (NF != 6) print "FAIL: mean row " $0; next }
    /fitted on all/ { next }
    { rows++; for (i = 4; i <= 8; i++) if (!($i > 0 && $i < 1)) print "FAIL: " $1 " column " i ": " $i }
    END { if (rows != 2) print "FAIL: " rows " model rows, expected 2"; if (mean != 1) print "FAIL: no quadruped mean" }
' "$out" | grep FAIL && exit 1
exit 0

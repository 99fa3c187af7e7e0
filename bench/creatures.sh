#!/bin/sh
# Random creatures through the riggers and scan-to-animation (doc/autorig.md, "Random creatures").
#
#   bench/creatures.sh [BUILDDIR] [SEEDS] [FIRST]
#
# For seeds FIRST .. FIRST+SEEDS-1 (default 1 .. 20) of each body plan (biped, quadruped, dragon,
# and "legs": the quadruped of that seed with 1 to 3 more pairs of legs along its trunk),
# tests/rig/creature makes a creature: a GLB with its generated skeleton and skin (the answer) and
# the bare mesh as an OBJ as generated (any up, facing and scale). Then:
#   - rigflow rig-bench --look CMU-walk on every GLB, both riggers: bench.csv (rig-bench's columns;
#     the model column names plan and seed);
#   - pipelines/scan-to-animation.json on every OBJ (the scan case: no rig, no declared facing,
#     Z up for a quarter of them), the output through the Khronos glTF-Validator: scan.csv
#     (plan,seed,exit,valid,joints,stretch_p99,worst_part,torn_p99,floor_median,floor_p95,
#     height_ratio,reason: the height along the up the rig stands on over the height along the
#     body's own up, 1 when it stands as built, far from 1 when it was rigged lying);
#   - the figures per plan and rigger on stdout, and every row that breaks a rule: a crash (exit
#     status over 2), a rigger row neither ok nor refused, a vertex without weights, a NaN where a
#     figure is due, a GLB the validator rejects.
# Output in $RF_BENCH_OUT (default a temporary folder, printed). Needs ../shared/data's CMU walk.
set -u
build=$(cd "${1:-_build}" && pwd)
seeds=${2:-20}
first=${3:-1}
src=$(cd "$(dirname "$0")/.." && pwd)
data="${RF_DATA_DIR:-$src/../shared/data}"
walk="$data/bvh/cmu_01_01.bvh"
out="${RF_BENCH_OUT:-$(mktemp -d)}"
mkdir -p "$out"
export RIGFLOW_PLUGIN_PATH="$build/plugins" RIGFLOW_QUIET=1
export RF_BUILDDIR="$build" RF_NPM_DIR="${RF_NPM_DIR:-$build/npm/node_modules}"
[ -f "$walk" ] || { echo "no CMU walk at $walk"; exit 77; }

: >"$out/creatures.txt"
glbs="" objs=""
i=$first
last=$((first + seeds - 1))
while [ "$i" -le "$last" ]; do
    for plan in biped quadruped dragon; do
        "$build/tests/rig/creature" --plan "$plan" --seed "$i" --obj "$out/$plan-$i.obj" \
            "$out/$plan-$i.glb" >>"$out/creatures.txt" || echo "creature $plan $i failed"
        glbs="$glbs $out/$plan-$i.glb" objs="$objs $out/$plan-$i.obj"
    done
    # many legs: a quadruped with 1 to 3 more pairs along its trunk
    if "$build/tests/rig/creature" --plan quadruped --seed "$i" --legs $((1 + i % 3)) \
        --obj "$out/legs-$i.obj" "$out/legs-$i.glb" >"$out/made"; then
        sed 's/^quadruped seed/legs seed/' "$out/made" >>"$out/creatures.txt"
    else
        echo "creature legs $i failed"
    fi
    glbs="$glbs $out/legs-$i.glb" objs="$objs $out/legs-$i.obj"
    i=$((i + 1))
done

# shellcheck disable=SC2086 # lists of files
"$build/rigflow" rig-bench --look "$walk" $glbs >"$out/bench.csv" 2>"$out/bench.err"
echo "rig-bench: exit $? ($(grep -c . "$out/bench.err") lines on stderr)"

echo "plan,seed,exit,valid,joints,stretch_p99,worst_part,torn_p99,floor_median,floor_p95,height_ratio,reason" \
    >"$out/scan.csv"
num() { sed -n "s/.*\"$1\": \([-0-9.e+naif]*\).*/\1/p" "$2"; }
for obj in $objs; do
    base=$(basename "$obj" .obj) plan=${base%-*} seed=${base##*-}
    glb="$out/$base-walk.glb" json="$out/$base-walk.json"
    "$build/rigflow" run "$src/pipelines/scan-to-animation.json" -p "mesh.path=$obj" \
        -p "motion.path=$walk" -p "export.path=$glb" -p retarget.last_frame=119 \
        -p "measure.path=$json" >"$out/$base-walk.out" 2>"$out/$base-walk.err"
    code=$? valid=- joints=- f="nan,nan,nan,nan,nan,nan" reason=
    height=$(sed -n "s/^$plan seed $seed: .*, height \([0-9.e+-]*\)$/\1/p" "$out/creatures.txt")
    if [ "$code" -eq 0 ]; then
        node "$src/tests/gltf/validate.js" "$glb" >"$out/$base-valid.txt" 2>&1
        case $? in 0) valid=yes ;; 77) valid=skipped ;; *) valid=no ;; esac
        joints=$(sed -n 's/^summary: \([0-9]*\) joints.*/\1/p' "$out/$base-walk.out")
        f="$(awk -v v="$(num stretch_p99 "$json")" 'BEGIN { printf "%.2f", 100 * v }'),"
        f="$f$(awk -v v="$(num part_stretch_p99 "$json")" 'BEGIN { printf "%.2f", 100 * v }'),"
        f="$f$(awk -v v="$(num seam_p99 "$json")" 'BEGIN { printf "%.2f", 100 * v }'),"
        f="$f$(awk -v v="$(num floor_median "$json")" 'BEGIN { printf "%.2f", 100 * v }'),"
        f="$f$(awk -v v="$(num floor_p95 "$json")" 'BEGIN { printf "%.2f", 100 * v }'),"
        f="$f$(awk -v v="$(num height "$json")" -v h="$height" 'BEGIN { printf "%.3f", v / h }')"
    else
        reason=$(grep -m1 "node '" "$out/$base-walk.err" | tr ',' ';')
    fi
    echo "$plan,$seed,$code,$valid,$joints,$f,$reason" >>"$out/scan.csv"
done

# per plan and rigger: medians and worst values of rig-bench's columns
awk -F, '
    FNR == 1 { for (k = 1; k <= NF; k++) col[$k] = k; next }
    { m = $col["model"]; gsub(/"|-[0-9]*\.glb/, "", m); key = $col["rigger"] " " m
      rows[key]++
      st = $col["status"]
      if (st ~ /^"ok"$/) ok[key]++; else if (st ~ /^"refused/) ref[key]++
      else printf "BROKEN %s %s: %s\n", $col["rigger"], $col["model"], st
      if (st !~ /^"ok"$/) next
      n = ++cnt[key]
      cd[key, n] = $col["cd_j2j"]; pr[key, n] = $col["precision"]; re[key, n] = $col["recall"]
      gp[key, n] = $col["given_precision"]; gr[key, n] = $col["given_recall"]
      sp[key, n] = $col["look_stretch_p99"]; wp[key, n] = $col["look_worst_part"]
      tp[key, n] = $col["look_torn_p99"]; fm[key, n] = $col["look_floor_median"]
      uw[key] += $col["unweighted"]
      if ($col["unweighted"] > 0) printf "UNWEIGHTED %s %s: %s\n", $col["rigger"], $col["model"], $col["unweighted"]
      if ($col["cd_j2j"] == "nan" || $col["look_stretch_p99"] == "nan")
        printf "NAN %s %s\n", $col["rigger"], $col["model"]
      if ($col["forward_agree"] < 0.5) bw[key]++ }
    function med(a, key, n,   i, j, t, v) {
      for (i = 1; i <= n; i++) v[i] = a[key, i] + 0
      for (i = 2; i <= n; i++) for (j = i; j > 1 && v[j - 1] > v[j]; j--) { t = v[j]; v[j] = v[j - 1]; v[j - 1] = t }
      return n ? (n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2) : "nan" }
    function mx(a, key, n,   i, v) { v = -1e9; for (i = 1; i <= n; i++) if (a[key, i] + 0 > v) v = a[key, i] + 0; return v }
    END {
      print "rigger plan: rigged/refused of rows; CD-J2J median, max; after the matcher precision, recall median;" \
            " given precision, recall median; read facing back; look stretch p99 median, max; worst part median, max;" \
            " torn p99 median, max; floor median max |.|; unweighted"
      for (key in rows) {
        n = cnt[key]; fmx = 0
        if (!n) { printf "%s: 0/%d of %d\n", key, ref[key], rows[key]; continue }
        for (i = 1; i <= n; i++) { v = fm[key, i] + 0; if (v < 0) v = -v; if (v > fmx) fmx = v }
        printf "%s: %d/%d of %d; cd %.4f, %.4f; after %.2f, %.2f; given %.2f, %.2f; back %d; stretch %.1f, %.1f; worst %.1f, %.1f; torn %.1f, %.1f; floor %.2f; unweighted %d\n",
          key, ok[key], ref[key], rows[key], med(cd, key, n), mx(cd, key, n), med(pr, key, n),
          med(re, key, n), med(gp, key, n), med(gr, key, n), bw[key], med(sp, key, n), mx(sp, key, n),
          med(wp, key, n), mx(wp, key, n), med(tp, key, n), mx(tp, key, n), fmx, uw[key] }
    }' "$out/bench.csv" | sort
# scan-to-animation on the bare meshes
awk -F, 'NR > 1 { rows[$1]++
      if ($3 == 0) { ok[$1]++; if ($4 == "no") printf "INVALID %s-%s\n", $1, $2
        if ($6 == "nan" || $10 == "nan") printf "NAN scan %s-%s\n", $1, $2
        t = $8 + 0; if (t > tmax[$1]) tmax[$1] = t; f = $9 < 0 ? -$9 : $9; if (f > fmax[$1]) fmax[$1] = f
        p = $10 + 0; if (p > pmax[$1]) pmax[$1] = p; w = $7 + 0; if (w > wmax[$1]) wmax[$1] = w
        if ($11 < 0.95 || $11 > 1.05) { lying[$1]++; printf "LYING scan %s-%s: height ratio %s\n", $1, $2, $11 } }
      else if ($3 == 1) ref[$1]++
      else printf "CRASH scan %s-%s: exit %s\n", $1, $2, $3 }
    END { for (p in rows)
        printf "scan %s: %d rigged, %d refused of %d; %d rigged lying; worst part max %.1f; torn p99 max %.1f; floor median max |.| %.2f, p95 max %.2f\n",
          p, ok[p], ref[p], rows[p], lying[p], wmax[p], tmax[p], fmax[p], pmax[p] }' "$out/scan.csv" | sort
grep -h . "$out"/*-walk.err 2>/dev/null | grep -v ': info: ' | sort | uniq -c | sort -rn | head -5
echo "output in $out"

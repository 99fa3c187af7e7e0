#!/usr/bin/env bash
# report.html without a browser: the data block holds no '<' and parses back to the joint names
# given (markup and control characters included); a missing three.js fails the run with a message
# and leaves no file; without report.path nothing is written; report.summary escapes its label.
# every measures input is shown, a joint the target lacks as -1; Ctrl-C during rigflow report
# leaves nothing. Needs node.
set -u
rigflow="${RF_BUILDDIR:?}/rigflow"
src="${RF_SRCDIR:?}"
command -v node >/dev/null || { echo "SKIP: node not found (apt-get install nodejs)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
ok() { echo "ok - $*"; }
bad() { echo "not ok - $*"; fail=1; }

node "$src/tests/report/make-bvh.mjs" names >"$tmp/names.bvh"
node "$src/tests/report/make-bvh.mjs" tail 40 >"$tmp/plain.bvh"
run() { "$rigflow" run "$src/pipelines/map.json" -p source.path="$tmp/plain.bvh" \
    -p target.path="$tmp/names.bvh" -p save.path="$tmp/map.json" "$@"; }

if run -p report.path="$tmp/r.html" >"$tmp/log" 2>&1; then ok "map pipeline with a report"
else bad "map pipeline with a report failed:"; sed 's/^/    /' "$tmp/log"; fi
# the data block: between the rf-data script's '>' and the next '</script>'
node -e '
  const fs = require("fs");
  const html = fs.readFileSync(process.argv[1], "latin1");
  const start = html.indexOf("id=\"rf-data\">") + 13, end = html.indexOf("</script>", start);
  const block = html.slice(start, end);
  const want = JSON.parse(require("child_process").execFileSync("node", [process.argv[2], "names-json"]));
  const fail = (m) => { console.log("not ok - " + m); process.exitCode = 1; };
  if (block.includes("<")) fail("a raw < in the data block");
  else console.log("ok - no raw < in the data block (" + block.length + " bytes)");
  const data = JSON.parse(Buffer.from(block, "latin1").toString("utf8"));
  const target = data.characters.find((c) => c.role === "target");
  const names = target.joints.map((j) => j.name);
  for (const w of want)
    if (names.includes(w)) console.log("ok - " + JSON.stringify(w) + " round-trips");
    else fail(JSON.stringify(w) + " not among " + JSON.stringify(names));
  if (target.joints.length !== 22) fail(target.joints.length + " target joints, expected 22");
' "$tmp/r.html" "$src/tests/report/make-bvh.mjs" || fail=1

if run -p report.path="$tmp/none.html" -p report.three="$tmp/nothing" >"$tmp/log" 2>&1; then
    bad "a missing three.js was not noticed"
elif grep -q "three.js" "$tmp/log" && grep -q "libjs-three" "$tmp/log"; then
    ok "a missing three.js fails the run: $(grep -m1 three.js "$tmp/log")"
else bad "no clear message for a missing three.js:"; sed 's/^/    /' "$tmp/log"; fi
left=$(find "$tmp" -name 'none*' | wc -l)
[ "$left" = 0 ] && ok "no file left behind" || { bad "files left: $(ls "$tmp")"; }

if run >"$tmp/log" 2>&1 && [ -z "$(find "$tmp" -name '*.html' ! -name r.html)" ]; then
    ok "no report.path, no report"
else bad "a run without report.path failed or wrote a page"; fi
# report.summary: a label from a pipeline file reaches the terminal escaped (an ESC sequence there
# would retitle or recolour it)
sed 's/"type": "report.summary",/"type": "report.summary", "params": {"label": "x\\u001b]0;owned\\u0007\\u00c2\\u009b2J"},/' \
    "$src/pipelines/bvh-roundtrip.json" >"$tmp/label.json"
if "$rigflow" run "$tmp/label.json" -p source.path="$tmp/plain.bvh" -p export.path="$tmp/label.bvh" \
    >"$tmp/out" 2>"$tmp/log" && grep -q 'label' "$tmp/label.json"; then
    if LC_ALL=C grep -q $'[\x1b\x07]' "$tmp/out" || grep -q $'\u009b' "$tmp/out"; then
        bad "report.summary printed control bytes from the pipeline: $(od -c "$tmp/out" | head -3)"
    elif grep -qF 'x\x1b]0;owned\x07' "$tmp/out"; then ok "report.summary escapes its label"
    else bad "report.summary label missing: $(cat "$tmp/out")"; fi
else bad "the labelled round trip failed: $(cat "$tmp/log")"; fi
# rigflow report: the retarget pipeline with its page, no GLB unless asked; -o is required
if "$rigflow" -q report "$tmp/plain.bvh" "$tmp/names.bvh" -o "$tmp/cmd.html" >"$tmp/log" 2>&1 &&
    grep -q 'id="rf-data"' "$tmp/cmd.html" && [ -z "$(find "$tmp" -name '*.glb')" ]; then
    ok "rigflow report writes the page and no GLB"
else bad "rigflow report:"; sed 's/^/    /' "$tmp/log"; fi
"$rigflow" report "$tmp/plain.bvh" "$tmp/names.bvh" >"$tmp/log" 2>&1
code=$?
[ "$code" = 2 ] && grep -q -- "-o OUT.html is required" "$tmp/log" && ok "rigflow report without -o: usage error" ||
    bad "rigflow report without -o exited $code: $(cat "$tmp/log")"
# a clip whose Frame Time is tiny (1e-300 s: 1e300 fps, finite): the page shows its frames
sed 's/^Frame Time:.*/Frame Time: 1e-300/' "$tmp/plain.bvh" >"$tmp/fast.bvh"
"$rigflow" -q report "$tmp/fast.bvh" "$tmp/plain.bvh" -o "$tmp/fast.html" >"$tmp/log" 2>&1
code=$?
[ "$code" = 0 ] && grep -q '"timeline":{"total":2,"step":2,"shown":1,' "$tmp/fast.html" &&
    ok "a 1e300 fps clip: one frame of two shown" || bad "a 1e300 fps clip: exit $code $(cat "$tmp/log")"

# a measure about a joint the target does not have (a plugin's mistake): the page gets -1 (the
# whole character) for it, not an index its viewer would look up past the joints
cat >"$tmp/badjoint.json" <<EOF
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "target", "type": "bvh.import", "params": {"path": "$tmp/plain.bvh"}},
  {"id": "m", "type": "test.measures", "params": {"joint": 999}},
  {"id": "report", "type": "report.html", "params": {"path": "$tmp/badjoint.html"},
   "inputs": {"target": "target.skeleton", "measures": ["m.measures"]}}]}
EOF
"$rigflow" -q --plugin-path "$RF_BUILDDIR/tests/report/.libs" run "$tmp/badjoint.json" >"$tmp/log" 2>&1
code=$?
joint=$(node -e '
  const html = require("fs").readFileSync(process.argv[1], "utf8");
  const start = html.indexOf("id=\"rf-data\">") + 13, end = html.indexOf("</script>", start);
  console.log(JSON.parse(html.slice(start, end)).measures[0].joint);
' "$tmp/badjoint.html" 2>/dev/null)
[ "$code" = 0 ] && [ "$joint" = -1 ] && ok "a measure about joint 999 of 40 is shown as about the whole character" ||
    bad "a measure about joint 999: exit $code, joint '$joint': $(cat "$tmp/log")"

# every measures input reaches the page: 17 of them carry 17 times the series of one
node -e '
  const fs = require("fs");
  const p = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
  p.nodes.find((n) => n.id === "report").inputs.measures = Array(17).fill("measure.measures");
  fs.writeFileSync(process.argv[2], JSON.stringify(p));
' "$src/pipelines/retarget.json" "$tmp/many.json"
cp "$src/pipelines/retarget.json" "$tmp/one.json"
series() { # PIPELINE: how many series the page of a retarget shows
    "$rigflow" -q run "$1" -p source.path="$tmp/plain.bvh" -p target.path="$tmp/names.bvh" \
        -p export.path="$tmp/m.glb" -p report.path="$tmp/m.html" >/dev/null 2>"$tmp/log" &&
        node -e '
          const html = require("fs").readFileSync(process.argv[1], "utf8");
          const start = html.indexOf("id=\"rf-data\">") + 13, end = html.indexOf("</script>", start);
          console.log(JSON.parse(html.slice(start, end)).measures.length);
        ' "$tmp/m.html"
}
one=$(series "$tmp/one.json")
many=$(series "$tmp/many.json")
[ -n "$one" ] && [ "$one" -gt 0 ] && [ "$many" = $((17 * one)) ] &&
    ok "17 measures inputs: $many series, 17 x $one" ||
    bad "17 measures inputs gave '$many' series, one gave '$one': $(cat "$tmp/log")"

# Ctrl-C during rigflow report removes every output, temporary files included, as rigflow run does
# (a long clip keeps the run going; env gives the background job the default SIGINT back).
if env --default-signal=INT true 2>/dev/null; then
    node "$src/tests/report/make-bvh.mjs" tail 22 | awk -v n=200000 '/^Frames:/ { print "Frames: " n; next }
        /^Frame Time/ { print; getline; for (i = 0; i < n; i++) print; exit } { print }' >"$tmp/long.bvh"
    mkdir -p "$tmp/int"
    env --default-signal=INT "$rigflow" -q report "$tmp/long.bvh" "$tmp/plain.bvh" -o "$tmp/int/r.html" \
        --glb "$tmp/int/r.glb" >"$tmp/log" 2>&1 &
    pid=$!
    for _ in $(seq 1000); do ls -A "$tmp/int" | grep -q 'rf-' && break; sleep 0.01; done
    kill -INT "$pid"
    wait "$pid"
    code=$?
    left=$(ls -A "$tmp/int")
    [ "$code" = 130 ] && [ -z "$left" ] && ok "Ctrl-C during rigflow report: exit 130, nothing left" ||
        bad "Ctrl-C during rigflow report: exit $code, left: $left"
else
    echo "# SKIP Ctrl-C during rigflow report: env --default-signal missing"
fi
exit $fail

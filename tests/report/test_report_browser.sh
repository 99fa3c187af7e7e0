#!/usr/bin/env bash
# report.html in a real browser (doc/report.md): reports of the CMU walk onto the Fox and onto the
# fire dragon, a clip of 10,000 frames, a 200-joint skeleton and joint names full of markup, opened
# in Debian's chromium through npm's playwright-core (tests/report/report-browser.mjs). Screenshots
# stay in $RF_BUILDDIR/tests/report/artefacts. Exit 77 (SKIP) without chromium, node,
# playwright-core, three.js or the shared data.
set -u
rigflow="${RF_BUILDDIR:?}/rigflow"
src="${RF_SRCDIR:?}"
data="${RF_DATA_DIR:-}"
walk="$data/bvh/cmu_01_01.bvh" fox="$data/models/Fox.glb"
dragon="$data/models/creatures/draconis_fire_dragon.b3d"
skip() { echo "SKIP: $*"; exit 77; }
command -v node >/dev/null || skip "node not found (apt-get install nodejs)"
[ -x "${RF_CHROMIUM:-/usr/bin/chromium}" ] || skip "chromium not found (apt-get install chromium)"
[ -d "${RF_NPM_DIR:-}/playwright-core" ] || skip "playwright-core not in ${RF_NPM_DIR:-} (./quickstart.sh deps)"
for f in "$walk" "$fox" "$dragon"; do [ -f "$f" ] || skip "test data $f not found (RF_DATA_DIR)"; done

out="$RF_BUILDDIR/tests/report/artefacts"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rm -rf "$out" && mkdir -p "$out"
fail=0
report() { # NAME TARGET SOURCE [-p ...]: retarget SOURCE onto TARGET with a report; prints the target's joints
    local name=$1 target=$2 source=$3
    shift 3
    local log="$tmp/$name.log"
    if ! "$rigflow" run "$src/pipelines/retarget.json" -p source.path="$source" -p target.path="$target" \
        -p export.path="$tmp/$name.glb" -p report.path="$out/$name.html" "$@" >"$log" 2>&1; then
        echo "not ok - $name: the pipeline failed:"; sed 's/^/    /' "$log"; return 1
    fi
    # the joint count as report.summary prints it, not as the page says
    sed -n 's/^summary: \([0-9]*\) joints.*/\1/p' "$log"
}
grep -q "three.js" <("$rigflow" describe report.html) || skip "no report.html node"
ls "$(sed -n 's/^#define RF_THREE_DIR "\(.*\)"$/\1/p' "$RF_BUILDDIR/config.h")/build/three.min.js" >/dev/null 2>&1 ||
    skip "three.js not found (apt-get install libjs-three)"

fox_n=$(report fox "$fox" "$walk") || fail=1
dragon_n=$(report dragon "$dragon" "$walk") || fail=1

# Large input: 10,000 frames onto the Fox; a 200-joint creature (a biped with a long tail)
node "$src/../shared/peers/gen_bvh.mjs" 10000 120 "$tmp/long.bvh" >/dev/null 2>&1 ||
    node "$RF_DATA_DIR/../peers/gen_bvh.mjs" 10000 120 "$tmp/long.bvh" >/dev/null
long_n=$(report long "$fox" "$tmp/long.bvh") || fail=1
node "$src/tests/report/make-bvh.mjs" tail 200 >"$tmp/tail.bvh"
tail_n=$(report tail200 "$tmp/tail.bvh" "$walk") || fail=1
# Joint names full of markup and control characters, as the source and as the target
node "$src/tests/report/make-bvh.mjs" names >"$tmp/names.bvh"
names_n=$(report names "$tmp/names.bvh" "$walk") || fail=1
export RF_REPORT_NAMES
RF_REPORT_NAMES=$(node "$src/tests/report/make-bvh.mjs" names-json)

size=$(stat -c %s "$out/fox.html" 2>/dev/null || echo 0)
if [ "$size" -gt 0 ] && [ "$size" -lt 5000000 ]; then echo "ok - the CMU walk onto the Fox: $size bytes (< 5 MB)"
else echo "not ok - the Fox report is $size bytes"; fail=1; fi
[ "$fail" = 0 ] || exit 1

node "$src/tests/report/report-browser.mjs" "$out" "full:fox:$out/fox.html:$fox_n" \
    "full:dragon:$out/dragon.html:$dragon_n" "large:long:$out/long.html:$long_n" \
    "large:tail200:$out/tail200.html:$tail_n" "names:names:$out/names.html:$names_n"

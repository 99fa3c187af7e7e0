#!/usr/bin/env bash
# The bad-input matrix (doc/reliability.md lists every row and where the rows that other
# tests already cover live). Each row feeds the rigflow command one hostile input or condition and
# checks the exit code, the message, and that no output (nor a temporary file) is left behind.
# Every input is made here, in a scratch folder; nothing comes from outside the repository except
# the optional shared data.
#
# Environment: RF_BUILDDIR, RF_SRCDIR (set by make check); RF_RIGFLOW runs the command through a
# wrapper (make valgrind sets it); RF_DEEP_JOINTS (default 100000) sizes the deep-nesting rows.
set -u
build="${RF_BUILDDIR:?}"
src="${RF_SRCDIR:?}"
rigflow="${RF_RIGFLOW:-$build/rigflow}"
convert="$src/pipelines/convert.json"
deep=${RF_DEEP_JOINTS:-100000}
tmp=$(mktemp -d)
trap 'chmod -R u+rwx "$tmp" 2>/dev/null; umount "$tmp/full" 2>/dev/null; rm -rf "$tmp"' EXIT
pass=0 fail=0 skip=0

ok() { pass=$((pass + 1)); echo "ok - $1"; }
bad() { fail=$((fail + 1)); echo "not ok - $1"; sed 's/^/    stderr: /' "$tmp/err" | head -12; }
skipped() { skip=$((skip + 1)); echo "ok - $1 # SKIP $2"; }

# rf ARGS...: the command, stdout to $tmp/out, stderr to $tmp/err; sets $code. rfv keeps the
# warnings --quiet drops.
rf() {
    "$rigflow" --quiet "$@" >"$tmp/out" 2>"$tmp/err"
    code=$?
}
rfv() {
    "$rigflow" "$@" >"$tmp/out" 2>"$tmp/err"
    code=$?
}

# leftovers DIR: what a run left in DIR (outputs and temporary files), or nothing.
leftovers() { ls -A "$1" 2>/dev/null; }

# row NAME CODE MESSAGE INPUT OUTPUT [-p ...]: converts INPUT to OUTPUT (format by extension) and
# expects exit CODE, MESSAGE in stderr and nothing in OUTPUT's folder.
row() {
    local name=$1 want=$2 msg=$3 in=$4 out=$5
    shift 5
    rm -rf "$tmp/o" && mkdir -p "$tmp/o"
    rf run "$convert" -p source.path="$in" -p export.path="$out" "$@"
    local left
    left=$(leftovers "$(dirname "$out")")
    if [ "$code" != "$want" ]; then bad "$name: exit $code, expected $want"
    elif ! grep -qF -- "$msg" "$tmp/err"; then bad "$name: '$msg' not in the message"
    elif [ -n "$left" ]; then bad "$name: left $left behind"
    else ok "$name"; fi
}

# good NAME INPUT OUTPUT [MESSAGE]: a hostile but valid input converts, with MESSAGE if given
# (a warning: the run is not --quiet then).
good() {
    local name=$1 in=$2 out=$3 msg=${4:-}
    rm -f "$out"
    if [ -n "$msg" ]; then rfv run "$convert" -p source.path="$in" -p export.path="$out"
    else rf run "$convert" -p source.path="$in" -p export.path="$out"; fi
    if [ "$code" != 0 ]; then bad "$name: exit $code, expected 0"
    elif [ -n "$msg" ] && ! grep -qF -- "$msg" "$tmp/err"; then bad "$name: '$msg' not in the message"
    elif [ ! -s "$out" ]; then bad "$name: no output written"
    else ok "$name"; fi
}

o="$tmp/o/out" # every failing row writes here; its folder must stay empty
cp "$src/tests/fuzz/seeds/bvh/minimal.bvh" "$tmp/ok.bvh"
good "a small valid BVH converts to GLB (the material for the GLB rows)" "$tmp/ok.bvh" "$tmp/ok.glb"

# ---- truncated and empty files ----
: >"$tmp/empty.bvh"
row "empty BVH" 1 "empty.bvh:1: expected HIERARCHY, found the end of the file" "$tmp/empty.bvh" "$o.glb"
head -n 9 "$tmp/ok.bvh" >"$tmp/cut-hierarchy.bvh"
row "BVH cut inside the hierarchy" 1 "the file ends inside joint 'Spine'" "$tmp/cut-hierarchy.bvh" "$o.glb"
head -c "$(($(wc -c <"$tmp/ok.bvh") - 20))" "$tmp/ok.bvh" >"$tmp/cut-motion.bvh"
row "BVH cut inside the motion" 1 "cut-motion.bvh:" "$tmp/cut-motion.bvh" "$o.glb"
: >"$tmp/empty.glb"
row "empty GLB" 1 "empty.glb: Assimp cannot read it" "$tmp/empty.glb" "$o.bvh"
head -c "$(($(wc -c <"$tmp/ok.glb") / 2))" "$tmp/ok.glb" >"$tmp/cut.glb"
glb_size=$(wc -c <"$tmp/ok.glb")
row "GLB cut in half" 1 \
    "cut.glb: the GLB header declares a length of $glb_size bytes but the file has $((glb_size / 2))" \
    "$tmp/cut.glb" "$o.bvh"
# a header that claims 0x7FFFFFFF bytes, as a corrupt download may: refused with both lengths
cp "$tmp/ok.glb" "$tmp/long.glb"
printf '\377\377\377\177' | dd of="$tmp/long.glb" bs=1 seek=8 conv=notrunc status=none
row "GLB whose header declares another length" 1 \
    "long.glb: the GLB header declares a length of 2147483647 bytes but the file has $glb_size" \
    "$tmp/long.glb" "$o.bvh"

# ---- wrong format behind a known extension ----
cp "$tmp/ok.glb" "$tmp/glb-inside.bvh"
row "GLB bytes named .bvh" 1 "expected HIERARCHY at the start of the file, found 'glTF\\x02'" \
    "$tmp/glb-inside.bvh" "$o.glb"
printf '\x89PNG\r\n\x1a\n\0\0\0\rIHDR' >"$tmp/png-inside.glb"
row "PNG bytes named .glb" 1 "png-inside.glb: Assimp cannot read it" "$tmp/png-inside.glb" "$o.bvh"
echo '{"asset": {"version": "2.0"}, "nodes": "not a list"}' >"$tmp/bad-schema.gltf"
row "glTF JSON of the wrong shape" 1 "bad-schema.gltf: Assimp cannot read it" \
    "$tmp/bad-schema.gltf" "$o.bvh"

# ---- NaN, infinity, overflow ----
bvh1() { # bvh1 OFFSET-Y MOTION-LINE FRAME-TIME: a one-joint BVH
    printf 'HIERARCHY\nROOT a\n{\nOFFSET 0 %s 0\nCHANNELS 3 Xposition Yposition Zrotation\n' "$1"
    printf 'End Site\n{\nOFFSET 0 1 0\n}\n}\nMOTION\nFrames: 2\nFrame Time: %s\n0 0 0\n%s\n' "$3" "$2"
}
bvh1 0 "nan 1 2" 0.1 >"$tmp/nan.bvh"
row "NaN in the motion" 1 "nan.bvh:15: 'nan' is not a finite number (frame 2, joint 'a', Xposition)" \
    "$tmp/nan.bvh" "$o.glb"
bvh1 inf "0 1 2" 0.1 >"$tmp/inf.bvh"
row "infinite OFFSET" 1 "inf.bvh:4: 'inf' is not a finite number: expected the OFFSET's y" \
    "$tmp/inf.bvh" "$o.glb"
bvh1 0 "0 1 1e400" 0.1 >"$tmp/huge.bvh"
row "a number beyond double range" 1 "huge.bvh:15:" "$tmp/huge.bvh" "$o.glb"
bvh1 1e308 "1e308 1e308 0" 0.1 >"$tmp/big.bvh"
row "finite values beyond range (their squares would overflow)" 1 \
    "big.bvh:4: '1e308' is out of range: expected the OFFSET's y within +-1e+30" "$tmp/big.bvh" "$o.bvh"
bvh1 0 "0 1 2" 0.01e3081 >"$tmp/inf-time.bvh" # found by fuzz_bvh: the rate became 0 fps
row "Frame Time that reads as infinity" 1 "expected a positive Frame Time" "$tmp/inf-time.bvh" "$o.glb"
bvh1 0 "0 1 2" 1e-300 >"$tmp/tiny-time.bvh" # 1e300 fps: finite, but no float32 tells its frames apart
row "Frame Time too small for glTF's float32 times" 1 \
    "animation 0 'tiny-time': frames 0 and 1 fall on one time in glTF's float32 seconds (1e+300 fps)" \
    "$tmp/tiny-time.bvh" "$o.glb"
bvh1 0 "0 1 2" 1e300 >"$tmp/huge-time.bvh" # resampled to 30 fps: 3e301 frames, beyond any index
rm -rf "$tmp/o" && mkdir -p "$tmp/o"
rf run "$src/pipelines/retarget.json" -p source.path="$tmp/huge-time.bvh" \
    -p target.path="$tmp/huge-time.bvh" -p retarget.fps=30 -p export.path="$o.glb"
if [ "$code" = 1 ] && grep -qF "the clip would be 3e+301 frames at 30 fps (its 2 frames span 1e+300 s)" "$tmp/err" &&
    [ -z "$(leftovers "$tmp/o")" ]; then
    ok "a Frame Time of 1e300 s resampled to 30 fps is refused, and named"
else bad "Frame Time 1e300 resampled (exit $code)"; fi

# ---- names that are not UTF-8 (Latin-1 from an old exporter) written as glTF, whose JSON must be ----
printf 'HIERARCHY\nROOT H\351ps\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zrotation\nJOINT Spine\n' >"$tmp/latin1.bvh"
printf '{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n}\nMOTION\nFrames: 2\n' >>"$tmp/latin1.bvh"
printf 'Frame Time: 0.1\n0 0 0 0\n0 0 1 2\n' >>"$tmp/latin1.bvh"
good "a Latin-1 joint name converts to GLB" "$tmp/latin1.bvh" "$tmp/latin1.glb"
good "... which reads back, every joint in place" "$tmp/latin1.glb" "$tmp/latin1-back.bvh"
grep -q "ROOT H$(printf '\357\277\275')ps" "$tmp/latin1-back.bvh" && grep -q "JOINT Spine" "$tmp/latin1-back.bvh" &&
    ok "... the byte that is not UTF-8 became U+FFFD, the rest of the name kept" ||
    bad "... names after the round trip: $(grep -a 'ROOT\|JOINT' "$tmp/latin1-back.bvh" 2>/dev/null | od -c | head -3)"

# ---- bytes that would drive a terminal, quoted in a message ----
printf 'HIERARCHY\nROOT \033[2J\033]0;pwned\007\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\nJOINT \033[2J\033]0;pwned\007\n' >"$tmp/esc.bvh"
row "control characters from a file are escaped in messages" 1 \
    "duplicate joint name '\\x1b[2J\\x1b]0;pwned\\x07'" "$tmp/esc.bvh" "$o.glb"
if grep -q "$(printf '\033')" "$tmp/err"; then bad "... an escape byte reached the terminal"; else ok "... none reaches the terminal"; fi
# A valid file whose joint names carry ESC and C1 (8-bit CSI) sequences: the listings of inspect
# and map --explain show them escaped, and no raw control byte reaches the terminal.
{
    printf 'HIERARCHY\nROOT Hips\033]0;pwned\007\n{\nOFFSET 0 0 0\nCHANNELS 3 Xrotation Yrotation Zrotation\n'
    printf 'JOINT Leg\302\2331m\n{\nOFFSET 0 -1 0\nCHANNELS 3 Xrotation Yrotation Zrotation\n'
    printf 'End Site\n{\nOFFSET 0 -1 0\n}\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0 0 0 0\n'
} >"$tmp/names.bvh"
controls="$(printf '\033\007\302\233')"
rfv inspect "$tmp/names.bvh"
if [ "$code" != 0 ]; then bad "inspect lists hostile joint names: exit $code"
elif grep -q "[$controls]" "$tmp/out" "$tmp/err"; then bad "inspect: a control byte reached the terminal"
elif ! grep -qF 'Hips\x1b]0;pwned\x07' "$tmp/out" || ! grep -qF 'Leg\xc2\x9b1m' "$tmp/out"; then
    bad "inspect: names not shown escaped: $(head -c 300 "$tmp/out")"
else ok "inspect shows hostile joint names escaped"; fi
rfv map --explain "$tmp/names.bvh" "$tmp/names.bvh"
if [ "$code" != 0 ]; then bad "map --explain lists hostile joint names: exit $code"
elif grep -q "[$controls]" "$tmp/out" "$tmp/err"; then bad "map --explain: a control byte reached the terminal"
elif ! grep -qF 'Leg\xc2\x9b1m' "$tmp/out"; then bad "map --explain: names not shown escaped"
else ok "map --explain shows hostile joint names escaped"; fi

# rig-bench prints model file names in its CSV rows and its messages: a name carrying ESC and C1
# (8-bit CSI) sequences is shown escaped there too, the CSV row on one line.
hostile="$tmp/rb$(printf '\033]0;pwned\007')x$(printf '\302\233')1m"
printf 'not a GLB' >"$hostile.glb"
printf 'HIERARCHY\n' >"$hostile.bvh"
rfv rig-bench -r general "$hostile.bvh" "$hostile.glb" # one rigger: one row
if [ "$code" = 2 ] && grep -q "no rigger plugin found" "$tmp/err"; then
    skipped "rig-bench shows hostile file names escaped" "no rigger plugin built"
elif [ "$code" != 1 ]; then bad "rig-bench on unreadable models: exit $code, expected 1"
elif grep -q "[$controls]" "$tmp/out" "$tmp/err"; then bad "rig-bench: a control byte reached the terminal"
elif ! grep -qF 'rb\x1b]0;pwned\x07x\xc2\x9b1m.bvh: its importer cannot ignore a rig' "$tmp/err"; then
    bad "rig-bench: the unread file is not named escaped"
elif ! grep -qF '"rb\x1b]0;pwned\x07x\xc2\x9b1m.glb"' "$tmp/out" || [ "$(wc -l <"$tmp/out")" != 2 ]; then
    bad "rig-bench: the CSV row does not name the model escaped on one line: $(head -c 400 "$tmp/out")"
else ok "rig-bench shows hostile file names escaped"; fi

# A model that cannot be read (a GLB cut short) is the bench's input failing, not a rigger refusing
# it: named on stderr, its row marked as an error, and the bench exits 1 (it exited 0, the row
# reading "refused" as if the rigger had declined a good model).
head -c 100 "$tmp/ok.glb" >"$tmp/cut.glb"
rfv rig-bench -r general "$tmp/cut.glb"
if [ "$code" = 2 ] && grep -q "no rigger plugin found" "$tmp/err"; then
    skipped "rig-bench on a model cut short" "no rigger plugin built"
elif [ "$code" != 1 ]; then bad "rig-bench on a model cut short: exit $code, expected 1"
elif ! grep -qF "cut.glb: cannot read the model: " "$tmp/err"; then bad "rig-bench: the unreadable model is not named"
elif ! grep -qF ',"error: cannot read the model: ' "$tmp/out"; then bad "rig-bench: the row is not an error: $(tail -1 "$tmp/out")"
else ok "rig-bench on a model cut short: an error, exit 1"; fi

# A rigger plugin whose skin names a joint past its skeleton (tests/fixtures/fx_rigger.c): rig-bench
# says so in the row's status, its skin columns empty; it read past its tables and printed "ok".
rigged="${RF_DATA_DIR:-}/models/RiggedFigure.glb"
if [ -f "$rigged" ]; then
    rfv --plugin-path "$build/tests/fixtures/rigger/.libs" rig-bench -r fx-bad-index "$rigged"
    if [ "$code" != 0 ]; then bad "rig-bench on a rigger with a bad skin index: exit $code"
    elif ! grep -qF ',nan,nan,nan,0,' "$tmp/out" ||
        ! grep -qF '"the rigger'"'"'s skin names joint 9 at vertex 0, of 3 joints"' "$tmp/out"; then
        bad "rig-bench does not report the rigger's bad skin index: $(tail -1 "$tmp/out")"
    else ok "rig-bench reports a rigger's skin index past its skeleton"; fi
else
    skipped "rig-bench on a rigger with a bad skin index" "$rigged not found (RF_DATA_DIR)"
fi

# ---- joint names that repeat ----
cat >"$tmp/dup.bvh" <<'EOF'
HIERARCHY
ROOT a
{
OFFSET 0 0 0
CHANNELS 1 Zrotation
JOINT b
{
OFFSET 0 1 0
CHANNELS 1 Zrotation
End Site
{
OFFSET 0 1 0
}
}
JOINT b
{
OFFSET 1 0 0
CHANNELS 1 Zrotation
End Site
{
OFFSET 1 0 0
}
}
}
MOTION
Frames: 1
Frame Time: 0.1
0 0 0
EOF
row "BVH joint name repeated" 1 "dup.bvh:15: duplicate joint name 'b' (first declared on line 6)" \
    "$tmp/dup.bvh" "$o.glb"
cat >"$tmp/dup.gltf" <<'EOF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "a", "children": [1, 2]}, {"name": "b", "translation": [0, 1, 0]},
           {"name": "b", "translation": [1, 0, 0]}]}
EOF
good "glTF joint name repeated: renamed, with a warning" "$tmp/dup.gltf" "$tmp/dup.bvh.out.bvh" \
    "duplicate joint name 'b' renamed 'b.1'"
rm -f "$tmp/dup.bvh.out.bvh"
rf run "$convert" -p source.path="$tmp/dup.gltf" -p export.path="$tmp/dup.bvh.out.bvh"
[ "$code" = 0 ] && [ -s "$tmp/dup.bvh.out.bvh" ] && [ ! -s "$tmp/err" ] &&
    ok "--quiet: the same conversion prints no warning (errors only)" ||
    bad "--quiet printed a warning (exit $code)"

# ---- hierarchy cycles in glTF node graphs (Assimp importer) ----
cat >"$tmp/cycle.gltf" <<'EOF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "a", "children": [1]}, {"name": "b", "children": [2]},
           {"name": "c", "children": [0]}]}
EOF
row "glTF nodes in a cycle" 1 "has recursive reference to itself" "$tmp/cycle.gltf" "$o.bvh"
cat >"$tmp/self.gltf" <<'EOF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "a", "children": [0]}]}
EOF
row "glTF node that is its own child" 1 "has recursive reference to itself" "$tmp/self.gltf" "$o.bvh"
cat >"$tmp/badchild.gltf" <<'EOF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "a", "children": [7]}]}
EOF
row "glTF child index out of range" 1 "badchild.gltf: Assimp cannot read it" "$tmp/badchild.gltf" "$o.bvh"

# ---- nesting deep enough to overflow a naive recursive parser ----
{
    printf 'HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n'
    awk -v n="$deep" 'BEGIN { for (i = 1; i < n; i++) printf "JOINT j%d\n{\nOFFSET 0 1 0\nCHANNELS 0\n", i }'
    printf 'End Site\n{\nOFFSET 0 1 0\n}\n'
    awk -v n="$deep" 'BEGIN { for (i = 0; i < n; i++) print "}" }'
    printf 'MOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n'
} >"$tmp/deep.bvh"
good "$deep nested BVH joints read and write (BVH)" "$tmp/deep.bvh" "$tmp/deep-out.bvh"
good "$deep nested BVH joints write as GLB" "$tmp/deep.bvh" "$tmp/deep.glb"
good "$deep nested glTF nodes read through Assimp (deep recursion on a sized stack)" \
    "$tmp/deep.glb" "$tmp/deep-back.bvh"
rm -f "$tmp"/deep*

# ---- huge declared frame counts with little data ----
bvh1 0 "0 1 2" 0.1 | sed 's/^Frames: 2$/Frames: 5000000000/' >"$tmp/frames-over.bvh"
row "Frames beyond the 32-bit range" 1 "expected a whole number of frames from 0 to" \
    "$tmp/frames-over.bvh" "$o.glb"
bvh1 0 "0 1 2" 0.1 | sed 's/^Frames: 2$/Frames: 4000000/' >"$tmp/frames-huge.bvh"
row "Frames: 4000000 with two frames of data" 1 \
    "'Frames: 4000000' is more than the rest of the file can hold" "$tmp/frames-huge.bvh" "$o.glb"

# Motion is frames x joints whatever the file holds: a few megabytes can ask for hundreds of
# gigabytes. Each importer refuses beyond half of the machine's memory before allocating; the
# rows run under a 4 GB address-space limit, so a regression fails instead of swamping the machine
# (not in a sanitizer build: ASan reserves terabytes of address space for its shadow memory).
limit_address_space() {
    grep -q 'fsanitize=address' "$build/Makefile" 2>/dev/null || ulimit -v 4000000
}
{
    printf 'HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 0\n'
    awk 'BEGIN { for (i = 1; i < 3000; i++) printf "JOINT j%d\n{\nOFFSET 0 1 0\nCHANNELS 0\n", i }'
    printf 'End Site\n{\nOFFSET 0 1 0\n}\n'
    awk 'BEGIN { for (i = 0; i < 3000; i++) print "}" }'
    printf 'MOTION\nFrames: 4000000\nFrame Time: 0.1\n'
    head -c 4000000 /dev/zero | tr '\0' '\n'
} >"$tmp/wide.bvh"
(limit_address_space; row "3000 joints x 4 million empty frames (4 MB of BVH)" 1 \
    "'Frames: 4000000' of 3000 joints would take 336.0 GB of memory, more than half of this machine's" \
    "$tmp/wide.bvh" "$o.glb"; echo "$pass $fail" >"$tmp/counts")
read -r pass fail <"$tmp/counts"
rm -f "$tmp/wide.bvh"
printf '{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "hips", "children": [1]}, {"name": "spine", "translation": [0, 1, 0]}],
 "buffers": [{"uri": "data:application/octet-stream;base64,AAAAAChrbk4AAAAAAAAAAAAAAAAAAIA/AAAAAIEENT8AAAAAgQQ1Pw==", "byteLength": 40}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 8}, {"buffer": 0, "byteOffset": 8, "byteLength": 32}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1e9]},
               {"bufferView": 1, "componentType": 5126, "count": 2, "type": "VEC4"}],
 "animations": [{"name": "forever", "samplers": [{"input": 0, "output": 1}],
                 "channels": [{"sampler": 0, "target": {"node": 1, "path": "rotation"}}]}]}\n' >"$tmp/forever.gltf"
(limit_address_space; row "a 1 KB glTF clip that lasts 30 years" 1 \
    "clip 'forever' (1e+09 s at 30 fps" "$tmp/forever.gltf" "$o.bvh"; echo "$pass $fail" >"$tmp/counts")
read -r pass fail <"$tmp/counts"
grep -q "more than half of this machine's" "$tmp/err" && ok "... refused for its memory, before allocating" ||
    bad "the 30-year clip was not refused for its memory"

# ---- unreadable input ----
mkdir "$tmp/folder.bvh"
row "a folder named .bvh" 1 "folder.bvh: not a regular file" "$tmp/folder.bvh" "$o.glb"
mkfifo "$tmp/fifo.bvh" "$tmp/fifo.glb"
row "a FIFO named .bvh (no hang)" 1 "fifo.bvh: not a regular file" "$tmp/fifo.bvh" "$o.glb"
row "a FIFO named .glb (no hang)" 1 "fifo.glb: not a regular file" "$tmp/fifo.glb" "$o.bvh"
row "a missing input" 1 "none.bvh" "$tmp/none.bvh" "$o.glb"
# A file name that is not UTF-8 (Latin-1 from an old archive) cannot go into a pipeline, which is
# JSON: every command that builds one says so, naming the file with the byte escaped, and never
# fails without a word.
latin="$tmp/h$(printf '\351')ros"
cp "$tmp/ok.bvh" "$latin.bvh"
row "run: an input name that is not UTF-8" 3 "source.path=$tmp/h\xe9ros.bvh': expected UTF-8" \
    "$latin.bvh" "$o.glb"
for cmd in "inspect 1" "map 3" "rig-bench 1"; do
    set -- $cmd
    case $1 in
    map) rf map --explain "$latin.bvh" "$tmp/ok.bvh" ;;
    rig-bench) rf rig-bench "$latin.bvh" ;;
    *) rf inspect "$latin.bvh" ;;
    esac
    [ "$code" = "$2" ] && grep -qF "rigflow $1: $tmp/h\xe9ros.bvh: expected a file name in UTF-8" "$tmp/err" &&
        ok "$1: a file name that is not UTF-8 is refused by name" ||
        bad "$1: a file name that is not UTF-8: exit $code, expected $2 and the name escaped"
done
# The same parameter given twice on one command line (a slip for another parameter, as
# -p target.path=... where source.path was meant) is refused, naming both values: it ran with the
# last one, silently.
rm -rf "$tmp/o" && mkdir -p "$tmp/o"
rf run "$convert" -p source.path="$tmp/ok.bvh" -p source.path="$tmp/ok2.bvh" -p export.path="$o.glb"
[ "$code" = 3 ] && grep -qF "source.path given twice" "$tmp/err" && grep -qF "ok2.bvh" "$tmp/err" &&
    [ -z "$(leftovers "$tmp/o")" ] && ok "a parameter given twice with -p" ||
    bad "a parameter given twice with -p: exit $code, expected 3 naming both values"
mkfifo "$tmp/fifo.json"
if [ -f "$src/pipelines/map-edit.json" ]; then # a mapping file of fixes (plugins/mapping-file)
    rm -rf "$tmp/o" && mkdir -p "$tmp/o"
    rf run "$src/pipelines/map-edit.json" -p source.path="$tmp/ok.bvh" -p target.path="$tmp/ok.bvh" \
        -p edit.path="$tmp/fifo.json" -p save.path="$o.json"
    [ "$code" = 1 ] && grep -q "fifo.json: not a regular file" "$tmp/err" && [ -z "$(leftovers "$tmp/o")" ] &&
        ok "a FIFO as the mapping file (no hang)" || bad "a FIFO as the mapping file (exit $code)"
else
    skipped "a FIFO as the mapping file" "no pipelines/map-edit.json in this tree"
fi
cp "$tmp/ok.bvh" "$tmp/locked.bvh" && chmod 000 "$tmp/locked.bvh"
if [ "$(id -u)" = 0 ]; then
    skipped "input without read permission" "running as root, who reads it anyway (the folder and FIFO rows cover refusals)"
else
    row "input without read permission" 1 "Permission denied" "$tmp/locked.bvh" "$o.glb"
fi

# ---- output folder missing or not writable ----
# (a missing output folder: test_cli.sh "unwritable output folder fails the run" and
# test_pipeline.c missing_output_folder_reported)
echo "a file" >"$tmp/plainfile"
rf run "$convert" -p source.path="$tmp/ok.bvh" -p export.path="$tmp/plainfile/out.glb"
[ "$code" = 1 ] && grep -q "plainfile: Not a directory" "$tmp/err" && [ "$(cat "$tmp/plainfile")" = "a file" ] &&
    ok "output folder is a regular file" || bad "output folder is a regular file (exit $code)"
mkdir -p "$tmp/ro" && chmod 555 "$tmp/ro"
if [ "$(id -u)" = 0 ]; then
    skipped "output folder without write permission" "running as root, who writes anyway (the regular-file row covers it)"
else
    rf run "$convert" -p source.path="$tmp/ok.bvh" -p export.path="$tmp/ro/out.glb"
    [ "$code" = 1 ] && grep -q "Permission denied" "$tmp/err" && [ -z "$(leftovers "$tmp/ro")" ] &&
        ok "output folder without write permission" || bad "output folder without write permission"
fi

# ---- a write that fails midway ----
big="${RF_DATA_DIR:-}/bvh/cmu_01_01.bvh"
[ -f "$big" ] || big="$tmp/ok.bvh"
for ext in bvh glb gltf; do # a file size limit: the write fails with EFBIG after 4 KiB
    mkdir -p "$tmp/lim"
    (trap '' XFSZ; ulimit -f 4; "$rigflow" --quiet run "$convert" -p source.path="$big" \
        -p export.path="$tmp/lim/out.$ext" >"$tmp/out" 2>"$tmp/err")
    code=$?
    if [ "$big" = "$tmp/ok.bvh" ]; then
        skipped "file size limit hit while writing .$ext" "no large sample (RF_DATA_DIR)"
    elif [ "$code" = 1 ] && grep -q "File too large" "$tmp/err" && [ -z "$(leftovers "$tmp/lim")" ]; then
        ok "file size limit hit while writing .$ext: failed, nothing left"
    else bad "file size limit hit while writing .$ext: exit $code, left '$(leftovers "$tmp/lim")'"; fi
done
# a full filesystem: a 64 KiB tmpfs, mounted directly as root or in a user namespace otherwise
mkdir -p "$tmp/full"
fill_and_run() { # runs inside the mount namespace
    mount -t tmpfs -o size=64k rf-full "$1" || exit 3
    head -c 40000 /dev/zero >"$1/ballast" 2>/dev/null
    "$rigflow" --quiet run "$convert" -p source.path="$2" -p export.path="$1/out.$3"
    echo "exit $?" >"$4"
    ls -A "$1" | grep -v '^ballast$' >>"$4"
    umount "$1"
}
export -f fill_and_run
export rigflow convert
for ext in bvh glb; do
    : >"$tmp/full.res"
    if [ "$(id -u)" = 0 ]; then runner=(unshare -m); else runner=(unshare -rm); fi
    if ! "${runner[@]}" true 2>/dev/null; then
        skipped "full filesystem while writing .$ext" "cannot make a mount namespace here"; continue
    fi
    "${runner[@]}" bash -c 'fill_and_run "$@"' _ "$tmp/full" "$big" "$ext" "$tmp/full.res" 2>"$tmp/err"
    if [ "$(head -1 "$tmp/full.res")" = "" ]; then
        skipped "full filesystem while writing .$ext" "cannot mount a tmpfs here"
    elif [ "$big" = "$tmp/ok.bvh" ]; then
        skipped "full filesystem while writing .$ext" "no large sample (RF_DATA_DIR)"
    elif [ "$(cat "$tmp/full.res")" = "exit 1" ] && grep -q "No space left on device" "$tmp/err"; then
        ok "full filesystem while writing .$ext: failed with ENOSPC, nothing left"
    else bad "full filesystem while writing .$ext: $(tr '\n' ' ' <"$tmp/full.res")"; fi
done

# ---- plugins: missing, failing init, loaded from where ----
# (a pipeline naming a missing plugin: test_pipeline.c unknown_type_says_plugin_not_installed;
# SIGINT leaving no partial file: test_cli.sh "interrupted run left no file")
fixtures="$build/tests/fixtures/.libs"
cat >"$tmp/fixture.json" <<'EOF'
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "s", "type": "test.source"},
  {"id": "w", "type": "test.sink", "params": {"path": "o/out.txt"}, "inputs": {"in": "s.value"}}]}
EOF
mkdir -p "$tmp/initfail" "$tmp/o" && cp "$fixtures/fx_initfail.so" "$tmp/initfail/"
RIGFLOW_PLUGIN_PATH= rfv --plugin-path "$tmp/initfail" run "$tmp/fixture.json"
[ "$code" = 3 ] && grep -q "plugin failed to initialise: the fixture's licence file is missing" "$tmp/err" &&
    grep -q "plugin not installed: test.source" "$tmp/err" && [ -z "$(leftovers "$tmp/o")" ] &&
    ok "a plugin that fails init is refused and its node types are not there" ||
    bad "a plugin that fails init (exit $code)"

# A pipeline is data: a type or key naming a library never loads it. The library would leave a
# marker file from its constructor if it were ever loaded.
cc=${CC:-cc}
printf '#include <stdio.h>\n__attribute__((constructor)) static void rf_evil(void)\n{ FILE *f = fopen("%s", "w"); if (f) fclose(f); }\nconst int rigflow_plugin_entry;\n' \
    "$tmp/LOADED" >"$tmp/evil.c"
if $cc -shared -fPIC -o "$tmp/evil.so" "$tmp/evil.c" 2>"$tmp/err"; then
    for type in "$tmp/evil.so" "evil.so" "evil" "../$(basename "$tmp")/evil.so"; do
        printf '{"format": "rigflow.pipeline", "version": 1, "nodes": [{"id": "x", "type": "%s"}]}\n' \
            "$type" >"$tmp/evil.json"
        rf run "$tmp/evil.json"
        [ "$code" = 3 ] && grep -q "plugin not installed" "$tmp/err" && [ ! -e "$tmp/LOADED" ] &&
            ok "a node type naming a library ($type) loads nothing" || bad "type $type loaded or misreported"
    done
    printf '{"format": "rigflow.pipeline", "version": 1, "plugins": ["%s"], "nodes": [{"id": "x", "type": "test.source", "plugin": "%s"}]}\n' \
        "$tmp/evil.so" "$tmp/evil.so" >"$tmp/evil.json"
    rf run "$tmp/evil.json"
    [ "$code" = 3 ] && grep -q "unknown key 'plugins'" "$tmp/err" && grep -q "unknown key 'plugin'" "$tmp/err" &&
        [ ! -e "$tmp/LOADED" ] && ok "plugin keys in a pipeline are refused, nothing loaded" ||
        bad "plugin keys in a pipeline"
    RIGFLOW_PLUGIN_PATH= rf --plugin-path "$tmp/nothere" run "$tmp/evil.json"
    [ ! -e "$tmp/LOADED" ] && ok "the pipeline's own folder is not a plugin folder" || bad "pipeline folder searched"
else
    skipped "pipelines naming libraries" "no C compiler ($cc) to build the marker library"
fi

# Plugin folders and files others may write to are refused (end to end; unit: test_plugins.c).
mkdir -p "$tmp/shared"
cp "$fixtures/fx_good.so" "$tmp/shared/"
chmod 777 "$tmp/shared"
RIGFLOW_PLUGIN_PATH= rfv --plugin-path "$tmp/shared" run "$tmp/fixture.json"
[ "$code" = 3 ] && grep -q "shared: plugin folder refused: it is writable by other users" "$tmp/err" &&
    grep -q "plugin not installed: test.source" "$tmp/err" &&
    ok "a plugin folder writable by others is refused with a warning" || bad "world-writable folder (exit $code)"
chmod 755 "$tmp/shared" && chmod 666 "$tmp/shared/fx_good.so"
RIGFLOW_PLUGIN_PATH= rfv --plugin-path "$tmp/shared" run "$tmp/fixture.json"
[ "$code" = 3 ] && grep -q "fx_good.so: plugin refused: the file is writable by other users" "$tmp/err" &&
    ok "a plugin file writable by others is refused with a warning" || bad "world-writable plugin file (exit $code)"

# ---- references inside a model resolve only inside its folder ----
m="$tmp/model"
mkdir -p "$m"
python3 -c 'import struct, sys; sys.stdout.buffer.write(struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0))' \
    >"$tmp/secret.bin" 2>/dev/null || printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0' >"$tmp/secret.bin"
cp "$tmp/secret.bin" "$m/inside.bin"
ln -s ../secret.bin "$m/link.bin"
gltf_with_buffer() { # gltf_with_buffer URI: a skeleton and a mesh whose vertices are in URI
    printf '{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "hips", "children": [1]}, {"name": "spine", "translation": [0, 1, 0], "children": [2]},
           {"name": "m", "mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]}],
 "buffers": [{"uri": "%s", "byteLength": 36}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}]}\n' "$1"
}
# traced ARGS...: runs the command under strace when it can, so rows can check what was opened;
# not --quiet: the rows read the refusals, which are warnings.
tracing=no
[ -z "${RF_RIGFLOW:-}" ] && strace -f -qq -o /dev/null true 2>/dev/null && tracing=yes
traced() {
    if [ "$tracing" = yes ]; then
        # LeakSanitizer cannot run under ptrace: a sanitizer build checks leaks in the other rows.
        ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" strace -f -qq \
            -e trace=open,openat -o "$tmp/trace" "$rigflow" "$@" >"$tmp/out" 2>"$tmp/err"
    else
        : >"$tmp/trace"
        "$rigflow" "$@" >"$tmp/out" 2>"$tmp/err"
    fi
    code=$?
}
# never_opened NAME FILE: FILE (outside the model's folder) was never opened.
never_opened() {
    if [ "$tracing" != yes ]; then skipped "$1: nothing opened outside" "strace unavailable (or under valgrind)"
    elif grep -F "\"$2\"" "$tmp/trace" | grep -vq '= -1'; then bad "$1: $2 was opened"
    else ok "$1: nothing opened outside"; fi
}
gltf_with_buffer inside.bin >"$m/inside.gltf"
good "glTF buffer beside the model is read" "$m/inside.gltf" "$tmp/inside.bvh"
gltf_with_buffer ../secret.bin >"$m/up.gltf"
traced run "$convert" -p source.path="$m/up.gltf" -p export.path="$o.bvh"
[ "$code" = 1 ] && grep -q "refused to read $m/../secret.bin: outside the model's folder" "$tmp/err" &&
    ok "glTF buffer URI ../secret.bin is refused, and named" || bad "glTF buffer ../ (exit $code)"
never_opened "glTF buffer URI ../" "$tmp/secret.bin"
gltf_with_buffer "$tmp/secret.bin" >"$m/abs.gltf"
traced run "$convert" -p source.path="$m/abs.gltf" -p export.path="$o.bvh"
[ "$code" = 1 ] && grep -q "could not open referenced file \"$tmp/secret.bin\"" "$tmp/err" &&
    ok "glTF buffer URI with an absolute path is not read" || bad "glTF buffer absolute (exit $code)"
never_opened "glTF buffer absolute URI" "$tmp/secret.bin"
gltf_with_buffer link.bin >"$m/link.gltf"
traced run "$convert" -p source.path="$m/link.gltf" -p export.path="$o.bvh"
[ "$code" = 1 ] && grep -q "refused to read $m/link.bin: outside the model's folder" "$tmp/err" &&
    ok "glTF buffer through a symbolic link leading out is refused" || bad "glTF buffer symlink (exit $code)"
never_opened "glTF buffer through a link" "$tmp/secret.bin"
cp "$tmp/secret.bin" "$tmp/secret.png"
printf '{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "hips", "children": [1]}, {"name": "spine", "translation": [0, 1, 0]}],
 "images": [{"uri": "../secret.png"}, {"uri": "%s"}], "textures": [{"source": 0}, {"source": 1}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}]}\n' "$tmp/secret.png" >"$m/img.gltf"
traced run "$convert" -p source.path="$m/img.gltf" -p export.path="$tmp/img.bvh"
[ "$code" = 0 ] && ok "glTF image URIs (../ and absolute) do not stop the import" || bad "glTF images (exit $code)"
never_opened "glTF image URIs ../ and absolute" "$m/../secret.png"
never_opened "glTF image URI absolute" "$tmp/secret.png"

# Ogre: a mesh names its skeleton file
cat >"$tmp/outside.skeleton.xml" <<'EOF'
<skeleton><bones><bone id="0" name="root"><position x="0" y="0" z="0"/><rotation angle="0"><axis x="1" y="0" z="0"/></rotation></bone><bone id="1" name="tip"><position x="0" y="1" z="0"/><rotation angle="0"><axis x="1" y="0" z="0"/></rotation></bone></bones><bonehierarchy><boneparent bone="tip" parent="root"/></bonehierarchy></skeleton>
EOF
ogre_mesh() { # ogre_mesh SKELETON: an Ogre XML mesh skinned to SKELETON
    printf '<mesh><submeshes><submesh material="m" usesharedvertices="false" use32bitindexes="false" operationtype="triangle_list">
<faces count="1"><face v1="0" v2="1" v3="2"/></faces><geometry vertexcount="3"><vertexbuffer positions="true">
<vertex><position x="0" y="0" z="0"/></vertex><vertex><position x="1" y="0" z="0"/></vertex><vertex><position x="0" y="1" z="0"/></vertex>
</vertexbuffer></geometry><boneassignments><vertexboneassignment vertexindex="0" boneindex="0" weight="1"/>
<vertexboneassignment vertexindex="1" boneindex="1" weight="1"/><vertexboneassignment vertexindex="2" boneindex="1" weight="1"/>
</boneassignments></submesh></submeshes><skeletonlink name="%s"/></mesh>\n' "$1"
}
cp "$tmp/outside.skeleton.xml" "$m/inside.skeleton.xml"
ogre_mesh inside.skeleton.xml >"$m/in.mesh.xml"
good "Ogre skeleton beside the mesh is read" "$m/in.mesh.xml" "$tmp/ogre.bvh"
for ref in ../outside.skeleton.xml "$tmp/outside.skeleton.xml"; do
    ogre_mesh "$ref" >"$m/out.mesh.xml"
    traced run "$convert" -p source.path="$m/out.mesh.xml" -p export.path="$o.bvh"
    grep -q "refused to read .*outside.skeleton.xml: outside the model's folder" "$tmp/err" &&
        [ -z "$(leftovers "$(dirname "$o")")" ] &&
        ok "Ogre skeleton link $ref is refused, and named" || bad "Ogre skeleton link $ref (exit $code)"
    never_opened "Ogre skeleton link $ref" "$tmp/outside.skeleton.xml"
done

# OBJ: a material library, whose textures are external files too
printf 'newmtl m\nKd 1 0 0\nmap_Kd ../secret.png\n' >"$tmp/outside.mtl"
printf 'mtllib ../outside.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n' >"$m/up.obj"
traced run "$convert" -p source.path="$m/up.obj" -p export.path="$tmp/mesh.glb"
grep -q "refused to read $m/../outside.mtl: outside the model's folder" "$tmp/err" &&
    ok "OBJ material library ../outside.mtl is refused, and named" || bad "OBJ mtllib ../ (exit $code)"
never_opened "OBJ material library ../" "$tmp/outside.mtl"
printf 'mtllib %s\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n' "$tmp/outside.mtl" >"$m/abs.obj"
traced run "$convert" -p source.path="$m/abs.obj" -p export.path="$tmp/mesh.glb"
never_opened "OBJ material library with an absolute path" "$tmp/outside.mtl"

echo "$pass passed, $fail failed, $skip skipped"
[ "$fail" = 0 ]

#!/usr/bin/env bash
# Nodes processing at once (rigflow run --jobs, doc/pipeline-format.md "Running"): the same
# stdout, stderr and files as one node at a time, whichever node finishes first; a failing node
# among them fails the run with nothing written; node types without RF_NODE_CONCURRENT process
# alone. The fixture's test.say nodes sleep, print lines on host->out and log between them.
set -u
rigflow="${RF_RIGFLOW:-${RF_BUILDDIR:?}/rigflow}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "${RF_SRCDIR:?}/tests/tap.sh"
fixtures="$tmp/plugins" # the good fixture alone: the others are refused, with warnings
mkdir -p "$fixtures" && cp "$RF_BUILDDIR/tests/fixtures/.libs/fx_good.so" "$fixtures/"

# a (slowest), b and c (writes c.txt) read nothing: one group; d reads a and comes after it.
cat >"$tmp/p.json" <<'EOF'
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "a", "type": "test.say", "params": {"text": "A", "delay": 0.3}},
  {"id": "b", "type": "test.say", "params": {"text": "B", "delay": 0.1, "lines": 3}},
  {"id": "c", "type": "test.say", "params": {"text": "C", "path": "c.txt"}},
  {"id": "d", "type": "test.say", "params": {"text": "D", "lines": 1}, "inputs": {"in": "a.value"}}]}
EOF
# run NAME JOBS [ARGS]: in $tmp/NAME, stdout and stderr together to both, then apart to out and
# err, the exit status to code; c writes c.txt there
run() {
    local name=$1 jobs=$2
    shift 2
    mkdir -p "$tmp/$name"
    (cd "$tmp/$name" && "$rigflow" --plugin-path "$fixtures" run "$tmp/p.json" --jobs "$jobs" \
        -p c.path=c.txt "$@" >both 2>&1; rm -f c.txt)
    (cd "$tmp/$name" && "$rigflow" --plugin-path "$fixtures" run "$tmp/p.json" --jobs "$jobs" \
        -p c.path=c.txt "$@" >out 2>err; echo $? >code)
}

# what one node at a time prints, written out by hand
printf 'A 1\nA 2\nB 1\nB 2\nB 3\nC 1\nC 2\nD 1\n' >"$tmp/want_out"
for x in "A 1" "A 2" "B 1" "B 2" "B 3" "C 1" "C 2" "D 1"; do
    echo "rigflow: node '$(echo "${x% *}" | tr 'A-D' 'a-d')': info: ${x% *} logged ${x#* }"
done >"$tmp/want_err"

run serial 1
run par 3
same "$(cat "$tmp/serial/code") $(cat "$tmp/par/code")" "0 0" "both runs succeed"
if cmp -s "$tmp/serial/out" "$tmp/want_out"; then ok "one at a time: stdout in node order"; else bad "one at a time: stdout $(tr '\n' '|' <"$tmp/serial/out")"; fi
if cmp -s "$tmp/serial/err" "$tmp/want_err"; then ok "one at a time: stderr in node order"; else bad "one at a time: stderr $(tr '\n' '|' <"$tmp/serial/err")"; fi
for f in out err both; do
    if cmp -s "$tmp/serial/$f" "$tmp/par/$f"; then ok "--jobs 3: $f byte-identical to --jobs 1"; else bad "--jobs 3: $f differs from --jobs 1: $(tr '\n' '|' <"$tmp/par/$f")"; fi
done
same "$(cat "$tmp/par/c.txt" 2>/dev/null)" "C" "--jobs 3: the concurrent node's file is written"

# the group really runs at once: a, first, waits for the file b makes, which one node at a time
# would never make before a gives up (20 s)
(cd "$tmp/par" && "$rigflow" -q --plugin-path "$fixtures" run "$tmp/p.json" --jobs 3 --profile \
    -p c.path=c.txt -p a.await=sig -p b.signal=sig >/dev/null 2>prof)
same "$?" 0 "--jobs 3: the first node sees a file made by a node after it"
contains "$tmp/par/prof" "profile: nodes a to c at once (3 threads)" "--profile names the group"

# a node of the group fails: in order, b's error ends the run; c, which also ran, leaves nothing
run sfail 1 -p b.fail=true
run pfail 3 -p b.fail=true
same "$(cat "$tmp/sfail/code") $(cat "$tmp/pfail/code")" "1 1" "a failing node fails the run (exit 1)"
contains "$tmp/pfail/err" "node 'b': test.say failed: B asked to fail" "the failed node is named"
for f in out err both; do
    if cmp -s "$tmp/sfail/$f" "$tmp/pfail/$f"; then ok "failed run: $f byte-identical to --jobs 1"; else bad "failed run: $f differs: $(tr '\n' '|' <"$tmp/pfail/$f")"; fi
done
same "$(ls -A "$tmp/pfail" | tr '\n' ' ')" "both code err out " "failed run: no file written, no temporary left"
# the first node of the group fails while the others run
run hfail 3 -p a.fail=true
run hsfail 1 -p a.fail=true
for f in out err both; do
    if cmp -s "$tmp/hsfail/$f" "$tmp/hfail/$f"; then ok "first node failing: $f byte-identical to --jobs 1"; else bad "first node failing: $f differs: $(tr '\n' '|' <"$tmp/hfail/$f")"; fi
done
same "$(ls -A "$tmp/hfail" | tr '\n' ' ')" "both code err out " "first node failing: no file written"

# node types without RF_NODE_CONCURRENT (test.source) process alone
cat >"$tmp/alone.json" <<'EOF'
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "s1", "type": "test.source"}, {"id": "s2", "type": "test.source"}]}
EOF
"$rigflow" -q --plugin-path "$fixtures" run "$tmp/alone.json" --profile >/dev/null 2>"$tmp/prof"
if grep -q "at once" "$tmp/prof"; then bad "unmarked node types processed at once"; else ok "unmarked node types process alone"; fi

expect 0 "describe a node type that may process beside others" -- \
    "$rigflow" --plugin-path "$fixtures" describe test.say
contains "$tmp/out" "processes beside the nodes it does not depend on" "describe says so"
expect 0 "describe one that may not" -- "$rigflow" --plugin-path "$fixtures" describe test.source
contains "$tmp/out" "processes alone" "describe says it processes alone"

# a plugin built against the frozen ABI 1.0 headers (tests/abi-1.0) has no flags: it reads as 0
mkdir -p "$tmp/abi10" && cp "$RF_BUILDDIR/tests/fixtures/.libs/fx_abi10.so" "$tmp/abi10/"
expect 0 "describe a node type of ABI 1.0" -- "$rigflow" --plugin-path "$tmp/abi10" describe abi10.chain
contains "$tmp/out" "processes alone" "a node type built before the flag processes alone"

expect 2 "--jobs 0 is a usage error" -- "$rigflow" --plugin-path "$fixtures" run "$tmp/p.json" --jobs 0
contains "$tmp/err" "expected a count of 1 or more" "--jobs 0 says what it expects"

echo "1..$((pass + fail))"
[ "$fail" = 0 ]

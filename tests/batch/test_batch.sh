#!/usr/bin/env bash
# rigflow batch on the worker pool: output names, a batch with a failing and a crashing job, the
# manifest (checked against sha256sum), resume after a rerun and after kill -9, the lock,
# Ctrl-C; then a real retarget batch on the shared data, each output compared with a lone
# `rigflow run` of the same job.
set -u
rigflow="${RF_RIGFLOW:-${RF_BUILDDIR:?}/rigflow}"
fx="$RF_BUILDDIR/tests/batch/.libs"
pipeline="${RF_SRCDIR:?}/tests/batch/copy.json"
tmp=$(mktemp -d)
bg=""
cleanup() { [ -n "$bg" ] && kill -9 $bg 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
. "$RF_SRCDIR/tests/tap.sh"
batch() { "$rigflow" --plugin-path "$fx" batch "$pipeline" "$@"; }

# ---- usage errors ----
expect 0 "batch --help" -- "$rigflow" batch --help
contains "$tmp/out" "Exit status" "--help documents exit codes"
expect 2 "batch without --over" -- batch
contains "$tmp/err" "at least one --over" "the missing --over is named"
expect 2 "a glob that matches nothing" -- batch --over "copy.input=$tmp/none/*.txt" --out "$tmp/o"
contains "$tmp/err" "matches no file" "the empty glob is named"
expect 2 "a malformed --over" -- batch --over "nodot=$tmp/x" --out "$tmp/o"
mkdir -p "$tmp/in"
echo hello >"$tmp/in/a.txt"
expect 3 "an invalid pipeline fails before any job" -- batch --over "copy.nosuch=$tmp/in/*.txt" \
    --out "$tmp/o"
[ ! -e "$tmp/o" ] && ok "an invalid pipeline creates no output folder" ||
    bad "an invalid pipeline created $tmp/o"

expect 2 "a batch that would overwrite its own input" -- batch --over "copy.input=$tmp/in/*.txt" \
    --out "$tmp/in"
contains "$tmp/err" "would overwrite its input $tmp/in/a.txt" "the refusal names the input"
same "$(cat "$tmp/in/a.txt")" hello "the input is untouched"

# ---- names: extension dropped, kept when stems collide, escaped, cross product ----
mkdir -p "$tmp/names/sub" "$tmp/tags"
for f in x.txt x.dat "my clip.txt" .hidden.txt sub/y.txt; do echo hi >"$tmp/names/$f"; done
echo t >"$tmp/tags/t1.cfg"
echo t >"$tmp/tags/t2.cfg"
expect 0 "--list" -- batch --over "copy.input=$tmp/names/*" --out "$tmp/o" --list
same "$(cut -f1 "$tmp/out" | tr '\n' ' ')" "my%20clip.txt x.dat x.txt " \
    "stems that collide keep their extensions; other bytes are escaped"
expect 0 "--list, nested" -- batch --over "copy.input=$tmp/names/*/*.txt" --over \
    "copy.tag=$tmp/tags/*.cfg" --out "$tmp/o" --list
same "$(cut -f1 "$tmp/out" | tr '\n' ' ')" "sub+y@t1 sub+y@t2 " "folders and the cross product"
same "$(cut -f2 "$tmp/out" | head -1)" "$tmp/o/sub+y@t1.txt" "the output keeps the pipeline's extension"
expect 0 "--list, a leading dot" -- batch --over "copy.input=$tmp/names/.h*" --out "$tmp/o" --list
same "$(cut -f1 "$tmp/out")" "%2Ehidden" "a leading dot is escaped (no hidden outputs)"

# ---- a batch: four good jobs, one failing, one crashing ----
in="$tmp/lib" out="$tmp/run"
mkdir -p "$in"
for i in 1 2 3 4; do echo "clip $i" >"$in/good$i.txt"; done
echo "fail please" >"$in/bad.txt"
# Under valgrind (make valgrind) the crash is a SIGKILL, as from the OOM killer: valgrind reports
# an abort as an error of its own.
if [ -n "${RF_VG_LOGS:-}" ]; then echo "kill please" >"$in/boom.txt"; sig="9"; else
    echo "crash please" >"$in/boom.txt"; sig="6"; fi
expect 1 "a batch with a failing and a crashing job exits 1" -- batch --over "copy.input=$in/*.txt" \
    --out "$out" -j 2
contains "$tmp/out" "6 jobs: 4 done, 1 failed, 1 crashed, 0 skipped" "the summary counts each outcome"
contains "$tmp/out" "failed bad: " "the summary names the failed job"
contains "$tmp/out" "bad.txt asks to fail" "with its error"
contains "$tmp/out" "crashed boom: the worker process died: killed by signal $sig" \
    "the crash is reported as such, with the signal"
for i in 1 2 3 4; do
    printf 'copied by test.copy\nclip %s\n' "$i" | cmp -s - "$out/good$i.txt" ||
        bad "good$i.txt: wrong or missing output"
done
ok "every good job wrote its output (checked byte for byte)"
[ ! -e "$out/bad.txt" ] && [ ! -e "$out/boom.txt" ] && ok "failed jobs leave no output" ||
    bad "a failed job left an output"
same "$(ls -A "$out" | grep -c '\.rf-')" 0 "no temporary file is left"
contains "$out/rigflow-batch/logs/boom.log" "crashing as" "the crashed job's log keeps what it printed"
same "$(wc -l <"$out/rigflow-batch/manifest.jsonl" | tr -d ' ')" 6 "one manifest line per job"
want=$(sha256sum "$out/good3.txt" | cut -d' ' -f1)
contains "$out/rigflow-batch/manifest.jsonl" "\"sha256\":\"$want\"" "the manifest's SHA-256 is sha256sum's"
size=$(stat -c %s "$in/good3.txt")
contains "$out/rigflow-batch/manifest.jsonl" "\"path\":\"$in/good3.txt\",\"size\":$size" \
    "the manifest records the input's size"
contains "$out/rigflow-batch/manifest.jsonl" "\"status\":\"crashed\"" "the crash is in the manifest"

# ---- rerun: finished jobs are skipped, failed ones redone, changed ones redone ----
before=$(stat -c %Y.%y "$out/good1.txt")
sleep 0.01
expect 1 "a rerun" -- batch --over "copy.input=$in/*.txt" --out "$out" -j 2
contains "$tmp/out" "0 done, 1 failed, 1 crashed, 4 skipped" "a rerun skips the finished jobs"
same "$(stat -c %Y.%y "$out/good1.txt")" "$before" "a skipped job's output is untouched"
echo "clip 2, changed" >"$in/good2.txt"
echo "fixed" >"$in/bad.txt"
rm "$in/boom.txt"
expect 0 "a rerun after fixing the inputs" -- batch --over "copy.input=$in/*.txt" --out "$out"
contains "$tmp/out" "5 jobs: 2 done, 0 failed, 0 crashed, 3 skipped" \
    "a changed input and a fixed failure are redone, nothing else"
contains "$out/good2.txt" "changed" "the changed input's output is new"
rm "$out/good4.txt"
expect 0 "a rerun after an output was deleted" -- batch --over "copy.input=$in/*.txt" --out "$out"
contains "$tmp/out" "1 done, 0 failed, 0 crashed, 4 skipped" "a missing output is redone"
expect 0 "a rerun with another parameter" -- batch --over "copy.input=$in/*.txt" --out "$out" \
    -p copy.tag=v2
contains "$tmp/out" "5 done, 0 failed, 0 crashed, 0 skipped" "changed parameters redo every job"

cp "$pipeline" "$tmp/copy.json"
expect 0 "a batch of a pipeline copy" -- "$rigflow" --plugin-path "$fx" batch "$tmp/copy.json" \
    --over "copy.input=$in/*.txt" --out "$tmp/pcopy"
sed -i 's/"description": "/"description": "edited: /' "$tmp/copy.json"
expect 0 "a rerun after the pipeline was edited" -- "$rigflow" --plugin-path "$fx" batch \
    "$tmp/copy.json" --over "copy.input=$in/*.txt" --out "$tmp/pcopy"
contains "$tmp/out" "5 done, 0 failed, 0 crashed, 0 skipped" "an edited pipeline redoes every job"
expect 0 "--list --shard 1/3" -- batch --over "copy.input=$in/*.txt" --out "$out" --list --shard 1/3
same "$(cut -f1 "$tmp/out" | tr '\n' ' ')" "good1 good4 " "a shard holds the jobs whose index modulo N is I (bad good1 good2 good3 good4: 1 and 4)"
expect 2 "a bad --shard" -- batch --over "copy.input=$in/*.txt" --out "$out" --shard 3/3
contains "$tmp/err" "expected I/N with 0 <= I < N" "--shard says what it expects"

# ---- --job-timeout: a job that runs too long is stopped, the others finish ----
mkdir -p "$tmp/hang"
echo "sleep 30" >"$tmp/hang/hang.txt"
echo "quick" >"$tmp/hang/quick.txt"
limit=1 # seconds: the quick job must finish within it, under valgrind on a loaded machine too
[ -n "${RF_VG_LOGS:-}" ] && limit=5
expect 1 "--job-timeout stops a job that runs too long" -- batch --over "copy.input=$tmp/hang/*.txt" \
    --out "$tmp/hang-out" -j 2 --job-timeout "$limit"
contains "$tmp/out" "1 done, 1 failed, 0 crashed" "the overdue job is recorded as failed, the other done"
contains "$tmp/out" "failed hang: stopped after running longer than --job-timeout $limit s" \
    "the summary says why"
[ ! -e "$tmp/hang-out/hang.txt" ] && [ "$(ls -A "$tmp/hang-out" | grep -c '\.rf-')" = 0 ] &&
    ok "the stopped job left no file" || bad "the stopped job left a file"

# ---- the lock, and kill -9 in the middle ----
# Three jobs finish at once; the others wait for a gate file that appears only after the kill,
# so the kill lands mid-batch however slow the machine (or valgrind) is.
in="$tmp/gated" out="$tmp/killed"
mkdir -p "$in"
for i in 01 02 03; do echo "quick $i" >"$in/s$i.txt"; done
for i in 04 05 06 07 08 09 10; do echo "gate $tmp/gate" >"$in/s$i.txt"; done
"$rigflow" --plugin-path "$fx" batch "$pipeline" --over "copy.input=$in/*.txt" --out "$out" -j 2 \
    >"$tmp/bg.out" 2>&1 &
bg=$!
# waits (up to 60 s) until FILE has at least N lines
wait_lines() { for _ in $(seq 1200); do [ "$(cat "$1" 2>/dev/null | wc -l)" -ge "$2" ] && return; sleep 0.05; done; }
wait_lines "$out/rigflow-batch/lock" 1
expect 5 "a second batch on the same folder is refused" -- batch --over "copy.input=$in/*.txt" \
    --out "$out"
contains "$tmp/err" "in use by another batch (pid $bg on" "the refusal names the holding process"
expect 5 "a shard of a Slurm array on the same folder is refused too" -- batch \
    --over "copy.input=$in/*.txt" --out "$out" --shard 0/2
wait_lines "$out/rigflow-batch/manifest.jsonl" 3
expect 6 "--status while a local batch runs" -- "$rigflow" batch --status "$out"
contains "$tmp/out" "a batch runs on this folder now (pid $bg on" "--status names the running batch"
kill -9 "$bg"
wait "$bg" 2>/dev/null
bg=""
sleep 0.4 # the workers see their parent die and stop
[ -n "${RF_VG_LOGS:-}" ] && sleep 3 # valgrind takes a while to end a process
done_before=$(grep -c '"status":"done"' "$out/rigflow-batch/manifest.jsonl")
same "$done_before" 3 "killed mid-batch: the three quick jobs are recorded, no waiting one"
lost=0
while read -r line; do
    f=$(sed -n 's/.*"outputs":\[{"path":"\([^"]*\)".*"sha256":"\([0-9a-f]*\)".*/\1 \2/p' <<<"$line")
    [ -n "$f" ] || continue
    [ "$(sha256sum "${f% *}" 2>/dev/null | cut -d' ' -f1)" = "${f#* }" ] || lost=$((lost + 1))
done <"$out/rigflow-batch/manifest.jsonl"
same "$lost" 0 "every recorded output is there, as recorded"
pids=$(sed -n 's/.*"pid":\([0-9]*\).*/\1/p' "$out/rigflow-batch/manifest.jsonl" | sort -u)
alive=0
for p in $pids; do # a zombie is dead (some containers' init never reaps orphans)
    case "$(ps -o stat= -p "$p" 2>/dev/null)" in "" | Z*) ;; *) alive=$((alive + 1)) ;; esac
done
same "$alive" 0 "the workers died with their parent"
touch "$tmp/gate"
expect 0 "the rerun after kill -9" -- batch --over "copy.input=$in/*.txt" --out "$out" -j 2
contains "$tmp/out" "$((10 - done_before)) done, 0 failed, 0 crashed, $done_before skipped" \
    "the rerun does exactly the unrecorded jobs"
same "$(ls "$out" | grep -c '^s.*\.txt$')" 10 "every output exists after the rerun"
same "$(ls -A "$out" | grep -c '\.rf-')" 0 "no temporary file is left"
same "$(grep -c '"status":"done"' "$out/rigflow-batch/manifest.jsonl")" 10 \
    "no job is recorded twice as done"

# ---- --status on a local batch ----
expect 0 "--status of a finished local batch" -- "$rigflow" batch --status "$out"
contains "$tmp/out" "10 jobs: 10 done, 0 failed, 0 running, 0 pending, 0 missing" "--status counts"
expect 2 "--status of a folder that holds no batch" -- "$rigflow" batch --status "$in"
contains "$tmp/err" "is not a batch folder" "--status says why"
expect 2 "--resubmit of a local batch" -- "$rigflow" batch --resubmit "$out"
contains "$tmp/err" "was not submitted to Slurm" "--resubmit says why"

# ---- a manifest that cannot take a record (a file size limit here, a full disk elsewhere) ----
# The record is not left torn (the next one would join it and be lost too), the batch says so
# and exits 1, and the reruns do exactly the unrecorded jobs, once.
if [ -z "${RF_VG_LOGS:-}" ]; then
    mkdir -p "$tmp/limit"
    for i in 1 2 3 4; do echo hi >"$tmp/limit/j$i.txt"; done
    (trap '' XFSZ; ulimit -f 1; batch --over "copy.input=$tmp/limit/*.txt" --out "$tmp/limit-out" -j 1 \
        >"$tmp/out" 2>"$tmp/err")
    same "$?" 1 "a batch whose manifest is full exits 1"
    contains "$tmp/out" "not recorded in the manifest" "the summary says records are missing"
    contains "$tmp/err" "cannot write the manifest: File too large" "the reason is given"
    same "$(tail -c 1 "$tmp/limit-out/rigflow-batch/manifest.jsonl" | od -An -c | tr -d ' ')" '\n' \
        "the manifest ends with a whole line"
    expect 0 "the rerun with room" -- batch --over "copy.input=$tmp/limit/*.txt" --out "$tmp/limit-out"
    expect 0 "a third run" -- batch --over "copy.input=$tmp/limit/*.txt" --out "$tmp/limit-out"
    contains "$tmp/out" "0 done, 0 failed, 0 crashed, 4 skipped" "every record of the rerun was kept"
    printf '{"job":"j1","status":"do' >>"$tmp/limit-out/rigflow-batch/manifest.jsonl" # torn by a crash
    echo edited >"$tmp/limit/j2.txt"
    expect 0 "a run after a crash tore the manifest's last line" -- \
        batch --over "copy.input=$tmp/limit/*.txt" --out "$tmp/limit-out"
    expect 0 "and one more" -- batch --over "copy.input=$tmp/limit/*.txt" --out "$tmp/limit-out"
    contains "$tmp/out" "0 done, 0 failed, 0 crashed, 4 skipped" "the record after a torn line is kept"
fi

# the lock file's text is a file's bytes: what names the holder reaches the terminal escaped
mkdir -p "$tmp/held-in"
echo "sleep 30" >"$tmp/held-in/long.txt"
out="$tmp/held"
"$rigflow" --plugin-path "$fx" batch "$pipeline" --over "copy.input=$tmp/held-in/*.txt" --out "$out" \
    >/dev/null 2>&1 &
bg=$!
wait_lines "$out/rigflow-batch/lock" 1
for _ in $(seq 1200); do [ -e "$out/rigflow-batch/plan.json" ] && break; sleep 0.05; done
printf 'pid 1 \033]0;owned\007 \302\2332J\n' >"$out/rigflow-batch/lock"
"$rigflow" batch --status "$out" >"$tmp/out" 2>"$tmp/err"
"$rigflow" --plugin-path "$fx" batch "$pipeline" --over "copy.input=$tmp/held-in/*.txt" --out "$out" \
    >>"$tmp/out" 2>>"$tmp/err"
# a Slurm submission onto a folder a batch holds is refused before sbatch runs (its tasks would
# only find the folder locked, or overwrite the running batch's outputs)
mkdir -p "$tmp/fakebin"
printf '#!/bin/sh\ntouch "%s/sbatch-ran"\necho 4242\n' "$tmp" >"$tmp/fakebin/sbatch"
chmod +x "$tmp/fakebin/sbatch"
PATH="$tmp/fakebin:$PATH" "$rigflow" --plugin-path "$fx" batch "$pipeline" \
    --over "copy.input=$tmp/held-in/*.txt" --out "$out" --slurm >"$tmp/slurm.out" 2>"$tmp/slurm.err"
same "$?" 5 "--slurm onto a folder a batch holds exits 5"
[ ! -e "$tmp/sbatch-ran" ] && ok "... without running sbatch" || bad "... sbatch was run"
contains "$tmp/slurm.err" "is in use by another batch" "... and says why"
kill -9 "$bg"
wait "$bg" 2>/dev/null
bg=""
if LC_ALL=C grep -q $'[\033\007\233]' "$tmp/out" "$tmp/err"; then
    bad "the lock's text reached the terminal raw: $(cat "$tmp/out" "$tmp/err" | od -c | head -4)"
else
    contains "$tmp/out" 'now (pid 1 \x1b]0;owned\x07 \xc2\x9b2J)' "--status prints the lock's text escaped"
    contains "$tmp/err" 'another batch (pid 1 \x1b]0;owned\x07 \xc2\x9b2J)' "the refusal prints it escaped"
fi

# ---- an output that cannot be read back (a disk error, simulated by tests/batch/fx_eio.c, preloaded) ----
# The job is failed, naming the output and the error; not recorded as done with the hash of
# nothing; its output is removed as a failed job's is; the rerun redoes it.
mkdir -p "$tmp/eio"
echo one >"$tmp/eio/a.txt"
echo two >"$tmp/eio/b.txt"
RF_FX_EIO_PATH="$tmp/eio-out/b.txt" LD_PRELOAD="$RF_BUILDDIR/tests/batch/preload/.libs/fx_eio.so" \
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0" \
    batch --over "copy.input=$tmp/eio/*.txt" --out "$tmp/eio-out" -j 1 >"$tmp/out" 2>"$tmp/err"
same "$?" 1 "a batch with an output it cannot read back exits 1"
contains "$tmp/out" "2 jobs: 1 done, 1 failed" "that job counts as failed"
contains "$tmp/out" "cannot read back its output $tmp/eio-out/b.txt to record it: Input/output error" \
    "the summary names the output and the error"
grep '"job":"b"' "$tmp/eio-out/rigflow-batch/manifest.jsonl" | grep -q '"status":"failed"' &&
    ok "the manifest records it failed" || bad "the manifest does not record b as failed"
[ ! -e "$tmp/eio-out/b.txt" ] && ok "its output is removed" || bad "its output was left"
expect 0 "the rerun without the error" -- batch --over "copy.input=$tmp/eio/*.txt" --out "$tmp/eio-out"
contains "$tmp/out" "1 done, 0 failed, 0 crashed, 1 skipped" "the rerun redoes only that job"

# ---- a job whose log cannot be opened (a folder of its name here; a full disk, permissions) ----
# It is failed naming the log and not run: its output would have gone to the batch's terminal.
mkdir -p "$tmp/nolog" "$tmp/nolog-out/rigflow-batch/logs/b.log"
echo one >"$tmp/nolog/a.txt"
echo "fail loudly" >"$tmp/nolog/b.txt"
expect 1 "a batch with a job whose log cannot be opened exits 1" -- \
    batch --over "copy.input=$tmp/nolog/*.txt" --out "$tmp/nolog-out" -j 1
contains "$tmp/out" "2 jobs: 1 done, 1 failed" "that job counts as failed"
contains "$tmp/out" "cannot open its log $tmp/nolog-out/rigflow-batch/logs/b.log: Is a directory" \
    "the summary names the log and why"
grep -q "asks to fail" "$tmp/out" "$tmp/err" && bad "the job ran with its output on the terminal" ||
    ok "the job did not run onto the batch's terminal"
[ ! -e "$tmp/nolog-out/b.txt" ] && ok "it wrote no output" || bad "it wrote an output"

# ---- --status on damaged or hostile state files: a clear refusal, never a crash ----
state="$tmp/hostile/rigflow-batch"
mkdir -p "$state"
echo '{"pipeline": "p", "out": "o", "jobs": ["a", 7]}' >"$state/plan.json"
expect 2 "--status: a plan whose job is not a name" -- "$rigflow" batch --status "$tmp/hostile"
contains "$tmp/err" "plan.json: job 1 is not a name" "the damaged plan is named"
printf '{"pipeline": "p", "out": "o", "jobs": ["a\\u009b2Jb"]}\n' >"$state/plan.json"
expect 1 "--status: a job name holding a C1 control" -- "$rigflow" batch --status "$tmp/hostile"
if LC_ALL=C grep -q $'\302\233' "$tmp/out"; then bad "--status printed a C1 control raw"
else contains "$tmp/out" 'missing a\xc2\x9b2Jb: no record' "--status escapes C1 controls in names"; fi
echo '{"pipeline": "p", "out": "o", "jobs": ["a", "b"]}' >"$state/plan.json"
for shards in 2000000000 3 -1; do
    echo "{\"shards\": $shards, \"submissions\": [{\"job_id\": \"1\", \"array\": \"0-1\"}]}" \
        >"$state/slurm.json"
    expect 2 "--status: slurm.json claims $shards array tasks for 2 jobs" -- \
        "$rigflow" batch --status "$tmp/hostile"
    contains "$tmp/err" "slurm.json: $shards array tasks for 2 jobs" "the damaged slurm.json is named"
done

# ---- the progress line on a terminal (script(1) gives the batch one) ----
in="$tmp/slow"
mkdir -p "$in"
slow=0.25 # seconds a job: long enough for the progress line and for Ctrl-C to land mid-batch
[ -n "${RF_VG_LOGS:-}" ] && slow=2
for i in 01 02 03 04 05 06 07 08 09 10; do echo "sleep $slow $i" >"$in/s$i.txt"; done
if command -v script >/dev/null && [ -z "${RF_VG_LOGS:-}" ]; then
    script -qec "'$rigflow' --plugin-path '$fx' batch '$pipeline' --over 'copy.input=$in/*.txt' \
        --out '$tmp/tty' -j 2" /dev/null >"$tmp/tty.out" 2>&1
    grep -q $'\r\033\[Krigflow batch: [0-9]*/10 jobs, 0 failed, 0 crashed, .* jobs/s, ETA ' "$tmp/tty.out" &&
        ok "on a terminal, a progress line is redrawn with counts, rate and ETA" ||
        bad "no progress line on a terminal: $(head -c 300 "$tmp/tty.out" | od -c | head -5)"
else
    echo "# SKIP progress on a terminal: script(1) not found, or under valgrind"
fi

# ---- Ctrl-C ----
out="$tmp/interrupted"
"$rigflow" --plugin-path "$fx" batch "$pipeline" --over "copy.input=$in/*.txt" --out "$out" -j 2 \
    >"$tmp/int.out" 2>"$tmp/int.err" &
bg=$!
wait_lines "$out/rigflow-batch/manifest.jsonl" 1
kill -INT "$bg"
wait "$bg"
code=$?
bg=""
same "$code" 130 "Ctrl-C ends the batch with exit 130"
contains "$tmp/int.out" "not finished (interrupted)" "the summary says it was interrupted"
n=$(grep -c '"status":"done"' "$out/rigflow-batch/manifest.jsonl")
same "$(ls "$out" | grep -c '^s.*\.txt$')" "$n" "only finished jobs have outputs"
same "$(ls -A "$out" | grep -c '\.rf-')" 0 "an interrupted job leaves no temporary file"

# ---- SIGINT to one worker alone (not Ctrl-C): its job is interrupted, the batch goes on ----
if [ -z "${RF_VG_LOGS:-}" ] && command -v pgrep >/dev/null; then
    mkdir -p "$tmp/one"
    for i in 1 2 3; do echo "sleep 0.5 $i" >"$tmp/one/w$i.txt"; done
    out="$tmp/one-out"
    "$rigflow" --plugin-path "$fx" batch "$pipeline" --over "copy.input=$tmp/one/*.txt" --out "$out" \
        -j 1 >"$tmp/one.out" 2>"$tmp/one.err" &
    bg=$!
    for _ in $(seq 600); do [ -e "$out/rigflow-batch/logs/w1.log" ] && break; sleep 0.05; done
    kill -INT $(pgrep -P "$bg")
    wait "$bg"
    code=$?
    bg=""
    same "$code" 130 "a job interrupted on its own makes the batch exit 130"
    contains "$tmp/one.out" "3 jobs: 2 done, 0 failed, 0 crashed, 0 skipped (finished before), 1 not finished" \
        "the other jobs on that worker still run, and the summary counts the interrupted one"
fi

# ---- a real retarget batch ----
data="${RF_DATA_DIR:-}"
if [ -f "$data/bvh/cmu_01_01.bvh" ] && [ -f "$data/models/Fox.glb" ]; then
    out="$tmp/retarget"
    expect 0 "retarget 2 clips onto 2 characters" -- "$rigflow" batch \
        "$RF_SRCDIR/pipelines/retarget.json" --over "source.path=$data/bvh/bandai_*k.bvh" \
        --over "target.path=$data/models/[FR][oi][xg]*.glb" -p export.path=.glb --out "$out" -j 2
    same "$(cd "$out" && ls *.glb | tr '\n' ' ')" \
        "bandai_kick@Fox.glb bandai_kick@RiggedFigure.glb bandai_walk@Fox.glb bandai_walk@RiggedFigure.glb " "the retarget outputs"
    expect 0 "the same job run alone" -- "$rigflow" run "$RF_SRCDIR/pipelines/retarget.json" \
        -p source.path="$data/bvh/bandai_walk.bvh" -p target.path="$data/models/RiggedFigure.glb" \
        -p export.path="$tmp/alone.glb"
    cmp -s "$tmp/alone.glb" "$out/bandai_walk@RiggedFigure.glb" &&
        ok "a batch job writes the same bytes as rigflow run" || bad "batch and run outputs differ"
    contains "$out/rigflow-batch/logs/bandai_walk@RiggedFigure.log" "measure: direction fidelity" \
        "a job's printed report is in its log"
else
    echo "# SKIP real retarget batch: no shared data in RF_DATA_DIR='${RF_DATA_DIR:-}'"
fi

echo "# $pass passed, $fail failed"
[ "$fail" = 0 ]

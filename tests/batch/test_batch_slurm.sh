#!/usr/bin/env bash
# rigflow batch --slurm against a real Slurm: a one-node cluster (munged, slurmctld, slurmd) on
# 127.0.0.1, started in a temporary folder for this test and stopped after it. Submits an array
# with a failing job and a task cancelled mid-job, follows it with --status, fixes the inputs,
# --resubmit, and checks every output. The daemons stopped are exactly those started here (their PIDs recorded at start: the
# daemons delete their own pid files on exit). Skips (77) without slurm-wlm and munge, or when
# not root (the daemons run as root with SlurmUser=root). The cluster: slurm-cluster.sh.
set -u
rigflow="${RF_RIGFLOW:-${RF_BUILDDIR:?}/rigflow}"
fx="$RF_BUILDDIR/tests/batch/.libs"
pipeline="${RF_SRCDIR:?}/tests/batch/copy.json"

. "$RF_SRCDIR/tests/batch/slurm-cluster.sh"
why=$(slurm_cluster_check) || { echo "# SKIP Slurm batch test: $why"; exit 77; }

tmp=$(mktemp -d)
trap 'slurm_cluster_stop; rm -rf "$tmp"' EXIT
. "$RF_SRCDIR/tests/tap.sh"

chmod 0755 "$tmp" # munged wants every folder above its socket searchable
mkdir -p "$tmp/cluster"
slurm_cluster_start "$tmp/cluster" >"$tmp/why" || { echo "Bail out! $(cat "$tmp/why")"; exit 99; }
ok "a one-node Slurm cluster is up on 127.0.0.1 (port $slurm_port)"

# Waits for the batch in $1 to leave Slurm's queue (squeue, polled: sbatch --wait polls slowly).
wait_batch() {
    local i
    for i in $(seq 600); do
        "$rigflow" batch --status "$1" >"$tmp/status" 2>&1
        [ $? != 6 ] && return 0
        sleep 0.1
    done
    return 1
}

# ---- submit an array: a failing job, and a long one whose task is cancelled ----
# Jobs in name order: bad c1 c2 c3 c4 c5 c6 slow; task I of 4 runs jobs I and I+4, so task 0
# holds the failing job and task 3 the long one.
in="$tmp/in" out="$tmp/out-dir"
mkdir -p "$in"
echo "fail, until fixed" >"$in/bad.txt"
for i in 1 2 3 4 5 6; do echo "clip $i" >"$in/c$i.txt"; done
echo "sleep 60" >"$in/slow.txt"
expect 0 "--slurm submits the array" -- "$rigflow" --plugin-path "$fx" batch "$pipeline" \
    --over "copy.input=$in/*.txt" --out "$out" --slurm --array-size 4 --time 5
contains "$tmp/out" "submitted 8 jobs as Slurm array" "the submission is reported"
array=$(sed -n 's/.*as Slurm array \([0-9]*\) .*/\1/p' "$tmp/out")
contains "$out/rigflow-batch/slurm.sbatch" "--shard \"\$SLURM_ARRAY_TASK_ID/4\"" \
    "the script runs one shard per array task"
contains "$out/rigflow-batch/slurm.sbatch" "#SBATCH --array=0-3" "four array tasks"
expect 6 "--status while the array is queued" -- "$rigflow" batch --status "$out"
# cancel task 3 once it has recorded c3 and is running the long job
for i in $(seq 600); do grep -qs '"job":"c3"' "$out"/rigflow-batch/manifest-shard-3-of-4.jsonl && break; sleep 0.1; done
scancel "${array}_3"
t0=$(date +%s.%N)
wait_batch "$out" || { echo "Bail out! the array did not finish within 60 s"; exit 99; }
t1=$(date +%s.%N)
echo "# the array ended $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s after the cancellation"
expect 1 "--status after the array: a job failed, one is missing" -- "$rigflow" batch --status "$out"
sed 's/^/# status: /' "$tmp/out"
contains "$tmp/out" "8 jobs: 6 done, 1 failed, 0 running, 0 pending, 1 missing" "--status counts"
contains "$tmp/out" "failed bad: " "--status names the failed job"
contains "$tmp/out" "bad.txt asks to fail" "with its error"
contains "$tmp/out" "missing slow: its array task 3 ended CANCELLED" \
    "--status names the missing job and how its task ended"
tasks=$(grep "^Slurm array tasks:" "$tmp/out")
case "$tasks" in *"1 FAILED"*"2 COMPLETED"*"1 CANCELLED"*) ok "scontrol's word on each task" ;;
*) bad "scontrol's word on each task: '$tasks'" ;; esac
good=0
for i in 1 2 3 4 5 6; do
    printf 'copied by test.copy\nclip %s\n' "$i" | cmp -s - "$out/c$i.txt" && good=$((good + 1))
done
[ "$good" = 6 ] && ok "every good job's output is right" || bad "$good of 6 outputs right"
[ ! -e "$out/slow.txt" ] && [ "$(ls -A "$out" | grep -c '\.rf-')" = 0 ] &&
    ok "the cancelled job left no output, not even a temporary one" || bad "the cancelled job left a file"
[ "$(ls "$out"/rigflow-batch/manifest-shard-*-of-4.jsonl | wc -l)" = 4 ] &&
    ok "each shard kept its own manifest" || bad "expected 4 shard manifests"

# ---- resubmit the failed and the missing job's tasks only ----
echo "fixed" >"$in/bad.txt"
echo "sleep 0.1" >"$in/slow.txt"
expect 0 "--resubmit" -- "$rigflow" batch --resubmit "$out"
contains "$tmp/out" "resubmitted 1 failed and 1 missing jobs" "--resubmit names what it sends"
contains "$tmp/out" "(tasks 0,3)" "only the tasks of those jobs are submitted"
wait_batch "$out" || { echo "Bail out! the resubmitted tasks did not finish within 60 s"; exit 99; }
expect 0 "--status after the resubmission: all done" -- "$rigflow" batch --status "$out"
contains "$tmp/out" "8 jobs: 8 done, 0 failed" "--status counts every job done"
contains "$out/bad.txt" "fixed" "the resubmitted failed job wrote its output"
contains "$out/slow.txt" "sleep 0.1" "the resubmitted missing job wrote its output"
for task in 0 3; do
    skips=$(grep -h "skipped (finished before)" "$out"/rigflow-batch/logs/slurm-*_$task.out | tail -1)
    case "$skips" in *"2 jobs: 1 done, 0 failed, 0 crashed, 1 skipped"*) ok "resubmitted task $task redid only its unfinished job" ;;
    *) bad "resubmitted task $task: $skips" ;; esac
done
expect 0 "--resubmit with nothing left" -- "$rigflow" batch --resubmit "$out"
contains "$tmp/out" "nothing to resubmit" "--resubmit says so"

# ---- an output folder whose path holds a space and a '%' (Slurm's pattern character) ----
out2="$tmp/out dir 100%"
mkdir -p "$tmp/in2"
echo one >"$tmp/in2/one.txt"
echo two >"$tmp/in2/two.txt"
expect 0 "--slurm with a space and a % in --out" -- "$rigflow" --plugin-path "$fx" batch "$pipeline" \
    --over "copy.input=$tmp/in2/*.txt" --out "$out2" --slurm
wait_batch "$out2" || { echo "Bail out! the array in '$out2' did not finish within 60 s"; exit 99; }
expect 0 "... every job done" -- "$rigflow" batch --status "$out2"
[ "$(ls "$out2"/rigflow-batch/logs/slurm-*_[01].out 2>/dev/null | wc -l)" = 2 ] &&
    ok "... each task's Slurm log in DIR/rigflow-batch/logs" ||
    bad "... Slurm logs: $(ls "$out2/rigflow-batch/logs" 2>&1 | tr '\n' ' ')"

started=("${slurm_daemons[@]}")
slurm_cluster_stop
left=0
for p in "${started[@]}"; do slurm_alive "$p" && left=$((left + 1)); done
[ "$left" = 0 ] && ok "the daemons started here are stopped" || bad "$left daemons still run"
echo "# $pass passed, $fail failed"
[ "$fail" = 0 ]

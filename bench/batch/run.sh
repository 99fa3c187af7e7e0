#!/usr/bin/env bash
# rigflow batch: clips per second with -j 1 and -j 2 and through a local one-node Slurm, beside
# one `rigflow run` process per job (what a shell loop or xargs -P does), and the per-job overhead
# of the pool beside the retarget of cmu_01_01 run alone.
#   bench/batch/run.sh BUILDDIR [--quick]
# Workload: the shared BVH clips plus generated ones (../shared/peers/gen_bvh.mjs, 240 to 480
# frames) retargeted onto five shared characters with pipelines/retarget.json. Prints a table and
# a RESULT {json} line. Scratch files stay in BUILDDIR/bench-batch.
set -u
build=$(cd "${1:?usage: run.sh BUILDDIR [--quick]}" && pwd)
quick=${2:-}
src=$(cd "$(dirname "$0")/../.." && pwd)
data=${RF_DATA_DIR:-$src/../shared/data}
peers=$src/../shared/peers
rigflow=$build/rigflow
pipeline=$src/pipelines/retarget.json
scratch=$build/bench-batch
generated=193 copies=40 alone=5
[ "$quick" = --quick ] && generated=33 copies=20 alone=3
characters=(Fox.glb RiggedFigure.glb RobotExpressive.glb Wizard.glb girl.glb)

for f in "$data/bvh/cmu_01_01.bvh" "${characters[@]/#/$data/models/}"; do
    [ -f "$f" ] || { echo "bench/batch: $f not found (set RF_DATA_DIR)"; exit 1; }
done
command -v node >/dev/null || { echo "bench/batch: node not found (for gen_bvh.mjs)"; exit 1; }

now() { date +%s.%N; }
calc() { awk "BEGIN { printf \"%.${2:-3}f\", $1 }"; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# field FIELD FOLDER: each manifest line's number FIELD ("seconds": a job's load, validation and
# run, wall; "cpu_seconds": the same in CPU time)
field() { cat "$2"/rigflow-batch/manifest*.jsonl | sed -n "s/.*\"$1\":\([0-9.e-]*\).*/\1/p"; }
total() { awk '{ s += $1 } END { print s }'; }
# timed FILE COMMAND...: runs COMMAND, writes "wall cpu" (cpu: user + system, children included)
timed() {
    local out=$1
    shift
    /usr/bin/time -f "%e %U %S" -o "$out.time" "$@" || return 1
    awk '{ printf "%s %.3f\n", $1, $2 + $3 }' "$out.time" >"$out"
}
load() { cut -d' ' -f1 /proc/loadavg; }

rm -rf "$scratch"
mkdir -p "$scratch/clips" "$scratch/characters" "$scratch/copies"
chmod 0755 "$scratch"
cp "$data"/bvh/*.bvh "$scratch/clips/"
for k in $(seq "$generated"); do
    node "$peers/gen_bvh.mjs" $((240 + (k * 37) % 241)) 120 "$scratch/clips/gen_$(printf %03d "$k").bvh" >/dev/null
done
for c in "${characters[@]}"; do ln -s "$data/models/$c" "$scratch/characters/$c"; done
for k in $(seq "$copies"); do ln -s "$data/bvh/cmu_01_01.bvh" "$scratch/copies/c$(printf %03d "$k").bvh"; done
clips=$(ls "$scratch/clips" | wc -l)
jobs=$((clips * ${#characters[@]}))
echo "bench/batch: $clips clips x ${#characters[@]} characters = $jobs jobs; load $(load)"

batch() { # batch OUT J: "wall cpu" seconds of one batch over every clip and character
    local out=$1 j=$2
    timed "$out.t" "$rigflow" batch "$pipeline" --over "source.path=$scratch/clips/*.bvh" \
        --over "target.path=$scratch/characters/*.glb" -p export.path=.glb --out "$out" -j "$j" \
        -q >"$out.log" 2>&1 || { echo "bench/batch: batch failed:" >&2; tail -5 "$out.log" >&2; exit 1; }
    cat "$out.t"
}

# ---- -j 1 and -j 2: a warm-up, then each twice, alternating; the faster run of each counts
# (the machine is shared: other work only ever slows a run down) ----
batch "$scratch/warm" 2 >/dev/null
w1="" w2=""
for round in 1 2; do
    for j in 1 2; do
        rm -rf "$scratch/j$j"
        read -r w cpu <<<"$(batch "$scratch/j$j" "$j")"
        echo "  -j $j, round $round: $w s ($(calc "$jobs / $w" 1) jobs/s), CPU $cpu s; load $(load)"
        if [ "$j" = 1 ]; then w1=$(echo "${w1:-$w} $w" | tr ' ' '\n' | sort -g | head -1)
        else w2=$(echo "${w2:-$w} $w" | tr ' ' '\n' | sort -g | head -1); fi
    done
done

# ---- one process per job, on a sample: what a loop of `rigflow run` costs ----
sample=$(ls "$scratch/clips" | head -$(( (copies + ${#characters[@]} - 1) / ${#characters[@]} )))
t0=$(now)
n=0
for c in $sample; do
    for m in "${characters[@]}"; do
        "$rigflow" -q run "$pipeline" -p source.path="$scratch/clips/$c" \
            -p target.path="$scratch/characters/$m" -p export.path="$scratch/proc.glb" \
            >/dev/null 2>&1 || exit 1
        n=$((n + 1))
    done
done
t1=$(now)
per_process=$(calc "($t1 - $t0) / $n" 4)
per_batch1=$(calc "$w1 / $jobs" 4)
echo "  one rigflow run per job: $(calc "$per_process * 1000" 1) ms a job ($n jobs), -j 1 batch $(calc "$per_batch1 * 1000" 1) ms"

# ---- per-job overhead beside cmu_01_01 onto the Fox run alone ----
for i in $(seq "$alone"); do
    t0=$(now)
    "$rigflow" -q run "$pipeline" -p source.path="$data/bvh/cmu_01_01.bvh" \
        -p target.path="$data/models/Fox.glb" -p export.path="$scratch/alone.glb" >/dev/null
    t1=$(now)
    echo "$(calc "$t1 - $t0" 4)"
done >"$scratch/alone.txt"
lone=$(median <"$scratch/alone.txt")
over=$scratch/overhead
overbatch() {
    timed "$1" "$rigflow" batch "$pipeline" --over "source.path=$scratch/copies/*.bvh" \
        --over "target.path=$data/models/Fox.glb" -p export.path=.glb --out "$over" -j 1 -q
}
overbatch "$scratch/over.t" >/dev/null 2>&1
overbatch "$scratch/fixed.t" >/dev/null 2>&1 # again, every job skipped: start-up, plan, manifest
read -r wo co <"$scratch/over.t"
read -r wf cf <"$scratch/fixed.t"
job=$(field seconds "$over" | median)
jobcpu=$(field cpu_seconds "$over" | median)
overhead_ms=$(calc "($wo - $wf - $(field seconds "$over" | total)) / $copies * 1000" 2)
overhead_cpu_ms=$(calc "($co - $cf - $(field cpu_seconds "$over" | total)) / $copies * 1000" 2)
echo "  cmu_01_01 onto the Fox: rigflow run alone $(calc "$lone * 1000" 1) ms (process included);" \
    "in a -j 1 batch of $copies: the job $(calc "$job * 1000" 1) ms ($(calc "$jobcpu * 1000" 1) ms CPU)," \
    "the pool's overhead $overhead_ms ms a job ($overhead_cpu_ms ms CPU), start-up $(calc "$wf * 1000" 0) ms once; load $(load)"

# ---- through a local one-node Slurm: 2 array tasks of -j 1 (one per core) ----
wslurm=""
. "$src/tests/batch/slurm-cluster.sh"
if why=$(slurm_cluster_check); then
    trap 'slurm_cluster_stop' EXIT
    if slurm_cluster_start "$scratch/cluster" >"$scratch/cluster.why"; then
        t0=$(now)
        "$rigflow" batch "$pipeline" --over "source.path=$scratch/clips/*.bvh" \
            --over "target.path=$scratch/characters/*.glb" -p export.path=.glb \
            --out "$scratch/slurm" --slurm --array-size "$(nproc)" >/dev/null
        while "$rigflow" batch --status "$scratch/slurm" >"$scratch/slurm.status" 2>&1; [ $? = 6 ]; do
            sleep 0.1
        done
        t1=$(now)
        wslurm=$(calc "$t1 - $t0")
        echo "  Slurm, $(nproc) tasks of -j 1: $wslurm s ($(calc "$jobs / $wslurm" 1) jobs/s): $(head -1 "$scratch/slurm.status")"
        slurm_cluster_stop
    else
        echo "  Slurm: $(cat "$scratch/cluster.why")"
    fi
else
    echo "  Slurm: skipped ($why)"
fi

echo
echo "| run | wall s | clips/s | jobs/s | vs -j 1 |"
echo "|---|---|---|---|---|"
echo "| one rigflow run per job (sample of $n) | $(calc "$per_process * $jobs" 1) (projected) | $(calc "1 / $per_process / ${#characters[@]}" 1) | $(calc "1 / $per_process" 1) | $(calc "$per_batch1 / $per_process" 2)x |"
echo "| batch -j 1 | $w1 | $(calc "$clips / $w1" 1) | $(calc "$jobs / $w1" 1) | 1.00x |"
echo "| batch -j 2 | $w2 | $(calc "$clips / $w2" 1) | $(calc "$jobs / $w2" 1) | $(calc "$w1 / $w2" 2)x (efficiency $(calc "$w1 / $w2 / 2 * 100" 0)%) |"
[ -n "$wslurm" ] && echo "| Slurm, $(nproc) tasks x -j 1 | $wslurm | $(calc "$clips / $wslurm" 1) | $(calc "$jobs / $wslurm" 1) | $(calc "$w1 / $wslurm" 2)x |"
echo
echo "RESULT {\"bench\":\"batch\",\"clips\":$clips,\"characters\":${#characters[@]},\"jobs\":$jobs," \
    "\"j1_s\":$w1,\"j2_s\":$w2,\"speedup_j2\":$(calc "$w1 / $w2"),\"slurm_s\":${wslurm:-null}," \
    "\"process_per_job_ms\":$(calc "$per_process * 1000" 2),\"batch_per_job_ms\":$(calc "$per_batch1 * 1000" 2)," \
    "\"cmu_01_01_alone_ms\":$(calc "$lone * 1000" 2),\"cmu_01_01_job_ms\":$(calc "$job * 1000" 2)," \
    "\"overhead_ms\":$overhead_ms,\"overhead_cpu_ms\":$overhead_cpu_ms,\"load\":$(load)}"

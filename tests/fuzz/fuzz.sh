#!/usr/bin/env bash
# Builds every libFuzzer harness of tests/fuzz with clang (-fsanitize=fuzzer,address,undefined)
# and runs each for FUZZ_SECONDS seconds (`make fuzz FUZZ_SECONDS=N` calls this).
#
# Corpora live in a scratch folder, never in the repository: FUZZ_WORK (default
# $RF_BUILDDIR/fuzz-work), seeded at run time from tests/fuzz/seeds, the test fixtures, the bundled
# pipelines and the shared data beside the checkout (RF_DATA_DIR), so a later run goes on from
# what an earlier one found. A finding (crash, leak, timeout, broken promise) is kept there as
# crash-*, leak-* or timeout-* and fails the run; rerun it with `$RF_BUILDDIR/tests/fuzz/NAME FILE`.
#
# Environment: RF_SRCDIR, RF_BUILDDIR (set by make), FUZZ_SECONDS (default 60), FUZZ_ONLY
# (space-separated harness names), FUZZ_WORK, CLANG (default clang), RF_DATA_DIR.
set -u
src=${RF_SRCDIR:?}
build=${RF_BUILDDIR:?}
seconds=${FUZZ_SECONDS:-60}
work=${FUZZ_WORK:-$build/fuzz-work}
clang=${CLANG:-clang}
out="$build/tests/fuzz"
mkdir -p "$out" "$work"

say() { printf 'fuzz: %s\n' "$*" >&2; }

if ! command -v "$clang" >/dev/null; then
    say "$clang not found: install the Debian packages clang and libclang-rt-14-dev"
    exit 1
fi

cflags=(-std=c11 -D_DEFAULT_SOURCE -g -O1 -fno-omit-frame-pointer
        -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
        -I"$src/sdk/include" -I"$src/framework" -I"$build")
pkg() { pkg-config "$@" glib-2.0 jansson; }

# build NAME SOURCES... -- LIBS...: compiles one harness, quietly unless it fails.
build() {
    local name=$1 args=()
    shift
    while [ $# -gt 0 ] && [ "$1" != -- ]; do args+=("$1"); shift; done
    shift
    if ! "$clang" "${cflags[@]}" "${args[@]}" -o "$out/$name" "$@" -lm 2>"$out/$name.log"; then
        cat "$out/$name.log" >&2
        say "cannot build $name"
        return 1
    fi
}

build_bvh() {
    build fuzz_bvh -I"$src/sdk/formats/bvh" "$src/tests/fuzz/fuzz_bvh.c" "$src"/sdk/formats/bvh/bvh-*.c --
}

# The library's C sources, read from framework/local.mk so that list keeps one home.
librigflow_sources() {
    awk '/^framework_librigflow_la_SOURCES/ { on = 1 }
         on { for (i = 1; i <= NF; i++) if ($i ~ /\.c$/) print $i; if ($NF != "\\") on = 0 }' \
        "$src/framework/local.mk"
}

build_pipeline() {
    local f srcs=()
    for f in $(librigflow_sources); do srcs+=("$src/$f"); done
    [ ${#srcs[@]} -gt 0 ] || { say "no library sources found in framework/local.mk"; return 1; }
    # shellcheck disable=SC2046
    build fuzz_pipeline -DRF_PLUGINSDIR='"/nonexistent"' $(pkg --cflags) \
        "$src/tests/fuzz/fuzz_pipeline.c" "${srcs[@]}" -- $(pkg --libs) -lltdl -ldl
}

build_analysis() {
    build fuzz_analysis -I"$src/sdk/analysis" "$src/tests/fuzz/fuzz_analysis.c" \
        "$src"/sdk/analysis/*.c --
}

build_mapping() {
    # shellcheck disable=SC2046
    build fuzz_mapping -I"$src/plugins/mapping-file" $(pkg-config --cflags jansson) \
        "$src/tests/fuzz/fuzz_mapping.c" "$src"/plugins/mapping-file/mapfile-*.c \
        -- $(pkg-config --libs jansson)
}

build_ik() {
    local d srcs=() incs=()
    for d in ik-ccd ik-fabrik ik-jacobian ik-twobone; do incs+=(-I"$src/plugins/$d"); done
    srcs=("$src"/sdk/ik/{ikcommon,constraint,linalg}.c "$src"/plugins/ik-ccd/ccd.c
        "$src"/plugins/ik-fabrik/fabrik.c "$src"/plugins/ik-jacobian/jacobian.c
        "$src"/plugins/ik-twobone/twobone.c)
    build fuzz_ik "${incs[@]}" "$src/tests/fuzz/fuzz_ik.c" "${srcs[@]}" --
}

# seed NAME: fills the scratch corpus of a harness (copies; the sources stay untouched).
build_rig() {
    build fuzz_rig -I"$src/plugins/rig-general" "$src/tests/fuzz/fuzz_rig.c" \
        "$src"/plugins/rig-general/rig*.c "$src"/sdk/analysis/*.c \
        -- -lcholmod -lembree3 -lmeshoptimizer
}

seed() {
    local name=$1 dir="$work/$1/corpus" f
    mkdir -p "$dir"
    [ -d "$src/tests/fuzz/seeds/$name" ] && cp -f "$src/tests/fuzz/seeds/$name"/* "$dir/" 2>/dev/null
    case $name in
    bvh)
        # The start of each real file: its hierarchy and some frames (max_len keeps inputs short).
        for f in "${RF_DATA_DIR:-$src/../shared/data}"/bvh/*.bvh; do
            [ -f "$f" ] && head -c 16384 "$f" >"$dir/data-$(basename "$f")"
        done ;;
    pipeline)
        for f in "$src"/pipelines/*.json; do [ -f "$f" ] && cp -f "$f" "$dir/"; done ;;
    analysis)
        # Any varied bytes make varied trees: the start of each real BVH, read as joint records.
        for f in "${RF_DATA_DIR:-$src/../shared/data}"/bvh/*.bvh; do
            [ -f "$f" ] && head -c 2048 "$f" >"$dir/data-$(basename "$f")"
        done ;;
    esac
}

# run NAME MAX_LEN [ENV...]: runs one harness for $seconds; prints its figures.
run() {
    local name=$1 max_len=$2 dir="$work/$1" dict=() log
    shift 2
    log="$dir/last-run.log"
    [ -f "$src/tests/fuzz/$name.dict" ] && dict=(-dict="$src/tests/fuzz/$name.dict")
    rm -f "$dir"/crash-* "$dir"/leak-* "$dir"/timeout-* "$dir"/oom-*
    say "running $name for ${seconds}s (corpus $dir/corpus)"
    local t0=$SECONDS
    env "$@" "$out/fuzz_$name" -max_total_time="$seconds" -max_len="$max_len" -timeout=25 \
        -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$dir/" "${dict[@]}" \
        "$dir/corpus" >"$log" 2>&1
    local rc=$? runs
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    printf '%s\t%s s\t%s runs\tcorpus %s\texit %s\n' "$name" "$((SECONDS - t0))" "${runs:-?}" \
        "$(ls "$dir/corpus" | wc -l)" "$rc" | tee -a "$work/history.tsv"
    if [ $rc != 0 ]; then
        grep -E 'ERROR|SUMMARY|broken promise|runtime error' "$log" | head -20 >&2
        say "$name found a problem: see $log and $dir/crash-* (or leak-*, timeout-*)"
    fi
    return $rc
}

harnesses=${FUZZ_ONLY:-"bvh pipeline analysis mapping ik rig"}
plugins="$build/tests/fixtures/.libs/fx_good.so:$build/plugins"
pass=0 fail=0 skipped=0
for h in $harnesses; do
    case $h in
    bvh) build_bvh && seed bvh && run bvh 65536 ;;
    pipeline) build_pipeline && seed pipeline && run pipeline 16384 RF_FUZZ_PLUGINS="$plugins" ;;
    analysis)
        if [ ! -f "$src/sdk/analysis/analysis.c" ]; then
            say "skipped analysis: sdk/analysis is not in this tree yet"
            skipped=$((skipped + 1)); continue
        fi
        build_analysis && seed analysis && run analysis 16384 ;;
    mapping)
        if [ ! -f "$src/plugins/mapping-file/mapfile-read.c" ]; then
            say "skipped mapping: plugins/mapping-file is not in this tree yet"
            skipped=$((skipped + 1)); continue
        fi
        build_mapping && seed mapping && run mapping 16384 ;;
    ik) build_ik && seed ik && run ik 1024 ;;
    rig) build_rig && seed rig && run rig 4096 ;;
    *) say "unknown harness '$h'"; false ;;
    esac
    if [ $? = 0 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); fi
done
echo "fuzz: $pass passed, $fail failed, $skipped skipped"
[ "$fail" = 0 ]

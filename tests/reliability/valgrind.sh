#!/usr/bin/env bash
# Runs the rigflow command of the build tree under valgrind memcheck (`make valgrind` points the
# end-to-end tests at this script through RF_RIGFLOW). Any invalid access, use of uninitialised
# memory or definite leak makes the command exit 97, which fails the test row that ran it; each
# run's report is kept in RF_VG_LOGS. `valgrind.sh --summary` counts the reports.
set -u
logs=${RF_VG_LOGS:?}
if [ "${1:-}" = --summary ]; then
    total=0 bad=0
    for f in "$logs"/vg.*.log; do
        [ -f "$f" ] || continue
        total=$((total + 1))
        if [ -s "$f" ]; then # --quiet: valgrind writes only what it found
            bad=$((bad + 1))
            echo "valgrind found errors: $f"
            head -8 "$f" | sed 's/^/    /'
        fi
    done
    echo "valgrind: $((total - bad)) passed, $bad failed"
    [ "$total" -gt 0 ] && [ "$bad" = 0 ]
    exit
fi
mkdir -p "$logs"
build=${RF_BUILDDIR:?}
# libtool's --mode=execute runs the real binary (not its wrapper script) with the uninstalled
# library found, and execs it, so the test sees valgrind's pid (SIGINT rows).
exec "$build/libtool" --mode=execute valgrind --quiet --error-exitcode=97 \
    --leak-check=full --show-leak-kinds=definite --errors-for-leak-kinds=definite \
    --suppressions="$(dirname "$0")/valgrind.supp" \
    --log-file="$logs/vg.%p.log" "$build/rigflow" "$@"

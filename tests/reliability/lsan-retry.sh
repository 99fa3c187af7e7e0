#!/bin/sh
# Runs one test of the sanitizer build (LOG_COMPILER under --enable-sanitizers) and runs it once
# more when, and only when, LeakSanitizer itself crashed at a process's exit: its stop-the-world
# tracer sometimes dies with "Tracer caught signal 11" before any leak is looked at (a known
# fault of the sanitizer runtime, google/sanitizers#1353), which would fail a test that passed.
# A leak report, an ASan or UBSan report and a failing check are never retried; the rerun is
# said in the test's log.
out=$(mktemp) || exit 99
trap 'rm -f "$out"' EXIT
run() {
    "$@" >"$out" 2>&1
    code=$?
    cat "$out"
    return "$code"
}
run "$@"
code=$?
if [ "$code" -ne 0 ] && [ "$code" -ne 77 ] && grep -q "Tracer caught signal" "$out" &&
    grep -q "LeakSanitizer has encountered a fatal error" "$out" &&
    ! grep -q "ERROR: LeakSanitizer: detected memory leaks" "$out"; then
    echo "# LeakSanitizer's own tracer crashed at exit (no leak report, exit $code): run again"
    run "$@"
    code=$?
fi
exit "$code"

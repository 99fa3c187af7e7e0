#!/usr/bin/env bash
# In a --enable-sanitizers build, bugs inside a plugin loaded with dlopen are caught and reported
# by AddressSanitizer and UBSan (the plugin is instrumented, the runtime lives in the host), and
# the run fails instead of going on with corrupt memory. In any other build this test says so and
# skips.
set -u
build="${RF_BUILDDIR:?}"
rigflow="$build/rigflow"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok - $1"; }
bad() { fail=$((fail + 1)); echo "not ok - $1"; sed 's/^/    stderr: /' "$tmp/err" | head -20; }

if ! nm -D "$build/framework/.libs/librigflow.so" 2>/dev/null | grep -q __asan_; then
    echo "# skipped: not a sanitizer build (configure --enable-sanitizers)"
    echo "0 passed, 0 failed, 1 skipped"
    exit 77
fi
plugins="$tmp/plugins"
mkdir "$plugins" && cp "$build/tests/reliability/.libs/fx_overflow.so" "$plugins/"

# caught BUG MESSAGE NAME: runs the overflow node; the run must fail with the sanitizer's report.
caught() {
    cat >"$tmp/p.json" <<JSON
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "bug", "type": "test.overflow", "params": {"bug": "$1"}}]}
JSON
    RIGFLOW_PLUGIN_PATH= "$rigflow" --quiet --plugin-path "$plugins" run "$tmp/p.json" \
        >"$tmp/out" 2>"$tmp/err"
    local code=$?
    if [ "$code" != 0 ] && grep -qF -- "$2" "$tmp/err" && grep -q "fx_overflow" "$tmp/err"; then
        ok "$3 (exit $code)"
    else
        bad "$3: exit $code, expected a report with '$2' naming fx_overflow"
    fi
}
caught heap "heap-buffer-overflow" "AddressSanitizer reports a heap overflow inside a plugin"
caught signed "signed integer overflow" "UBSan reports undefined behaviour inside a plugin"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

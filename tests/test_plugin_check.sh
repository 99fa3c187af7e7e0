#!/usr/bin/env bash
# rigflow plugin-check: passes on every bundled plugin; fails, with the reason, on fixture plugins
# that each break one rule (and survives the one that crashes).
set -u
rigflow="${RF_BUILDDIR:?}/rigflow"
fx="$RF_BUILDDIR/tests/fixtures/.libs"
out=$(mktemp)
trap 'rm -f "$out"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok - $1"; }
bad() { fail=$((fail + 1)); echo "not ok - $1"; sed 's/^/    /' "$out" | head -20; }

shopt -s nullglob
bundled=("$RF_BUILDDIR"/plugins/.libs/*.so)
if [ "${#bundled[@]}" -gt 0 ]; then
    "$rigflow" plugin-check "${bundled[@]}" >"$out" 2>&1
    code=$?
    [ "$code" = 0 ] && ok "every bundled plugin passes (${#bundled[@]} files)" || bad "bundled plugins pass (exit $code)"
    ! grep -q '^FAIL' "$out" && ok "no FAIL line for bundled plugins" || bad "no FAIL line for bundled plugins"
    sed 's/^/# /' "$out" | grep -v '^# PASS'
fi

# expect_fail FIXTURE CHECK TEXT: plugin-check exits 1 with a FAIL line for CHECK saying TEXT
expect_fail() {
    "$rigflow" plugin-check "$fx/$1.so" >"$out" 2>&1
    local code=$?
    if [ "$code" = 1 ] && grep -q "^FAIL  .*$1.so  $2: .*$3" "$out"; then ok "$1: $2 fails with '$3'"
    else bad "$1: $2 fails with '$3' (exit $code)"; fi
}
expect_fail fx_unresolved loads "undefined symbol: rf_fixture_symbol_nobody_defines"
expect_fail fx_noentry exports "some_other_symbol"
expect_fail fx_noentry entry "not a rigflow plugin"
expect_fail fx_major entry "incompatible plugin ABI"
expect_fail fx_minor entry "incompatible plugin ABI"
expect_fail fx_initfail entry "licence file is missing"
expect_fail fx_baddefault descriptors "default 250 is outside \[0, 100\]"
expect_fail fx_crash create "crashed"
expect_fail fx_selftest selftest "1 + 1 came out as 3"

"$rigflow" plugin-check "$fx/fx_good.so" >"$out" 2>&1
[ $? = 0 ] && grep -q "^PASS .* selftest: test.source: passed" "$out" && ok "fx_good passes, its self-test ran" || bad "fx_good passes"
"$rigflow" plugin-check "$fx/fx_crash.so" "$fx/fx_good.so" >"$out" 2>&1
grep -q "^PASS  .*fx_good.so  create" "$out" && ok "a crashing plugin does not stop the checks of the next" || bad "checks go on after a crash"
"$rigflow" plugin-check >"$out" 2>&1
[ $? = 2 ] && ok "no file is a usage error" || bad "no file is a usage error"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

#!/bin/sh
# rigflow ik-bench: the CSV it prints, its skips and its usage errors.
set -u
rigflow=${RF_BUILDDIR:-.}/rigflow
fail() { echo "FAIL: $*"; exit 1; }
out=$("$rigflow" ik-bench -s fabrik -s twobone -w chain2-it10 -w chain5-it10 --min-time 0 2>err.$$)
rc=$?
err=$(cat err.$$); rm -f err.$$
[ $rc = 0 ] || fail "exit $rc: $err"
[ "$(echo "$out" | head -1)" = "solver,workload,us_per_solve,converged,mean_error,mean_iterations" ] ||
    fail "header: $out"
echo "$out" | grep -q '^fabrik,chain2-it10,' || fail "no fabrik row: $out"
echo "$out" | grep -q '^twobone,chain2-it10,[0-9.]*,1.0000,' || fail "twobone does not solve 2 bones: $out"
echo "$out" | grep -q '^twobone,chain5' && fail "twobone ran on 5 bones"
echo "$err" | grep -q 'twobone on chain5-it10: skipped' || fail "no skip note: $err"
[ "$(echo "$out" | wc -l)" = 4 ] || fail "expected 3 rows: $out"
"$rigflow" ik-bench -w no-such-workload >/dev/null 2>&1
[ $? = 2 ] || fail "an unknown workload is not a usage error"
"$rigflow" ik-bench -s no-such-solver >/dev/null 2>&1
[ $? = 2 ] || fail "an unknown solver is not a usage error"
"$rigflow" ik-bench --list | grep -q 'ik.dls' || fail "--list lacks ik.dls"
echo "1 passed, 0 failed"

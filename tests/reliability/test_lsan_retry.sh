#!/bin/sh
# tests/reliability/lsan-retry.sh (the sanitizer build's LOG_COMPILER) reruns a test only when
# LeakSanitizer's own tracer crashed: fake tests that print each kind of output and fail once.
src="${RF_SRCDIR:-.}"
retry="$src/tests/reliability/lsan-retry.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
# A test failing the first time with the given text on stderr, passing the second time.
fake() {
    cat >"$tmp/t" <<EOT
#!/bin/sh
if [ ! -f "$tmp/ran" ]; then touch "$tmp/ran"; printf '%s\n' "$1" >&2; exit 1; fi
echo passed; exit 0
EOT
    chmod +x "$tmp/t"
    rm -f "$tmp/ran"
}
expect() { # want-exit, what
    sh "$retry" "$tmp/t" >"$tmp/out" 2>&1
    got=$?
    if [ "$got" -eq "$1" ]; then echo "PASS: $2 (exit $got)"; else
        cat "$tmp/out"; echo "FAIL: $2: exit $got, expected $1"; fail=1; fi
}
fake 'Tracer caught signal 11: addr=0x0
==1==LeakSanitizer has encountered a fatal error.'
expect 0 "the tracer's own crash is run again"
fake '==1==ERROR: LeakSanitizer: detected memory leaks'
expect 1 "a leak report is not"
fake '==1==ERROR: AddressSanitizer: heap-buffer-overflow'
expect 1 "an AddressSanitizer report is not"
fake 'FAIL: some check'
expect 1 "a failing check is not"
cat >"$tmp/t" <<'EOT'
#!/bin/sh
echo "SKIP: no data"; exit 77
EOT
expect 77 "a skip stays a skip"
exit "$fail"

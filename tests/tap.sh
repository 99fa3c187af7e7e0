# TAP helpers shared by the shell tests (sourced after $tmp is made; counts into pass and fail).
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok - $1"; }
bad() { fail=$((fail + 1)); echo "not ok - $1"; [ -f "$tmp/err" ] && sed 's/^/    stderr: /' "$tmp/err" | head -20; }
expect() { # expect CODE NAME -- COMMAND...
    local want=$1 name=$2
    shift 3
    "$@" >"$tmp/out" 2>"$tmp/err"
    local got=$?
    if [ "$got" = "$want" ]; then ok "$name"; else bad "$name (exit $got, expected $want)"; fi
}
contains() { # contains FILE TEXT NAME
    if grep -qF -- "$2" "$1"; then ok "$3"; else bad "$3: '$2' not in $(basename "$1")"; fi
}
matches() { # matches FILE REGEX NAME: an extended regular expression, for lines of a listing
    if grep -qE -- "$2" "$1"; then ok "$3"; else bad "$3: /$2/ not in $(basename "$1")"; fi
}
same() { # same GOT WANT NAME
    if [ "$1" = "$2" ]; then ok "$3"; else bad "$3: got '$1', expected '$2'"; fi
}

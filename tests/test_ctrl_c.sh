#!/usr/bin/env bash
# Ctrl-C during `rigflow map`, `rigflow inspect` and `rigflow rig-bench`, as during `rigflow run`
# and `rigflow report`: the run stops at the next check, says so, exits 130 and leaves no file
# (map -o's hidden temporary file included). SIGINT is sent once the command's handler is in
# place (SigCgt in /proc/PID/status), so the run is interrupted, not killed: a command without a
# handler never gets there, runs to its end and fails the check. A run that ended before the
# signal reached it (a busy machine) is tried again, up to three times.
set -u
rigflow="${RF_BUILDDIR:?}/rigflow"
src="${RF_SRCDIR:?}"
data="${RF_DATA_DIR:-}"
command -v node >/dev/null || { echo "SKIP: node not found (apt-get install nodejs)"; exit 77; }
env --default-signal=INT true 2>/dev/null ||
    { echo "SKIP: env --default-signal missing (coreutils 8.31 or later)"; exit 77; }
[ -r /proc/self/status ] || { echo "SKIP: no /proc"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
ok() { echo "ok - $*"; }
bad() { echo "not ok - $*"; fail=1; }

# handler_in PID: true once the rigflow binary (not libtool's wrapper script) catches SIGINT;
# false when the process is gone or after 30 s
handler_in() {
    local key val
    for _ in $(seq 30000); do
        [ -d "/proc/$1" ] || return 1
        case "$(readlink "/proc/$1/exe" 2>/dev/null)" in */bash | */sh | */dash | '') sleep 0.001; continue ;; esac
        while read -r key val; do
            [ "$key" = SigCgt: ] && (((0x$val & 2) != 0)) && return 0
        done <"/proc/$1/status" 2>/dev/null
        sleep 0.001
    done
    return 1
}

# interrupt NAME DIR COMMAND...: runs COMMAND in DIR, Ctrl-C once its handler is in place
interrupt() {
    local name=$1 dir=$2 code=0 try
    shift 2
    for try in 1 2 3; do
        rm -rf "$dir" && mkdir -p "$dir"
        (cd "$dir" && exec env --default-signal=INT "$@" >"$tmp/out" 2>"$tmp/err") &
        local pid=$!
        handler_in "$pid" && kill -INT "$pid"
        wait "$pid"
        code=$?
        [ "$code" = 0 ] || break # 0: the run ended before the signal; try again
    done
    local left
    left=$(ls -A "$dir")
    if [ "$code" = 130 ] && grep -q "interrupted" "$tmp/err" && [ -z "$left" ]; then
        ok "$name: Ctrl-C stops it, exit 130, nothing left"
    else
        bad "$name: exit $code (130 expected), left: '$left', stderr: $(head -c 300 "$tmp/err")"
    fi
}

node "$src/tests/report/make-bvh.mjs" tail 22 | awk -v n=200000 '/^Frames:/ { print "Frames: " n; next }
    /^Frame Time/ { print; getline; for (i = 0; i < n; i++) print; exit } { print }' >"$tmp/long.bvh"
node "$src/tests/report/make-bvh.mjs" tail 40 >"$tmp/plain.bvh"

interrupt "rigflow map -o" "$tmp/map" "$rigflow" map "$tmp/long.bvh" "$tmp/plain.bvh" -o map.json
interrupt "rigflow inspect" "$tmp/inspect" "$rigflow" inspect "$tmp/long.bvh"
model="$data/models/RobotExpressive.glb"
if [ -f "$model" ]; then
    interrupt "rigflow rig-bench" "$tmp/bench" "$rigflow" rig-bench "$model"
else
    echo "# SKIP rigflow rig-bench: $model not found (RF_DATA_DIR)"
fi
exit $fail

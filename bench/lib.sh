# Sourced by the benchmarks that run beside the shared peers: the paths they share and the
# writable copy of the peers folder three.js is installed into, so both live in one place.
# The caller sets src (the source tree) first.

say() { printf '%s\n' "$*" >&2; }

# bench_paths BUILDDIR NAME: sets build, shared, peers, data and work ($build/bench-NAME, made).
bench_paths() {
    build=$(cd "$1" && pwd)
    shared=${RF_SHARED_DIR:-$src/../shared}
    peers=$shared/peers
    data=${RF_DATA_DIR:-$shared/data}
    work=$build/bench-$2
    mkdir -p "$work"
}

# bench_three: sets tpeers to a copy of the peers folder with three.js installed (npm, as pinned
# by the peers' package.json); the shared folder is read-only, so the copy lives under $work.
bench_three() {
    tpeers=$work/peers
    [ -d "$tpeers/node_modules/three" ] && return 0
    rm -rf "$tpeers" && cp -R "$peers" "$tpeers" && chmod -R u+w "$tpeers"
    ln -sfn "$data" "$work/data" # the peers' scripts look for ../data
    (cd "$tpeers" && npm install --no-audit --no-fund --silent) >&2
}

#!/usr/bin/env bash
# rigflow quick start. One command per job:
#   ./quickstart.sh          install what is missing, build, retarget a mocap walk onto a quadruped
#   ./quickstart.sh check    install what is missing, build with -Werror, run the whole test suite
#   ./quickstart.sh deps     only install what is missing (Debian packages; npm tools for tests)
#   ./quickstart.sh build    only configure and build (into _build/)
#   ./quickstart.sh check-asan   the test suite again, built with ASan and UBSan (into _build-asan/)
#   ./quickstart.sh fuzz [SECONDS]  build the fuzz harnesses with clang, run each (default 60 s)
#   ./quickstart.sh valgrind     the end-to-end tests with every command under valgrind memcheck
# Works without a terminal (CI=true). Installing needs root or sudo; nothing else is downloaded.
set -euo pipefail
cd "$(dirname "$0")"
top=$(pwd)
build="$top/_build"

debs=(build-essential autoconf automake libtool pkg-config libltdl-dev libassimp-dev
      libjansson-dev libglib2.0-dev libcmocka-dev assimp-utils assimp-testmodels nodejs npm
      clang libclang-rt-14-dev valgrind strace
      libsuitesparse-dev libembree-dev libmeshoptimizer-dev)

say() { printf '==> %s\n' "$*" >&2; }

as_root() {
    if [ "$(id -u)" = 0 ]; then "$@"
    elif command -v sudo >/dev/null; then sudo "$@"
    else say "need root to run: $*"; exit 1
    fi
}

deps() {
    local missing=()
    for p in "${debs[@]}"; do
        # node and npm may come from elsewhere than Debian: any working ones will do
        case "$p" in nodejs) command -v node >/dev/null && continue ;;
                     npm) command -v npm >/dev/null && continue ;; esac
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
    done
    if [ "${#missing[@]}" -gt 0 ]; then
        say "installing Debian packages: ${missing[*]}"
        as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq
        as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
    fi
    npm_tools
}

# Test-only tools from the npm registry, kept inside the build folder (never committed).
npm_tools() {
    local dir="$build/npm"
    [ -f "$top/tests/npm-tools.txt" ] || return 0
    command -v npm >/dev/null || { say "npm not found: tests that need it will skip"; return 0; }
    mkdir -p "$dir"
    local want=() pkg
    while read -r pkg; do
        case "$pkg" in ''|'#'*) continue ;; esac
        [ -d "$dir/node_modules/${pkg%@*}" ] || want+=("$pkg")
    done <"$top/tests/npm-tools.txt"
    if [ "${#want[@]}" -gt 0 ]; then
        say "installing npm tools for the tests: ${want[*]}"
        npm install --silent --no-audit --no-fund --prefix "$dir" "${want[@]}" >/dev/null ||
            say "npm install failed: tests that need ${want[*]} will skip"
    fi
}

configure_build() {
    [ -x "$top/configure" ] || (cd "$top" && autoreconf -fi >/dev/null 2>&1)
    mkdir -p "$build"
    cd "$build"
    [ -f Makefile ] || "$top/configure" --enable-werror -q "$@"
    make -j"$(nproc)" >/dev/null
    cd "$top"
}

# Sample data: the shared data folder beside the checkout, else Debian's assimp-testmodels (which
# has the same CMU walk and a quadruped, Testwuson).
sample_data() {
    local d
    for d in "${RF_DATA_DIR:-}" "$top/../shared/data"; do
        if [ -n "$d" ] && [ -f "$d/bvh/cmu_01_01.bvh" ] && [ -f "$d/models/Fox.glb" ]; then
            echo "$d/bvh/cmu_01_01.bvh $d/models/Fox.glb"; return
        fi
    done
    echo /usr/share/assimp/models/BVH/01_01.bvh /usr/share/assimp/models/X/Testwuson.X
}

# The main job: a CMU mocap walk retargeted onto a quadruped, written as GLB.
demo() {
    deps
    configure_build
    mkdir -p "$top/out"
    local motion target out="$top/out/walk.glb"
    read -r motion target <<<"$(sample_data)"
    say "retargeting $(basename "$motion") onto $(basename "$target") (pipelines/retarget.json)"
    "$build/rigflow" run "$top/pipelines/retarget.json" \
        -p source.path="$motion" -p target.path="$target" -p export.path="$out"
    say "wrote $out"
}

check() {
    deps
    configure_build
    cd "$build"
    make -j"$(nproc)" check RF_NPM_DIR="$build/npm/node_modules"
}

# The reliability runs (doc/reliability.md): a sanitizer build beside _build, fuzzing
# and valgrind in _build.
check_asan() {
    deps
    build="$top/_build-asan" configure_build --enable-sanitizers
    cd "$top/_build-asan"
    make -j"$(nproc)" check RF_NPM_DIR="$build/npm/node_modules"
}

fuzz() {
    deps
    configure_build
    make -C "$build" fuzz FUZZ_SECONDS="${1:-60}"
}

valgrind_check() {
    deps
    configure_build
    make -C "$build" valgrind
}

case "${1:-demo}" in
    demo) demo ;;
    check) check ;;
    deps) deps ;;
    build) configure_build ;;
    check-asan) check_asan ;;
    fuzz) fuzz "${2:-60}" ;;
    valgrind) valgrind_check ;;
    -h|--help) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' ;;
    *) say "unknown job '$1' (see ./quickstart.sh --help)"; exit 2 ;;
esac

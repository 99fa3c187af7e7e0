#!/usr/bin/env bash
# Every public header compiles on its own, in C11 and in C++, with -Wall -Wextra -pedantic.
set -u
inc="${RF_SRCDIR:?}/sdk/include"
cc="${CC:-cc}"
cxx=$(command -v c++ || command -v g++ || true)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
for h in "$inc"/rigflow/*.h; do
    name=$(basename "$h")
    printf '#include <rigflow/%s>\nint main(void) { return 0; }\n' "$name" >"$tmp/t.c"
    if $cc -std=c11 -Wall -Wextra -pedantic -Werror -I"$inc" -c "$tmp/t.c" -o "$tmp/t.o" 2>"$tmp/err"; then
        pass=$((pass + 1)); echo "ok - $name compiles alone as C11"
    else
        fail=$((fail + 1)); echo "not ok - $name as C11"; sed 's/^/    /' "$tmp/err"
    fi
    if [ -z "$cxx" ]; then echo "# skipped C++: no C++ compiler"; continue; fi
    cp "$tmp/t.c" "$tmp/t.cc"
    if $cxx -std=c++11 -Wall -Wextra -pedantic -Werror -I"$inc" -c "$tmp/t.cc" -o "$tmp/t.o" 2>"$tmp/err"; then
        pass=$((pass + 1)); echo "ok - $name compiles alone as C++11"
    else
        fail=$((fail + 1)); echo "not ok - $name as C++11"; sed 's/^/    /' "$tmp/err"
    fi
done
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

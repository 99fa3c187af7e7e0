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
# prefault.h calls madvise only where <sys/mman.h> declares it: a strict C11 unit that took
# MADV_POPULATE_WRITE from <linux/mman.h> (whose madvise stays hidden) must still compile.
if [ -e /usr/include/linux/mman.h ]; then
    printf '#include <linux/mman.h>\n#include <rigflow/prefault.h>\nvoid f(void *p, size_t n);\nvoid f(void *p, size_t n) { rf_prefault(p, n); }\n' >"$tmp/t.c"
    if $cc -std=c11 -Wall -Wextra -pedantic -Werror -I"$inc" -c "$tmp/t.c" -o "$tmp/t.o" 2>"$tmp/err"; then
        pass=$((pass + 1)); echo "ok - prefault.h after <linux/mman.h> as strict C11"
    else
        fail=$((fail + 1)); echo "not ok - prefault.h after <linux/mman.h> as strict C11"; sed 's/^/    /' "$tmp/err"
    fi
else
    echo "# skipped prefault.h after <linux/mman.h>: no such header here"
fi
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

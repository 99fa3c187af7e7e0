/* Allocation failure on demand for the out-of-memory tests: a program that includes this once and
 * links with -Wl,--wrap=malloc,--wrap=calloc fails its malloc or calloc call number `fail_at`
 * (counted in `calls` from 0) and serves every other one; -1 fails none. Only the code linked
 * into the program is wrapped, not the shared libraries it loads. */
#ifndef RIGFLOW_ALLOC_FAIL_H
#define RIGFLOW_ALLOC_FAIL_H

#include <stddef.h>

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t n, size_t size);
static long fail_at = -1, calls;

void *__wrap_malloc(size_t n)
{
    return calls++ == fail_at ? NULL : __real_malloc(n);
}

void *__wrap_calloc(size_t n, size_t size)
{
    return calls++ == fail_at ? NULL : __real_calloc(n, size);
}

#endif

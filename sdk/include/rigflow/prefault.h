/* rigflow SDK: large new arrays mapped in one call instead of page by page.
 *
 * A new array of megabytes from malloc is memory the kernel has not mapped yet: every page (4 KiB
 * on x86-64) then costs one page fault when first written. In a virtual machine a fault is an exit
 * to the hypervisor, several microseconds; the 10,000-frame retarget run took 3,400 of them, about
 * as long as its whole BVH parse. MADV_POPULATE_WRITE (Linux 5.14) maps a range in one system call,
 * about 0.2 us a page. Call rf_prefault on an array that is about to be written in full (an
 * array filled only in part would map pages it never uses). Where the call is missing (another
 * system, an older kernel, a strict-ISO build without madvise) it does nothing: the pages then
 * fault in as usual, which is only slower.
 */
#ifndef RIGFLOW_PREFAULT_H
#define RIGFLOW_PREFAULT_H

#include <stddef.h>
#include <stdint.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif
/* madvise is declared only outside strict ISO/POSIX modes (glibc's _DEFAULT_SOURCE, musl's
 * _BSD_SOURCE, both implied by _GNU_SOURCE), while <linux/mman.h> may define MADV_POPULATE_WRITE
 * in any mode: both are needed. */
#if defined(MADV_POPULATE_WRITE) &&                                                                \
    (defined(_DEFAULT_SOURCE) || defined(_BSD_SOURCE) || defined(_GNU_SOURCE))
#define RF_PREFAULT_MADVISE 1
#include <unistd.h>
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Below this a range is left to fault in: a few faults cost less than the call. */
#define RF_PREFAULT_MIN ((size_t)1 << 18)

/* Maps the whole pages inside [p, p + size) for writing, when the range is large enough. */
static inline void rf_prefault(void *p, size_t size)
{
#if defined(RF_PREFAULT_MADVISE)
    /* the system's page (16 or 64 KiB on some arm64 and ppc64le kernels): madvise refuses a
     * start that is not aligned to it */
    long ps = sysconf(_SC_PAGESIZE);
    const uintptr_t page = ps > 0 && !((uintptr_t)ps & ((uintptr_t)ps - 1)) ? (uintptr_t)ps : 4096;
    if (!p || size < RF_PREFAULT_MIN)
        return;
    uintptr_t b = ((uintptr_t)p + page - 1) & ~(page - 1), e = ((uintptr_t)p + size) & ~(page - 1);
    if (e > b)
        (void)madvise((void *)b, e - b, MADV_POPULATE_WRITE);
#else
    (void)p, (void)size;
#endif
}

#ifdef __cplusplus
}
#endif

#endif

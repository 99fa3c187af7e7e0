/* Test fixture for rigflow batch, loaded with LD_PRELOAD: open() of the path in $RF_FX_EIO_PATH
 * for reading fails with EIO, as a disk error would, so the batch's read-back of a job's output
 * can be made to fail while the job itself (which writes a temporary file) succeeds. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

typedef int (*open_fn)(const char *, int, ...);

static int fx_open(const char *name, const char *path, int flags, va_list ap)
{
    mode_t mode = (flags & (O_CREAT | O_TMPFILE)) ? (mode_t)va_arg(ap, int) : 0;
    const char *bad = getenv("RF_FX_EIO_PATH");
    if (bad && *bad && path && strcmp(path, bad) == 0 && (flags & O_ACCMODE) == O_RDONLY) {
        errno = EIO;
        return -1;
    }
    open_fn real = (open_fn)dlsym(RTLD_NEXT, name);
    return real ? real(path, flags, mode) : (errno = ENOSYS, -1);
}

__attribute__((visibility("default"))) int open(const char *path, int flags, ...)
{
    va_list ap;
    va_start(ap, flags);
    int fd = fx_open("open", path, flags, ap);
    va_end(ap);
    return fd;
}

__attribute__((visibility("default"))) int open64(const char *path, int flags, ...)
{
    va_list ap;
    va_start(ap, flags);
    int fd = fx_open("open64", path, flags, ap);
    va_end(ap);
    return fd;
}

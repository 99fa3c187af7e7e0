/* What Assimp may read, and the stack it runs on.
 *
 * Confinement: a model names other files (glTF buffers and images, an Ogre mesh's skeleton, an
 * OBJ's material library, textures). A model comes from anywhere, so those names are data from a
 * stranger: Assimp's reads go through an aiFileIO that opens the model itself and regular files
 * inside the model's own folder (or below it) only. "../x", an absolute path elsewhere, or a
 * symbolic link leading out are refused, before anything is opened, and named in the import's
 * message. The file actually opened is checked again (/proc/self/fd), so swapping a folder for a
 * link between the check and the open gains nothing.
 *
 * Stack: Assimp's importers, its post-processing and aiReleaseImport recurse once per level of
 * node nesting (about 400 bytes a level for glTF: 8 MiB overflows near 20 000 levels), so a
 * hostile file crashes a naive import. The import runs on a thread whose stack is sized for the
 * file instead: a file of N bytes nests at most N/8 levels (no format spends fewer bytes on a
 * nested node), and each level gets RF_AI_STACK_PER_BYTE * 8 bytes. The stack is reserved
 * without being committed (MAP_NORESERVE): only the depth actually used costs memory.
 */
#define _GNU_SOURCE /* O_CLOEXEC, MAP_NORESERVE, MAP_STACK */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/cfileio.h>

#include "aimport-io.h"

/* ---- confinement ---- */

/* The path of the file open on fd (symbolic links resolved), or NULL. (transfer full) */
static char *rf_ai_fd_path(int fd, const char *opened_as)
{
    char link[64], buf[PATH_MAX];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    ssize_t n = readlink(link, buf, sizeof buf - 1);
    if (n > 0 && buf[0] == '/') {
        buf[n] = '\0';
        return strdup(buf);
    }
    return realpath(opened_as, NULL); /* no /proc: resolve the name instead */
}

static bool rf_ai_inside(const rf_ai_confine *cf, const char *real)
{
    size_t n = strlen(cf->root);
    return strncmp(real, cf->root, n) == 0 && (cf->root[n - 1] == '/' || real[n] == '/');
}

static void rf_ai_refuse(rf_ai_confine *cf, const char *path, const char *why)
{
    cf->refused_count++;
    if (cf->refused[0])
        return; /* the first refusal explains the failure; the count tells there were more */
    snprintf(cf->refused, sizeof cf->refused, "refused to read %s: %s", path, why);
}

/* Notes a file Assimp asked for that is not there (a probe, or a part of the model such as an
 * Ogre mesh's .skeleton): said only if the import then lacks the skeleton it needed. */
static bool rf_ai_listed(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ',' || p[n] == '\0'))
            return true; /* a whole entry, not the end of a longer name */
    return false;
}

static void rf_ai_note_missing(rf_ai_confine *cf, const char *path)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t used = strlen(cf->missing);
    if (!*base || rf_ai_listed(cf->missing, base) || used + strlen(base) + 3 >= sizeof cf->missing)
        return;
    snprintf(cf->missing + used, sizeof cf->missing - used, "%s%s", used ? ", " : "", base);
}

static size_t rf_ai_file_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    return fread(buf, size, count, (FILE *)f->UserData);
}

static size_t rf_ai_file_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0; /* an import never writes */
}

static size_t rf_ai_file_tell(struct aiFile *f)
{
    long at = ftell((FILE *)f->UserData);
    return at < 0 ? 0 : (size_t)at;
}

static size_t rf_ai_file_size(struct aiFile *f)
{
    struct stat st;
    return fstat(fileno((FILE *)f->UserData), &st) == 0 ? (size_t)st.st_size : 0;
}

static enum aiReturn rf_ai_file_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    if (offset > LONG_MAX)
        return aiReturn_FAILURE;
    return fseek((FILE *)f->UserData, (long)offset, whence) == 0 ? aiReturn_SUCCESS
                                                                 : aiReturn_FAILURE;
}

static void rf_ai_file_flush(struct aiFile *f)
{
    (void)f;
}

/* The file to open for `path`: the model as given, or the resolved path of a file inside the
 * model's folder. NULL when missing (Assimp also probes for files that need not exist) or refused
 * (recorded in cf). Checked before opening, so nothing outside is ever opened. (transfer full) */
static char *rf_ai_io_resolve(rf_ai_confine *cf, const char *path)
{
    if (strcmp(path, cf->model) == 0)
        return strdup(path);
    char *real = realpath(path, NULL);
    if (!real && errno == ENOENT)
        rf_ai_note_missing(cf, path);
    if (real && !rf_ai_inside(cf, real)) {
        rf_ai_refuse(cf, path,
                     "outside the model's folder (a model may only name files beside it or below)");
        free(real);
        return NULL;
    }
    return real;
}

/* Opens `path` for Assimp when it is the model or a regular file inside the model's folder. */
static struct aiFile *rf_ai_io_open(struct aiFileIO *io, const char *path, const char *mode)
{
    rf_ai_confine *cf = (rf_ai_confine *)io->UserData;
    if (!mode || mode[0] != 'r' || strchr(mode, '+')) {
        rf_ai_refuse(cf, path, "an import may not write files");
        return NULL;
    }
    char *name = rf_ai_io_resolve(cf, path);
    /* O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused just below). */
    int fd = name ? open(name, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK) : -1;
    if (fd < 0) {
        free(name);
        return NULL;
    }
    struct stat st;
    const char *why = NULL;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
        why = "not a regular file";
    else if (strcmp(path, cf->model) != 0) { /* a folder swapped for a link since the check */
        char *real = rf_ai_fd_path(fd, name);
        if (!real || !rf_ai_inside(cf, real))
            why = "outside the model's folder (it changed while being opened)";
        free(real);
    }
    free(name);
    FILE *file = why ? NULL : fdopen(fd, "rb");
    struct aiFile *f = file ? calloc(1, sizeof *f) : NULL;
    if (!f) {
        if (why)
            rf_ai_refuse(cf, path, why);
        if (file)
            fclose(file);
        else
            close(fd);
        return NULL;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    f->ReadProc = rf_ai_file_read, f->WriteProc = rf_ai_file_write;
    f->TellProc = rf_ai_file_tell, f->FileSizeProc = rf_ai_file_size;
    f->SeekProc = rf_ai_file_seek, f->FlushProc = rf_ai_file_flush;
    f->UserData = (aiUserData)file;
    return f;
}

static void rf_ai_io_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (!f)
        return;
    fclose((FILE *)f->UserData);
    free(f);
}

bool rf_ai_confine_init(rf_ai_confine *cf, const char *model_path, struct aiFileIO *io)
{
    memset(cf, 0, sizeof *cf);
    cf->model = model_path;
    char *copy = strdup(model_path);
    const char *slash = copy ? strrchr(copy, '/') : NULL;
    if (copy && slash)
        copy[slash == copy ? 1 : slash - copy] = '\0';
    cf->root = copy ? realpath(slash ? copy : ".", NULL) : NULL;
    free(copy);
    if (!cf->root)
        return false;
    io->OpenProc = rf_ai_io_open;
    io->CloseProc = rf_ai_io_close;
    io->UserData = (aiUserData)cf;
    return true;
}

void rf_ai_confine_clear(rf_ai_confine *cf)
{
    free(cf->root);
    cf->root = NULL;
}

/* ---- the stack ---- */

#define RF_AI_STACK_MIN ((size_t)64 << 20)
#define RF_AI_STACK_MAX ((size_t)64 << 30)
#define RF_AI_STACK_PER_BYTE 256u /* 2 KiB per nesting level of at least 8 bytes */

typedef struct rf_ai_call {
    void (*fn)(void *);
    void *arg;
} rf_ai_call;

static void *rf_ai_thread_main(void *p)
{
    rf_ai_call *call = p;
    call->fn(call->arg);
    return NULL;
}

/* Reserves `*size` bytes of stack (halving down to the minimum when refused) plus a guard page
 * below it. Returns the mapping, or NULL. */
static void *rf_ai_reserve_stack(size_t *size, size_t page)
{
    for (; *size >= RF_AI_STACK_MIN; *size /= 2) {
        *size = (*size + page - 1) / page * page;
        void *mem = mmap(NULL, *size + page, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE | MAP_STACK, -1, 0);
        if (mem == MAP_FAILED)
            continue;
        if (mprotect(mem, page, PROT_NONE) == 0)
            return mem;
        munmap(mem, *size + page);
    }
    return NULL;
}

void rf_ai_call_with_stack_for(const char *path, void (*fn)(void *), void *arg)
{
    struct stat st;
    size_t file = stat(path, &st) == 0 && st.st_size > 0 ? (size_t)st.st_size : 0;
    size_t size = file < (RF_AI_STACK_MAX - RF_AI_STACK_MIN) / RF_AI_STACK_PER_BYTE
                      ? RF_AI_STACK_MIN + file * RF_AI_STACK_PER_BYTE
                      : RF_AI_STACK_MAX;
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    void *mem = rf_ai_reserve_stack(&size, page);
    rf_ai_call call = {fn, arg};
    pthread_attr_t attr;
    pthread_t thread;
    bool started = mem && pthread_attr_init(&attr) == 0;
    if (started) {
        started = pthread_attr_setstack(&attr, (char *)mem + page, size) == 0 &&
                  pthread_create(&thread, &attr, rf_ai_thread_main, &call) == 0;
        pthread_attr_destroy(&attr);
    }
    if (started)
        pthread_join(thread, NULL);
    else
        fn(arg); /* no thread to be had: the caller's stack, as before */
    if (mem)
        munmap(mem, size + page);
}

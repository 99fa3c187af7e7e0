/* The BVH reader.
 *
 * The input is read in chunks into one buffer that always holds at least one complete line, with
 * a NUL after the last byte read: the per-frame loop then parses numbers with no bounds checks,
 * since every line ends in '\n' or that NUL. Memory is the decoded data plus one chunk (or the
 * longest line), whatever the file size. The hierarchy is parsed with an explicit stack, so any
 * nesting depth is fine, and joint names are checked for duplicates through a hash table.
 */
#define _POSIX_C_SOURCE 200809L
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* madvise */
#endif

#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bvh-math.h"
#include "bvh-num.h"
#include "rigflow/bvh.h"
#include "rigflow/prefault.h"

#define CHUNK_SMALL (1u << 16) /* bytes read at a time: small files keep memory low */
#define CHUNK_LARGE (1u << 18) /* and large ones give the threads batches of many lines */
#define PROGRESS_FRAMES 1024u
#define BATCH_LINES 512             /* frame lines taken from the buffer at a time */
#define MIN_SPLIT 16                /* fewer lines than twice this are not split between threads */
#define THREAD_MIN_BYTES (1u << 20) /* a helper thread only for this much motion data or more */

/* A helper thread needs POSIX threads; without them everything runs on the caller's thread. */
#if defined(__unix__) && !defined(BVH_NO_THREADS)
#define BVH_THREADS 1
#include <pthread.h>
#include <stdatomic.h>
#include <time.h>
#if defined(__x86_64__) || defined(__i386__)
#include <emmintrin.h>
#endif
#else
#define BVH_THREADS 0
#endif

/* ---- input: complete lines from a file or memory ---- */

typedef struct source {
    FILE *file;      /* NULL when reading memory */
    const char *mem; /* memory input */
    size_t mem_size, mem_pos;
    char *buf; /* unread data is buf[pos, len); buf[len] == '\0', then BVH_PAD
                * more readable bytes */
    size_t cap, len, pos;
    size_t scan; /* buf[pos, scan) holds no '\n' (no rescans while refilling) */
    bool eof;
    uint64_t base;      /* input offset of buf[0] */
    uint64_t total;     /* size of the whole input */
    size_t chunk;       /* the usual read size */
    unsigned long line; /* number of the line at buf[pos], from 1 */
} source;

/* Moves the unread bytes to the front and reads more, growing the buffer when it is full of one
 * unfinished line. Returns false with errno set on a read error or when out of memory. */
static bool source_fill(source *s)
{
    size_t keep = s->len - s->pos;
    if (s->pos) {
        memmove(s->buf, s->buf + s->pos, keep);
        s->base += s->pos;
        s->scan -= s->pos;
        s->len = keep;
        s->pos = 0;
    }
    /* Grow when a line fills the buffer, or when little room is left and more input is known to
     * follow (so reads stay large). */
    size_t room = s->cap - 1 - s->len;
    uint64_t left = s->total > s->base + s->len ? s->total - s->base - s->len : 0;
    if (room == 0 || (room < s->chunk / 4 && left > room)) {
        size_t cap = s->cap * 2;
        char *b = realloc(s->buf, cap + BVH_PAD);
        if (!b)
            return false;
        s->buf = b, s->cap = cap;
    }
    size_t want = s->cap - 1 - s->len, got;
    if (s->file) {
        got = fread(s->buf + s->len, 1, want, s->file);
        if (got < want && ferror(s->file))
            return false;
    } else {
        got = s->mem_size - s->mem_pos < want ? s->mem_size - s->mem_pos : want;
        memcpy(s->buf + s->len, s->mem + s->mem_pos, got);
        s->mem_pos += got;
    }
    s->eof = got == 0;
    s->len += got;
    memset(s->buf + s->len, 0, BVH_PAD); /* the NUL, and bytes bvh_number_padded may read */
    return true;
}

/* The current line: its start, with *end at its '\n' (or at the final NUL for a last line
 * without one). NULL at the end of the input, or on a read error (errno set, *end NULL).
 * Pointers into the buffer stay valid until the next source_line call after source_next. */
static char *source_line(source *s, char **end)
{
    for (;;) {
        char *nl = memchr(s->buf + s->scan, '\n', s->len - s->scan);
        if (nl) {
            *end = nl;
            return s->buf + s->pos;
        }
        s->scan = s->len;
        if (s->eof) {
            *end = s->buf + s->len;
            return s->pos < s->len ? s->buf + s->pos : NULL;
        }
        if (!source_fill(s)) {
            *end = NULL;
            return NULL;
        }
    }
}

/* Consumes the current line, which ends at `end`. */
static void source_next(source *s, const char *end)
{
    s->pos = (size_t)(end - s->buf) + (end < s->buf + s->len);
    s->scan = s->pos;
    s->line++;
}

static uint64_t source_offset(const source *s)
{
    return s->base + s->pos;
}

/* ---- parser state ---- */

enum { CH_XPOS, CH_YPOS, CH_ZPOS, CH_XROT, CH_YROT, CH_ZROT };

/* Coordinates (offsets and position channels) beyond this are refused: the model keeps animated
 * positions as floats (which end at 3.4e38) and what reads them squares distances. No motion
 * capture comes near. */
#define BVH_MAX_COORD 1e30
static const char *const channel_names[6] = {"Xposition", "Yposition", "Zposition",
                                             "Xrotation", "Yrotation", "Zrotation"};

/* Whether a position channel's value is in range as the model holds it, a float: the float
 * nearest the limit lies just past it (1.00000002e+30 as written), and a file written from a
 * clip at the limit must read back. The first test keeps (float)v defined. */
static bool channel_in_range(double v)
{
    return fabs(v) <= BVH_MAX_COORD ||
           (fabs(v) < 2 * BVH_MAX_COORD && fabsf((float)v) <= (float)BVH_MAX_COORD);
}

typedef struct pjoint {
    char *name;
    int32_t parent;
    uint32_t flags;
    double offset[3];
    double end_site[3];
    unsigned long line; /* where it was declared */
    uint8_t nch;
    uint8_t ch[6]; /* CH_* in file order */
} pjoint;

/* How a joint's values are found in a frame's values, for the per-frame loop. */
typedef struct jplan {
    uint32_t rot[3]; /* value index of each rotation channel in listed order; missing ones point
                      * at a padding value of 0 degrees */
    uint8_t axis[3]; /* 0 = X, 1 = Y, 2 = Z for each; missing ones complete the permutation */
    double e;        /* +1 when the axes are in cyclic order (XYZ, YZX, ZXY), else -1 */
    int32_t pos[3];  /* value index of the X, Y, Z position channels, or -1 for the OFFSET */
} jplan;

/* Work space for turning one frame line into poses; one per thread. */
typedef struct scratch {
    double *vals, *sn, *cs; /* the frame's values and their half-angle sines and cosines */
    bool huge;              /* vals may hold angles too large for bvh_sincos_half */
    uint32_t *pos;          /* where a line's numbers start and end (bvh_line_avx2) */
} scratch;

typedef struct parser {
    source src;
    const char *name; /* for messages */
    const rf_bvh_read_opts *opts;
    char *err;
    size_t err_size;
    bool failed;
    /* hierarchy */
    pjoint *joints;
    size_t count, joints_cap;
    int32_t *stack; /* open joints */
    size_t depth, stack_cap;
    int32_t *names; /* hash table of joint index + 1, 0 for empty */
    size_t names_cap;
    size_t channels; /* total channels, the values per frame */
    /* per-frame work: the joints' plans, and this thread's work space (allocated once) */
    jplan *plan;
    scratch main;
    bool avx2; /* the processor has AVX2: sines and cosines four at a time, lines by masks */
#if BVH_TOKEN_AVX2
    uint8_t shuf[BVH_SHUFFLES][16]; /* bvh_short_avx2's table, made with the plan */
#endif
    /* tokenizer: the rest of the current line */
    char *cur, *end;
} parser;

typedef struct token {
    const char *p;
    size_t n;
    unsigned long line;
} token;

static bool fail(parser *ps, unsigned long line, const char *fmt, ...) RF_PRINTF(3, 4);

static bool fail(parser *ps, unsigned long line, const char *fmt, ...)
{
    if (ps->failed)
        return false;
    ps->failed = true;
    int n = snprintf(ps->err, ps->err_size, "%s:%lu: ", ps->name, line);
    if (n >= 0 && (size_t)n < ps->err_size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(ps->err + n, ps->err_size - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return false;
}

static bool fail_read(parser *ps)
{
    return fail(ps, ps->src.line, "cannot read: %s", errno ? strerror(errno) : "out of memory");
}

/* A short quoted rendering of the text at p (up to whitespace), for "found ..." in messages. */
static const char *describe(const char *p, const char *end, char *buf, size_t size)
{
    size_t n = 0;
    while (p + n < end && p[n] && p[n] != ' ' && p[n] != '\t' && p[n] != '\r' && p[n] != '\n')
        n++;
    if (n == 0)
        snprintf(buf, size, p < end && !*p ? "a NUL byte" : "the end of the line");
    else if (n > 40)
        snprintf(buf, size, "'%.40s...'", p);
    else
        snprintf(buf, size, "'%.*s'", (int)n, p);
    return buf;
}

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

static char *skip_spaces(char *p, const char *end)
{
    while (p < end && is_space(*p))
        p++;
    return p;
}

/* The next whitespace-separated token of the hierarchy, across lines. False at the end of the
 * input (or on a read error, which sets ps->failed). */
static bool next_token(parser *ps, token *t)
{
    for (;;) {
        if (!ps->cur) {
            ps->cur = source_line(&ps->src, &ps->end);
            if (!ps->cur) {
                if (!ps->end)
                    fail_read(ps);
                return false;
            }
        }
        while (ps->cur < ps->end && is_space(*ps->cur))
            ps->cur++;
        if (ps->cur == ps->end) {
            source_next(&ps->src, ps->end);
            ps->cur = NULL;
            continue;
        }
        t->p = ps->cur;
        t->line = ps->src.line;
        do
            ps->cur++;
        while (ps->cur < ps->end && !is_space(*ps->cur) && *ps->cur);
        t->n = (size_t)(ps->cur - t->p);
        return true;
    }
}

static char ascii_lower(char c)
{
    return c >= 'A' && c <= 'Z' ? (char)(c + ('a' - 'A')) : c;
}

/* Whether the token is `word`, ASCII case ignored (no locale: keywords are ASCII). */
static bool tok_is(const token *t, const char *word)
{
    size_t i = 0;
    for (; i < t->n; i++)
        if (!word[i] || ascii_lower(t->p[i]) != ascii_lower(word[i]))
            return false;
    return word[i] == '\0';
}

static bool fail_expected(parser *ps, const token *t, const char *what)
{
    char found[64];
    if (!t)
        return fail(ps, ps->src.line, "expected %s, found the end of the file", what);
    return fail(ps, t->line, "expected %s, found %s", what, describe(t->p, t->p + t->n, found, 64));
}

/* Reads the next token and checks it is `word`; `what` says what it belongs to. */
static bool expect_word(parser *ps, const char *word, const char *what)
{
    token t;
    char buf[128];
    bool got = next_token(ps, &t);
    if (got && tok_is(&t, word))
        return true;
    if (ps->failed)
        return false;
    snprintf(buf, sizeof buf, "%s%s", word, what);
    return fail_expected(ps, got ? &t : NULL, buf);
}

/* Parses a finite number that makes up the whole token. */
static bool token_number(parser *ps, const token *t, double *v, const char *what)
{
    const char *e = bvh_number(t->p, v), *w = t->p + (*t->p == '-' || *t->p == '+');
    if (e && e == t->p + t->n && isfinite(*v))
        return true;
    char found[64];
    describe(t->p, t->p + t->n, found, sizeof found);
    if (!e && (strncasecmp(w, "nan", 3) == 0 || strncasecmp(w, "inf", 3) == 0))
        return fail(ps, t->line, "%s is not a finite number: expected %s", found, what);
    if (!e || e != t->p + t->n)
        return fail(ps, t->line, "expected %s, found %s", what, found);
    if (!isfinite(*v))
        return fail(ps, t->line, "%s is not a finite number: expected %s", found, what);
    return true;
}

static bool read_offset(parser *ps, double out[3], const char *what)
{
    static const char *const coord[3] = {"the OFFSET's x", "the OFFSET's y", "the OFFSET's z"};
    if (!expect_word(ps, "OFFSET", what))
        return false;
    for (int i = 0; i < 3; i++) {
        token t;
        if (!next_token(ps, &t))
            return ps->failed ? false : fail_expected(ps, NULL, coord[i]);
        if (!token_number(ps, &t, &out[i], coord[i]))
            return false;
        if (!(fabs(out[i]) <= BVH_MAX_COORD)) {
            char found[64];
            describe(t.p, t.p + t.n, found, sizeof found);
            return fail(ps, t.line, "%s is out of range: expected %s within +-%g", found, coord[i],
                        BVH_MAX_COORD);
        }
    }
    return true;
}

/* ---- joint names ---- */

static uint64_t hash_name(const char *s)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

static bool names_grow(parser *ps)
{
    size_t cap = ps->names_cap ? ps->names_cap * 2 : 64;
    int32_t *t = calloc(cap, sizeof *t);
    if (!t)
        return false;
    for (size_t i = 0; i < ps->names_cap; i++) {
        if (!ps->names[i])
            continue;
        size_t h = (size_t)hash_name(ps->joints[ps->names[i] - 1].name) & (cap - 1);
        while (t[h])
            h = (h + 1) & (cap - 1);
        t[h] = ps->names[i];
    }
    free(ps->names);
    ps->names = t, ps->names_cap = cap;
    return true;
}

/* Adds joint `index` to the name table, or returns the index of a joint of that name. */
static int32_t names_insert(parser *ps, int32_t index)
{
    if ((ps->count + 1) * 2 > ps->names_cap && !names_grow(ps))
        return -2;
    const char *name = ps->joints[index].name;
    size_t h = (size_t)hash_name(name) & (ps->names_cap - 1);
    for (; ps->names[h]; h = (h + 1) & (ps->names_cap - 1))
        if (strcmp(ps->joints[ps->names[h] - 1].name, name) == 0)
            return ps->names[h] - 1;
    ps->names[h] = index + 1;
    return -1;
}

/* ---- hierarchy ---- */

static bool grow(void **arr, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return true;
    size_t c = *cap ? *cap * 2 : 64;
    void *p = realloc(*arr, c * elem);
    if (!p)
        return false;
    *arr = p, *cap = c;
    return true;
}

/* The joint name: the rest of the line, trimmed, without a trailing "{" (also returned). */
static char *read_name(parser *ps, bool *brace)
{
    char *p = ps->cur ? ps->cur : ps->end, *e = ps->end;
    while (p < e && is_space(*p))
        p++;
    while (e > p && is_space(e[-1]))
        e--;
    *brace = e > p && e[-1] == '{';
    if (*brace)
        for (e--; e > p && is_space(e[-1]);)
            e--;
    ps->cur = ps->end; /* the line is used up */
    size_t n = (size_t)(e - p);
    char *name = malloc(n + 1);
    if (name) {
        memcpy(name, p, n);
        name[n] = '\0';
    }
    return name;
}

static int channel_code(const token *t)
{
    for (int c = 0; c < 6; c++)
        if (tok_is(t, channel_names[c]))
            return c;
    return -1;
}

static bool read_channels(parser *ps, pjoint *j)
{
    token t;
    double v;
    if (!expect_word(ps, "CHANNELS", " after the OFFSET"))
        return false;
    if (!next_token(ps, &t))
        return ps->failed ? false : fail_expected(ps, NULL, "the channel count");
    if (!token_number(ps, &t, &v, "the channel count (0 to 6)"))
        return false;
    if (v != floor(v) || v < 0 || v > 6)
        return fail_expected(ps, &t, "a channel count from 0 to 6");
    j->nch = (uint8_t)v;
    for (int i = 0; i < j->nch; i++) {
        if (!next_token(ps, &t))
            return ps->failed ? false : fail_expected(ps, NULL, "a channel name");
        int c = channel_code(&t);
        if (c < 0) {
            char found[64];
            return fail(ps, t.line,
                        "unknown channel %s: expected Xposition, Yposition, Zposition, "
                        "Xrotation, Yrotation or Zrotation",
                        describe(t.p, t.p + t.n, found, sizeof found));
        }
        for (int k = 0; k < i; k++)
            if (j->ch[k] == c)
                return fail(ps, t.line, "channel %s listed twice for joint '%s'", channel_names[c],
                            j->name);
        j->ch[i] = (uint8_t)c;
    }
    ps->channels += j->nch;
    return true;
}

static bool open_joint(parser *ps, const char *keyword, unsigned long line)
{
    bool brace;
    if (!grow((void **)&ps->joints, &ps->joints_cap, ps->count + 1, sizeof *ps->joints) ||
        !grow((void **)&ps->stack, &ps->stack_cap, ps->depth + 1, sizeof *ps->stack))
        return fail(ps, line, "out of memory");
    int32_t index = (int32_t)ps->count;
    pjoint *j = &ps->joints[ps->count];
    memset(j, 0, sizeof *j);
    j->parent = ps->depth ? ps->stack[ps->depth - 1] : -1;
    j->line = line;
    j->name = read_name(ps, &brace);
    if (!j->name)
        return fail(ps, line, "out of memory");
    ps->count++; /* owned from here: freed with the others */
    if (!j->name[0])
        return fail(ps, line, "expected a joint name after %s", keyword);
    int32_t dup = names_insert(ps, index);
    if (dup == -2)
        return fail(ps, line, "out of memory");
    if (dup >= 0)
        return fail(ps, line,
                    "duplicate joint name '%s' (first declared on line %lu): expected "
                    "unique names",
                    j->name, ps->joints[dup].line);
    if (!brace && !expect_word(ps, "{", " after the joint name"))
        return false;
    if (!read_offset(ps, j->offset, " in the joint") || !read_channels(ps, j))
        return false;
    ps->stack[ps->depth++] = index;
    return true;
}

static bool read_end_site(parser *ps)
{
    pjoint *j = &ps->joints[ps->stack[ps->depth - 1]];
    unsigned long line = ps->src.line;
    if (!expect_word(ps, "Site", " after End") || !expect_word(ps, "{", " after End Site"))
        return false;
    if (j->flags & RF_JOINT_HAS_END_SITE)
        return fail(ps, line, "second End Site in joint '%s': expected at most one", j->name);
    if (!read_offset(ps, j->end_site, " in the End Site") ||
        !expect_word(ps, "}", " closing the End Site"))
        return false;
    j->flags |= RF_JOINT_HAS_END_SITE;
    return true;
}

/* One step inside an open joint: JOINT, End Site or '}'. */
static bool hierarchy_inner(parser *ps, const token *t)
{
    if (tok_is(t, "JOINT"))
        return open_joint(ps, "JOINT", t->line);
    if (tok_is(t, "End"))
        return read_end_site(ps);
    if (tok_is(t, "}")) {
        ps->depth--;
        return true;
    }
    char what[200];
    snprintf(what, sizeof what, "JOINT, End Site or '}' in joint '%.100s'",
             ps->joints[ps->stack[ps->depth - 1]].name);
    return fail_expected(ps, t, what);
}

/* Parses from HIERARCHY up to and including the MOTION line. */
static bool parse_hierarchy(parser *ps)
{
    token t;
    if (!next_token(ps, &t))
        return ps->failed ? false : fail_expected(ps, NULL, "HIERARCHY");
    if (!tok_is(&t, "HIERARCHY"))
        return fail_expected(ps, &t, "HIERARCHY at the start of the file");
    for (;;) {
        if (!next_token(ps, &t)) {
            if (ps->failed)
                return false;
            if (ps->depth) {
                const pjoint *j = &ps->joints[ps->stack[ps->depth - 1]];
                return fail(ps, ps->src.line,
                            "the file ends inside joint '%s' (opened on line %lu): expected '}'",
                            j->name, j->line);
            }
            return fail(ps, ps->src.line, "the file ends before MOTION: expected %s",
                        ps->count ? "ROOT or MOTION" : "ROOT");
        }
        if (ps->depth) {
            if (!hierarchy_inner(ps, &t))
                return false;
        } else if (tok_is(&t, "ROOT")) {
            if (!open_joint(ps, "ROOT", t.line))
                return false;
        } else if (tok_is(&t, "MOTION") && ps->count) {
            break;
        } else {
            return fail_expected(ps, &t, ps->count ? "ROOT or MOTION" : "ROOT");
        }
    }
    char *rest = skip_spaces(ps->cur, ps->end), found[64];
    if (rest != ps->end)
        return fail(ps, t.line, "expected the end of the line after MOTION, found %s",
                    describe(rest, ps->end, found, sizeof found));
    source_next(&ps->src, ps->end);
    ps->cur = NULL;
    return true;
}

/* ---- motion ---- */

/* The next line that holds anything but whitespace; NULL at the end of the input. */
static char *next_nonblank(parser *ps, char **end)
{
    for (;;) {
        char *p = source_line(&ps->src, end);
        if (!p) {
            if (!*end)
                fail_read(ps);
            return NULL;
        }
        char *q = p;
        while (q < *end && is_space(*q))
            q++;
        if (q < *end)
            return p;
        source_next(&ps->src, *end);
    }
}

/* Matches the words of a label such as "Frame Time:" at p, spaces between the words and before
 * the colon optional; returns the position after it or NULL. */
static char *match_label(char *p, const char *end, const char *const *words, int count)
{
    for (int i = 0; i < count; i++) {
        size_t n = strlen(words[i]);
        p = skip_spaces(p, end);
        if ((size_t)(end - p) < n || strncasecmp(p, words[i], n) != 0)
            return NULL;
        p += n;
    }
    p = skip_spaces(p, end);
    return p < end && *p == ':' ? p + 1 : NULL;
}

/* Reads "LABEL: number" on the next non-blank line into *v; `what` describes the number. */
static bool read_header_value(parser *ps, const char *const *words, int count, const char *label,
                              const char *what, double *v, unsigned long *line)
{
    char *end, *p = next_nonblank(ps, &end), found[64];
    if (!p)
        return ps->failed
                   ? false
                   : fail(ps, ps->src.line, "the file ends early: expected '%s' %s", label, what);
    char *q = match_label(p, end, words, count);
    if (!q)
        return fail(ps, ps->src.line, "expected '%s' followed by %s, found %s", label, what,
                    describe(skip_spaces(p, end), end, found, 64));
    q = skip_spaces(q, end);
    *line = ps->src.line;
    const char *e = bvh_number(q, v);
    if (!e || skip_spaces((char *)e, end) != end)
        return fail(ps, ps->src.line, "expected %s after '%s', found %s", what, label,
                    describe(q, end, found, 64));
    source_next(&ps->src, end);
    return true;
}

static bool read_motion_header(parser *ps, uint32_t *frames, double *frame_time,
                               unsigned long *frames_line)
{
    static const char *const frames_words[] = {"Frames"};
    static const char *const time_words[] = {"Frame", "Time"};
    double n;
    unsigned long time_line;
    if (!read_header_value(ps, frames_words, 1, "Frames:", "a whole number of frames", &n,
                           frames_line))
        return false;
    if (!(n >= 0 && n <= UINT32_MAX - 1 && n == floor(n)))
        return fail(ps, *frames_line,
                    "expected a whole number of frames from 0 to %" PRIu32 " after 'Frames:', "
                    "found %g",
                    (uint32_t)(UINT32_MAX - 1), n);
    *frames = (uint32_t)n;
    if (!read_header_value(ps, time_words, 2, "Frame Time:", "the seconds per frame", frame_time,
                           &time_line))
        return false;
    if (!(*frame_time > 0) || !isfinite(*frame_time) || !isfinite(1.0 / *frame_time))
        return fail(ps, time_line, "expected a positive Frame Time, found %g", *frame_time);
    return true;
}

/* Refuses a Frames count the rest of the input cannot hold before allocating for it: each frame
 * takes at least one digit and one separator per value (the last frame needs no final newline),
 * or one newline for a frame of no values. */
static bool check_frame_bound(parser *ps, uint32_t frames, unsigned long frames_line)
{
    uint64_t at = source_offset(&ps->src);
    uint64_t remaining = ps->src.total > at ? ps->src.total - at : 0;
    uint64_t most = ps->channels ? (remaining + 1) / (2 * (uint64_t)ps->channels) : remaining;
    if (frames <= most)
        return true;
    return fail(ps, frames_line,
                "'Frames: %" PRIu32 "' is more than the rest of the file can hold (%" PRIu64
                " bytes, at most %" PRIu64 " frames of %zu values): expected the number of "
                "frames that follow (truncated MOTION?)",
                frames, remaining, most, ps->channels);
}

static size_t count_values(const char *p, const char *end)
{
    size_t n = 0;
    while (p < end) {
        while (p < end && is_space(*p))
            p++;
        if (p < end)
            n++;
        while (p < end && !is_space(*p))
            p++;
    }
    return n;
}

/* Explains why no number was read at p for channel c of joint j in frame f (1-based). */
static bool value_error(parser *ps, const char *line, const char *end, const char *p, uint32_t f,
                        const pjoint *j, int c)
{
    char found[64];
    p = skip_spaces((char *)p, end);
    describe(p, end, found, sizeof found);
    if (p == end)
        return fail(ps, ps->src.line, "frame %" PRIu32 " has %zu values, expected %zu", f,
                    count_values(line, end), ps->channels);
    const char *w = p + (*p == '-' || *p == '+');
    double v;
    const char *e = bvh_number(p, &v);
    if (strncasecmp(w, "nan", 3) == 0 || strncasecmp(w, "inf", 3) == 0 || (e && !isfinite(v)))
        return fail(ps, ps->src.line,
                    "%s is not a finite number (frame %" PRIu32 ", joint '%s', %s): expected "
                    "a finite number",
                    found, f, j->name, channel_names[j->ch[c]]);
    return fail(ps, ps->src.line,
                "expected a number for joint '%s' %s in frame %" PRIu32 ", found %s", j->name,
                channel_names[j->ch[c]], f, found);
}

static bool range_error(parser *ps, const char *end, const char *p, uint32_t f, const pjoint *j,
                        int c)
{
    char found[64];
    describe(skip_spaces((char *)p, end), end, found, sizeof found);
    return fail(ps, ps->src.line,
                "%s is out of range (frame %" PRIu32 ", joint '%s', %s): expected a coordinate "
                "within +-%g",
                found, f, j->name, channel_names[j->ch[c]], BVH_MAX_COORD);
}

static bool frame_end_error(parser *ps, const char *line, const char *end, const char *p,
                            uint32_t f)
{
    char found[64];
    double v;
    const char *e = bvh_number(p, &v);
    if (e && (e == end || is_space(*e)))
        return fail(ps, ps->src.line, "frame %" PRIu32 " has %zu values, expected %zu", f,
                    count_values(line, end), ps->channels);
    return fail(ps, ps->src.line,
                "expected the end of frame %" PRIu32 " after its %zu values, found %s", f,
                ps->channels, describe(p, end, found, sizeof found));
}

static bool is_separator(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || !c;
}

#if BVH_TOKEN
/* The fast way through a well-formed frame line, into sc->vals: bvh_line_avx2 on processors
 * with AVX2, else bvh_token_number, which classifies each number's 16 bytes at once, so
 * finding the next number (the chain the processor must follow) takes a few operations while
 * the digits convert alongside. False for anything unusual (wrong count, a character that ends
 * a number early, a value too large for bvh_sincos_half): read_values then reads the line again,
 * one number at a time, to say what is wrong. Reads only the parser's shared, unchanging state,
 * so two threads may run it at once. */
#if BVH_TOKEN_AVX2
__attribute__((target("avx2"))) static bool read_values_avx2(const parser *ps, scratch *sc,
                                                             const char *line, const char *end)
{
    bvh_avx2_k k;
    bvh_avx2_k_init(&k);
    sc->huge = false;
    return bvh_line_avx2(line, end, sc->vals, ps->channels, sc->pos, ps->shuf, &k);
}
#endif

static bool read_values_fast(const parser *ps, scratch *sc, const char *line, const char *end)
{
#if BVH_TOKEN_AVX2
    if (ps->avx2)
        return read_values_avx2(ps, sc, line, end);
#endif
    double *v = sc->vals, *vend = v + ps->channels;
    const char *p = line, *next;
    sc->huge = false;
    while (*p == ' ' || *p == '\t' || *p == '\r')
        p++;
    while (p < end) {
        if (v == vend)
            return false;
        if (!bvh_token_number(p, v, &next)) {
            const char *e = bvh_number_padded(p, v);
            if (!e || !(e == end || is_space(*e)) || !(fabs(*v) < 1e15))
                return false;
            for (next = e; *next == ' ' || *next == '\t' || *next == '\r';)
                next++;
        }
        v++;
        p = next;
    }
    return v == vend && p == end;
}

#else
static bool read_values_fast(const parser *ps, scratch *sc, const char *line, const char *end)
{
    (void)ps, (void)sc, (void)line, (void)end;
    return false;
}
#endif

/* Reads frame f's line into ps->main.vals, or says what is wrong with it (at ps->src.line). */
static bool read_values(parser *ps, char *line, char *end, uint32_t f)
{
    if (read_values_fast(ps, &ps->main, line, end))
        return true;
    char *p = line;
    double *v = ps->main.vals;
    ps->main.huge = true; /* rare: let convert_frame check every angle */
    for (size_t ji = 0; ji < ps->count; ji++) {
        const pjoint *j = &ps->joints[ji];
        for (int c = 0; c < j->nch; c++) {
            while (*p == ' ' || *p == '\t')
                p++;
            const char *e = bvh_number_padded(p, v);
            if (!e || !is_separator(*e) || !isfinite(*v))
                return value_error(ps, line, end, p, f + 1, j, c);
            if (j->ch[c] <= CH_ZPOS && !channel_in_range(*v))
                return range_error(ps, end, p, f + 1, j, c);
            p = (char *)e;
            v++;
        }
    }
    p = skip_spaces(p, end);
    if (p != end)
        return frame_end_error(ps, line, end, p, f + 1);
    return true;
}

/* Turns the values in sc into frame f's local rotations and translations. */
static void convert_frame(const parser *ps, scratch *sc, rf_animation *a, uint32_t f)
{
    size_t n = ps->channels + 1; /* with the padding value */
    float *rot = a->rotations + (size_t)f * ps->count * 4;
    float *tr = a->translations + (size_t)f * ps->count * 3;
#if BVH_AVX2
    if (ps->avx2)
        bvh_sincos_half_avx2(sc->vals, sc->sn, sc->cs, n);
    else
#endif
        bvh_sincos_half(sc->vals, sc->sn, sc->cs, n);
    if (sc->huge)
        bvh_sincos_half_fix(sc->vals, sc->sn, sc->cs, n);
    const double *sn = sc->sn, *cs = sc->cs, *v = sc->vals;
    for (size_t ji = 0; ji < ps->count; ji++, rot += 4, tr += 3) {
        const jplan *pl = &ps->plan[ji];
        const double *off = ps->joints[ji].offset;
        bvh_euler3(pl->axis, pl->e, sn[pl->rot[0]], cs[pl->rot[0]], sn[pl->rot[1]], cs[pl->rot[1]],
                   sn[pl->rot[2]], cs[pl->rot[2]], rot);
        for (int k = 0; k < 3; k++)
            tr[k] = (float)(pl->pos[k] >= 0 ? v[pl->pos[k]] : off[k]);
    }
}

static bool scratch_init(scratch *sc, size_t channels)
{
    size_t n = channels + 1;
    sc->vals = malloc(n * sizeof *sc->vals);
    sc->sn = malloc(n * sizeof *sc->sn);
    sc->cs = malloc(n * sizeof *sc->cs);
    sc->pos = malloc(2 * n * sizeof *sc->pos); /* BVH_LINE_POS(channels) */
    if (sc->vals)
        sc->vals[channels] = 0; /* the padding angle of joints with fewer than 3 rotations */
    return sc->vals && sc->sn && sc->cs && sc->pos;
}

static void scratch_free(scratch *sc)
{
    free(sc->vals);
    free(sc->sn);
    free(sc->cs);
    free(sc->pos);
}

static bool make_plan(parser *ps)
{
#if BVH_AVX2
    ps->avx2 = __builtin_cpu_supports("avx2");
#endif
#if BVH_TOKEN_AVX2
    bvh_shuffles_init(ps->shuf);
#endif
    ps->plan = malloc((ps->count ? ps->count : 1) * sizeof *ps->plan);
    if (!ps->plan || !scratch_init(&ps->main, ps->channels))
        return fail(ps, ps->src.line, "out of memory");
    uint32_t index = 0;
    for (size_t ji = 0; ji < ps->count; ji++) {
        const pjoint *j = &ps->joints[ji];
        jplan *pl = &ps->plan[ji];
        int nrot = 0;
        bool used[3] = {false, false, false};
        for (int k = 0; k < 3; k++)
            pl->rot[k] = (uint32_t)ps->channels, pl->pos[k] = -1;
        for (int c = 0; c < j->nch; c++, index++) {
            if (j->ch[c] >= CH_XROT) {
                pl->axis[nrot] = (uint8_t)(j->ch[c] - CH_XROT);
                used[pl->axis[nrot]] = true;
                pl->rot[nrot++] = index;
            } else {
                pl->pos[j->ch[c]] = (int32_t)index;
            }
        }
        /* a rotation of 0 degrees about each missing axis changes nothing, in any order */
        for (uint8_t axis = 0; axis < 3; axis++)
            if (!used[axis])
                pl->axis[nrot++] = axis;
        pl->e = pl->axis[1] == (pl->axis[0] + 1) % 3 ? 1.0 : -1.0;
    }
    return true;
}

static bool report_progress(parser *ps)
{
    const rf_bvh_read_opts *o = ps->opts;
    if (!o || !o->progress)
        return true;
    double frac = ps->src.total ? (double)source_offset(&ps->src) / (double)ps->src.total : 0;
    if (o->progress(o->user, frac))
        return true;
    return fail(ps, ps->src.line, "cancelled");
}

/* Warns about lines after the declared frames: tolerated, since real files have them. */
static void check_trailing(parser *ps, uint32_t frames)
{
    unsigned long first = 0, lines = 0;
    char *end, *p;
    while ((p = next_nonblank(ps, &end)) != NULL) {
        if (!lines++)
            first = ps->src.line;
        source_next(&ps->src, end);
    }
    if (!lines || !ps->opts || !ps->opts->warning)
        return;
    char msg[256];
    snprintf(msg, sizeof msg,
             "%s:%lu: %lu line%s after the %" PRIu32 " frames that 'Frames:' declares, ignored",
             ps->name, first, lines, lines == 1 ? "" : "s", frames);
    ps->opts->warning(ps->opts->user, msg);
}

/* ---- frames, in batches, on two threads for large files ---- */

typedef struct frame_line {
    const char *line, *end;
    unsigned long number; /* line number, for messages */
} frame_line;

/* A run of frames for one thread: frame `first` + i is lines[i]. */
typedef struct batch {
    const parser *ps;
    scratch *sc;
    rf_animation *a;
    const frame_line *lines;
    size_t count;
    uint32_t first;
    size_t done; /* frames converted before the first the fast path declined */
} batch;

static void run_batch(batch *b)
{
    for (b->done = 0; b->done < b->count; b->done++) {
        const frame_line *l = &b->lines[b->done];
        if (!read_values_fast(b->ps, b->sc, l->line, l->end))
            return;
        convert_frame(b->ps, b->sc, b->a, b->first + (uint32_t)b->done);
    }
}

#if BVH_THREADS
/* A second thread that runs one batch at a time for the parser's thread. */
typedef struct helper {
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    batch *work; /* set by the parser, cleared when done */
    bool busy;   /* the helper has taken `work` */
    bool quit;
    scratch sc;
    /* hints read without the lock by a thread spinning before it sleeps (helper_spin): a batch
     * posted and not yet taken, the posted batch done, and the signs of a busy machine seen so
     * far (spinning stops at SPIN_STRIKES) */
    atomic_int posted, finished, strikes;
} helper;

/* How long a thread spins for the other before it sleeps on the condition variable. Waking a
 * sleeping thread took longer than half a batch (about 0.1 ms) in the virtual machines measured:
 * the parser's thread had finished its half and taken the helper's back before the helper ran,
 * and two threads read a file hardly faster than one (6.3 against 8.6 ms on the 10,000-frame
 * benchmark clip; 5.0 with spinning). */
#define SPIN_NS 100000
#define SPIN_STRIKES 4

#if defined(__x86_64__) || defined(__i386__)
#define SPIN_PAUSE() _mm_pause() /* tells the core it waits (emmintrin.h, at the top) */
#else
#define SPIN_PAUSE() ((void)0)
#endif

/* Spins until *flag is set (true) or SPIN_NS have passed (false); false at once when spinning
 * has been turned off for this read. */
static bool helper_spin(helper *h, atomic_int *flag)
{
    if (atomic_load_explicit(&h->strikes, memory_order_relaxed) >= SPIN_STRIKES)
        return false;
    struct timespec t0, t;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (unsigned i = 1;; i++) {
        if (atomic_load_explicit(flag, memory_order_acquire))
            return true;
        SPIN_PAUSE();
        if (i % 64 == 0) {
            clock_gettime(CLOCK_MONOTONIC, &t);
            if ((t.tv_sec - t0.tv_sec) * 1000000000L + (t.tv_nsec - t0.tv_nsec) > SPIN_NS)
                return false;
        }
    }
}

static void *helper_main(void *arg)
{
    helper *h = arg;
    pthread_mutex_lock(&h->mu);
    for (;;) {
        if (!h->work && !h->quit) { /* the next batch usually comes within SPIN_NS */
            pthread_mutex_unlock(&h->mu);
            helper_spin(h, &h->posted);
            pthread_mutex_lock(&h->mu);
        }
        while (!h->work && !h->quit)
            pthread_cond_wait(&h->cv, &h->mu);
        if (!h->work)
            break;
        h->busy = true;
        atomic_store(&h->posted, 0);
        pthread_mutex_unlock(&h->mu);
        run_batch(h->work);
        pthread_mutex_lock(&h->mu);
        h->work = NULL;
        h->busy = false;
        atomic_store_explicit(&h->finished, 1, memory_order_release);
        pthread_cond_broadcast(&h->cv);
    }
    pthread_mutex_unlock(&h->mu);
    return NULL;
}

static helper *helper_start(size_t channels)
{
    helper *h = calloc(1, sizeof *h);
    if (!h || !scratch_init(&h->sc, channels) || pthread_mutex_init(&h->mu, NULL) != 0) {
        if (h)
            scratch_free(&h->sc);
        free(h);
        return NULL;
    }
    pthread_cond_init(&h->cv, NULL);
    atomic_init(&h->posted, 0), atomic_init(&h->finished, 0), atomic_init(&h->strikes, 0);
    if (pthread_create(&h->thread, NULL, helper_main, h) != 0) {
        pthread_cond_destroy(&h->cv);
        pthread_mutex_destroy(&h->mu);
        scratch_free(&h->sc);
        free(h);
        return NULL;
    }
    return h;
}

static void helper_submit(helper *h, batch *b)
{
    pthread_mutex_lock(&h->mu);
    h->work = b;
    atomic_store(&h->finished, 0);
    atomic_store_explicit(&h->posted, 1, memory_order_release);
    pthread_cond_broadcast(&h->cv);
    pthread_mutex_unlock(&h->mu);
}

/* Waits for the submitted batch; if the helper has not started it yet (on a busy machine it may
 * not have run at all), takes it back and runs it here, so a second thread never makes a read
 * slower than one. The signs of a busy machine (a batch taken back, or one not done within
 * SPIN_NS of this thread's own) turn spinning off for the rest of the read at the
 * SPIN_STRIKES-th: a thread spinning on a processor the other needs would only delay it. */
static void helper_wait(helper *h)
{
    pthread_mutex_lock(&h->mu);
    if (h->work && !h->busy) {
        batch *b = h->work;
        h->work = NULL;
        atomic_store(&h->posted, 0), atomic_fetch_add(&h->strikes, 1);
        pthread_mutex_unlock(&h->mu);
        run_batch(b);
        return;
    }
    pthread_mutex_unlock(&h->mu);
    if (!helper_spin(h, &h->finished))
        atomic_fetch_add(&h->strikes, 1);
    pthread_mutex_lock(&h->mu);
    while (h->work)
        pthread_cond_wait(&h->cv, &h->mu);
    pthread_mutex_unlock(&h->mu);
}

static void helper_stop(helper *h)
{
    if (!h)
        return;
    pthread_mutex_lock(&h->mu);
    h->quit = true;
    pthread_cond_broadcast(&h->cv);
    pthread_mutex_unlock(&h->mu);
    pthread_join(h->thread, NULL);
    pthread_cond_destroy(&h->cv);
    pthread_mutex_destroy(&h->mu);
    scratch_free(&h->sc);
    free(h);
}

/* A helper thread when the frames are many enough to be worth one, the caller allows it and
 * there is a second processor; NULL otherwise (everything then runs on the caller's thread). */
static helper *maybe_helper(const parser *ps, uint32_t frames)
{
    int allowed = ps->opts ? ps->opts->threads : 0;
    uint64_t at = source_offset(&ps->src);
    uint64_t left = ps->src.total > at ? ps->src.total - at : 0;
    if (allowed == 1 || left < THREAD_MIN_BYTES || frames < 2 * MIN_SPLIT ||
        sysconf(_SC_NPROCESSORS_ONLN) < 2)
        return NULL;
    return helper_start(ps->channels);
}
#else
typedef struct helper helper;
static helper *maybe_helper(const parser *ps, uint32_t frames)
{
    (void)ps, (void)frames;
    return NULL;
}
static void helper_stop(helper *h)
{
    (void)h;
}
#endif

/* Takes up to `max` frame lines that are already whole in the buffer (skipping blank lines),
 * without reading more: their pointers stay valid until the next read. */
static size_t take_lines(parser *ps, frame_line *lines, size_t max)
{
    source *s = &ps->src;
    size_t n = 0;
    while (n < max) {
        char *p = s->buf + s->pos;
        char *nl = memchr(p, '\n', s->len - s->pos);
        if (!nl)
            break;
        if (skip_spaces(p, nl) != nl) {
            lines[n].line = p, lines[n].end = nl;
            lines[n++].number = s->line;
        }
        source_next(s, nl);
    }
    return n;
}

/* The lines from the first the fast path declined, one by one on this thread: a line the fast
 * path cannot take either parses the careful way or fails with the message. */
static bool finish_batch(parser *ps, rf_animation *a, const frame_line *lines, size_t from,
                         size_t count, uint32_t first)
{
    unsigned long line = ps->src.line;
    for (size_t i = from; i < count; i++) {
        ps->src.line = lines[i].number; /* for messages */
        if (!read_values(ps, (char *)lines[i].line, (char *)lines[i].end, first + (uint32_t)i))
            return false;
        convert_frame(ps, &ps->main, a, first + (uint32_t)i);
    }
    ps->src.line = line;
    return true;
}

/* Converts `count` whole lines into frames first..: halves on two threads when there is a
 * helper and enough lines. */
static bool run_lines(parser *ps, helper *h, rf_animation *a, const frame_line *lines, size_t count,
                      uint32_t first)
{
    size_t half = h && count >= 2 * MIN_SPLIT ? count / 2 : count;
    batch mine = {ps, &ps->main, a, lines, half, first, 0};
#if BVH_THREADS
    batch theirs = {ps,           h ? &h->sc : NULL,      a, lines + half,
                    count - half, first + (uint32_t)half, 0};
    if (half < count)
        helper_submit(h, &theirs);
#endif
    run_batch(&mine);
    size_t from = mine.done;
#if BVH_THREADS
    if (half < count) {
        helper_wait(h);
        if (from == half)
            from = half + theirs.done;
    }
#endif
    return finish_batch(ps, a, lines, from, count, first);
}

/* One frame the ordinary way, when no whole line is buffered (the buffer needs refilling). */
static bool one_frame(parser *ps, rf_animation *a, uint32_t f)
{
    char *end, *line;
    line = ps->channels ? next_nonblank(ps, &end) : source_line(&ps->src, &end);
    if (!line) {
        if (!ps->failed && !end)
            fail_read(ps);
        if (ps->failed)
            return false;
        return fail(ps, ps->src.line,
                    "MOTION is truncated: the file ends after %" PRIu32 " of %" PRIu32
                    " frames, expected %" PRIu32 " more",
                    f, a->frame_count, a->frame_count - f);
    }
    if (!read_values(ps, line, end, f))
        return false;
    convert_frame(ps, &ps->main, a, f);
    source_next(&ps->src, end);
    return true;
}

static bool parse_frames(parser *ps, rf_animation *a)
{
    frame_line lines[BATCH_LINES];
    helper *h = ps->channels ? maybe_helper(ps, a->frame_count) : NULL;
    uint32_t f = 0, reported = 0;
    bool ok = true;
    while (ok && f < a->frame_count) {
        size_t want = a->frame_count - f < BATCH_LINES ? a->frame_count - f : BATCH_LINES;
        /* frames of no values are lines, blank or not: those go one at a time */
        size_t n = ps->channels ? take_lines(ps, lines, want) : 0;
        if (n)
            ok = run_lines(ps, h, a, lines, n, f);
        else
            ok = one_frame(ps, a, f), n = 1;
        f += (uint32_t)n;
        if (ok && f - reported >= PROGRESS_FRAMES) {
            ok = report_progress(ps);
            reported = f;
        }
    }
    helper_stop(h);
    if (ok)
        check_trailing(ps, a->frame_count);
    return ok && !ps->failed;
}

/* ---- results ---- */

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static char *clip_name(const char *path)
{
    const char *b = base_name(path);
    size_t n = strlen(b);
    if (n > 4 && strcasecmp(b + n - 4, ".bvh") == 0)
        n -= 4;
    char *s = malloc(n + 1);
    if (s) {
        memcpy(s, b, n);
        s[n] = '\0';
    }
    return s;
}

/* A new animation whose arrays are left for the parser to fill: rf_animation_new's
 * initialisation would write every value once more. */
static rf_animation *new_animation(uint32_t joints, uint32_t frames, double fps)
{
    size_t n = (size_t)joints * frames;
    if ((joints && n / joints != frames) || n > SIZE_MAX / (4 * sizeof(float)))
        return NULL;
    rf_animation *a = rf_animation_new(joints, 0, fps);
    float *r = malloc((n ? n : 1) * 4 * sizeof(float));
    float *t = malloc((n ? n : 1) * 3 * sizeof(float));
    if (!a || !r || !t) {
        free(r);
        free(t);
        rf_animation_free(a);
        return NULL;
    }
    free(a->rotations);
    free(a->translations);
    a->rotations = r, a->translations = t, a->frame_count = frames;
    rf_prefault(r, n * 4 * sizeof(float));
    rf_prefault(t, n * 3 * sizeof(float));
    return a;
}

/* Moves the parsed joints into a new skeleton (the names change owner). */
static rf_skeleton *build_skeleton(parser *ps)
{
    rf_skeleton *s = rf_skeleton_new((uint32_t)ps->count);
    if (!s)
        return NULL;
    for (size_t i = 0; i < ps->count; i++) {
        pjoint *j = &ps->joints[i];
        rf_joint *o = &s->joints[i];
        o->name = j->name;
        j->name = NULL;
        o->parent = j->parent;
        o->flags = j->flags;
        o->rest.t = rf_v3(j->offset[0], j->offset[1], j->offset[2]);
        o->end_site = rf_v3(j->end_site[0], j->end_site[1], j->end_site[2]);
    }
    s->name = strdup(base_name(ps->name));
    return s;
}

static void mark_channels(const parser *ps, rf_animation *a)
{
    for (size_t i = 0; i < ps->count; i++)
        for (int c = 0; c < ps->joints[i].nch; c++)
            a->channels[i] |=
                ps->joints[i].ch[c] < CH_XROT ? RF_CHANNEL_TRANSLATION : RF_CHANNEL_ROTATION;
}

static void parser_free(parser *ps)
{
    for (size_t i = 0; i < ps->count; i++)
        free(ps->joints[i].name);
    free(ps->joints);
    free(ps->stack);
    free(ps->names);
    free(ps->src.buf);
    free(ps->plan);
    scratch_free(&ps->main);
}

/* The decoded motion takes frames x joints whatever the channels, so a file of a megabyte with
 * many joints and no channels asks for gigabytes. Refuses what would take more than half of
 * this machine's memory, which would fail or drive the machine into swapping. */
static bool check_motion_memory(parser *ps, uint32_t frames, unsigned long frames_line)
{
    double need = (double)frames * (double)ps->count * 7 * sizeof(float);
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double half = pages > 0 && page > 0 ? (double)pages * (double)page / 2 : 0;
    if (half == 0 || need <= half)
        return true;
    return fail(ps, frames_line,
                "'Frames: %" PRIu32 "' of %zu joints would take %.1f GB of memory, more than "
                "half of this machine's %.1f GB: expected fewer frames or joints",
                frames, ps->count, need / 1e9, 2 * half / 1e9);
}

static bool parse(parser *ps, rf_skeleton **skeleton, rf_animation **animation)
{
    uint32_t frames = 0;
    double frame_time = 0;
    ps->src.chunk = ps->src.total >= THREAD_MIN_BYTES ? CHUNK_LARGE : CHUNK_SMALL;
    size_t first = ps->src.total < ps->src.chunk ? (size_t)ps->src.total : ps->src.chunk;
    ps->src.cap = first + 1;
    ps->src.buf = malloc(ps->src.cap + BVH_PAD);
    ps->src.line = 1;
    if (!ps->src.buf)
        return fail(ps, 0, "out of memory");
    memset(ps->src.buf, 0, BVH_PAD);
    unsigned long frames_line;
    if (!parse_hierarchy(ps) || !read_motion_header(ps, &frames, &frame_time, &frames_line) ||
        !check_frame_bound(ps, frames, frames_line) ||
        !check_motion_memory(ps, frames, frames_line))
        return false;
    rf_animation *a = new_animation((uint32_t)ps->count, frames, 1.0 / frame_time);
    if (!a || !(a->name = clip_name(ps->name))) {
        rf_animation_free(a);
        return fail(ps, ps->src.line, "out of memory for %" PRIu32 " frames of %zu joints", frames,
                    ps->count);
    }
    mark_channels(ps, a);
    if (!make_plan(ps) || !parse_frames(ps, a) || !report_progress(ps)) {
        rf_animation_free(a);
        return false;
    }
    /* Built after the frames: the skeleton takes the joint names over, and frame errors name
     * joints. */
    rf_skeleton *s = build_skeleton(ps);
    if (!s || !s->name) {
        rf_skeleton_free(s);
        rf_animation_free(a);
        return fail(ps, ps->src.line, "out of memory for %zu joints", ps->count);
    }
    *skeleton = s, *animation = a;
    return true;
}

static bool read_source(parser *ps, rf_skeleton **skeleton, rf_animation **animation)
{
    *skeleton = NULL, *animation = NULL;
    bool ok = parse(ps, skeleton, animation);
    parser_free(ps);
    return ok;
}

bool rf_bvh_read_memory(const char *data, size_t size, const char *name,
                        const rf_bvh_read_opts *opts, rf_skeleton **skeleton,
                        rf_animation **animation, char *err, size_t err_size)
{
    parser ps = {0};
    ps.src.mem = data, ps.src.mem_size = size, ps.src.total = size;
    ps.name = name ? name : "(memory)";
    ps.opts = opts, ps.err = err, ps.err_size = err_size;
    return read_source(&ps, skeleton, animation);
}

bool rf_bvh_read_file(const char *path, const rf_bvh_read_opts *opts, rf_skeleton **skeleton,
                      rf_animation **animation, char *err, size_t err_size)
{
    struct stat st;
    *skeleton = NULL, *animation = NULL;
    /* O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused just below; regular
     * files ignore the flag). */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        snprintf(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        if (fd >= 0)
            close(fd);
        return false;
    }
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        snprintf(err, err_size, "%s: not a regular file", path);
        fclose(f);
        return false;
    }
    setvbuf(f, NULL, _IONBF, 0); /* reads go straight into the parser's buffer */
    parser ps = {0};
    ps.src.file = f, ps.src.total = (uint64_t)st.st_size;
    ps.name = path, ps.opts = opts, ps.err = err, ps.err_size = err_size;
    bool ok = read_source(&ps, skeleton, animation);
    fclose(f);
    return ok;
}

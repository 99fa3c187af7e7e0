/* The BVH writer.
 *
 * BVH has no rest rotations: at zero rotation every joint frame is aligned with the world. A
 * skeleton whose rest pose rotates its joints (glTF and Assimp rigs) is written in its
 * world-aligned rest frame: with Wr[j] the world rest rotation and Ws[j] the world rest scale,
 *   OFFSET[j]      = Wr[p] (Ws[p] * rest_t[j])     (p the parent; the world rest position for
 * roots) rotation[j](f) = Wr[p] r[j](f) Wr[j]^-1        (identity at rest: the zero pose is the
 * rest pose) position[j](f) = Wr[p] (Ws[p] * t[j](f)) Each follows from asking that every frame's
 * world joint positions and orientations (relative to the rest orientation) stay the same; the
 * chain above the joint cancels out, so no forward kinematics is needed per frame.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/bvh.h"
#include "rigflow/text.h"

#define PROGRESS_FRAMES 1024u
#define MAX_INDENT 32 /* deeper joints are not indented further: 100k levels stay readable */

typedef struct writer {
    FILE *out;
    const char *name;
    const rf_skeleton *s;
    const rf_animation *a;
    rf_bvh_write_opts o;
    int axes[3];
    char *err;
    size_t err_size;
    uint32_t n;
    int32_t *first_child, *next_sibling;
    uint32_t *order; /* joints in file (depth-first) order */
    char **names;    /* unique names without whitespace */
    rf_quat *wr;     /* world rest rotation */
    rf_vec3 *ws;     /* world rest scale */
    rf_vec3 *offset; /* OFFSET in the world-aligned rest frame */
    bool *pos;       /* has position channels */
    double *prev;    /* last frame's Euler angles, for continuity */
    char *line;      /* one frame's text */
    size_t line_cap;
} writer;

static bool wfail(writer *w, const char *fmt, ...) RF_PRINTF(2, 3);

static bool wfail(writer *w, const char *fmt, ...)
{
    int n = snprintf(w->err, w->err_size, "%s: ", w->name);
    if (n >= 0 && (size_t)n < w->err_size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(w->err + n, w->err_size - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return false;
}

static bool validate(writer *w)
{
    const rf_skeleton *s = w->s;
    if (!s || s->joint_count == 0 || !s->joints)
        return wfail(w, "expected a skeleton with at least one joint");
    for (uint32_t i = 0; i < s->joint_count; i++) {
        const rf_joint *j = &s->joints[i];
        rf_quat r = j->rest.r;
        char label[160]; /* the name from the file, escaped */
        if (!rf_v3_isfinite(j->rest.t) || !rf_v3_isfinite(j->rest.s) ||
            !rf_v3_isfinite(j->end_site) || !isfinite(r.x + r.y + r.z + r.w))
            return wfail(w,
                         "joint %" PRIu32 " ('%s') has a rest pose that is not finite: expected "
                         "finite numbers",
                         i, rf_joint_label(s, i, label, sizeof label));
    }
    int64_t bad = rf_skeleton_misordered(s);
    char why[416];
    if (bad >= 0)
        return wfail(w, "%s", rf_skeleton_order_error(s, (uint32_t)bad, why, sizeof why));
    if (w->a && w->a->joint_count != s->joint_count)
        return wfail(
            w, "the animation has %" PRIu32 " joints, the skeleton %" PRIu32 ": expected the same",
            w->a->joint_count, s->joint_count);
    if (w->a && !(w->a->fps > 0 && isfinite(w->a->fps)))
        return wfail(w, "the animation's fps is %g: expected a positive number", w->a->fps);
    if (w->o.precision == 0)
        w->o.precision = 9;
    if (w->o.precision < 3 || w->o.precision > 17)
        return wfail(w, "precision %d: expected 3 to 17 significant digits", w->o.precision);
    return true;
}

/* ---- names ---- */

static uint64_t hash_str(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

/* Adds names[i] to the set (table of index + 1); false when the name is taken. */
static bool name_add(writer *w, uint32_t *table, size_t cap, uint32_t i)
{
    size_t h = (size_t)hash_str(w->names[i]) & (cap - 1);
    for (; table[h]; h = (h + 1) & (cap - 1))
        if (strcmp(w->names[table[h] - 1], w->names[i]) == 0)
            return false;
    table[h] = i + 1;
    return true;
}

/* A copy of `name` that BVH readers can take back: no whitespace or braces; `joint<i>` when
 * empty; `suffix` > 0 appends "_<suffix>" to make it unique. */
static char *clean_name(const char *name, uint32_t i, unsigned suffix)
{
    char fallback[32];
    if (!name || !*name) {
        snprintf(fallback, sizeof fallback, "joint%" PRIu32, i);
        name = fallback;
    }
    size_t n = strlen(name);
    char *c = malloc(n + 16);
    if (!c)
        return NULL;
    for (size_t k = 0; k < n; k++) {
        unsigned char ch = (unsigned char)name[k];
        c[k] = (ch <= ' ' || ch == '{' || ch == '}' || ch == 127) ? '_' : (char)ch;
    }
    c[n] = '\0';
    if (suffix)
        snprintf(c + n, 16, "_%u", suffix);
    return c;
}

static bool make_names(writer *w)
{
    size_t cap = 16;
    while (cap < 2 * (size_t)w->n)
        cap *= 2;
    uint32_t *table = calloc(cap, sizeof *table);
    if (!table)
        return wfail(w, "out of memory");
    bool ok = true;
    for (uint32_t i = 0; ok && i < w->n; i++) {
        for (unsigned suffix = 0;; suffix++) {
            free(w->names[i]);
            w->names[i] = clean_name(w->s->joints[i].name, i, suffix);
            if (!w->names[i]) {
                ok = wfail(w, "out of memory");
                break;
            }
            if (name_add(w, table, cap, i))
                break;
        }
    }
    free(table);
    return ok;
}

/* ---- rest frame ---- */

static void compute_rest(writer *w)
{
    const rf_joint *j = w->s->joints;
    for (uint32_t i = 0; i < w->n; i++) {
        int32_t p = j[i].parent;
        rf_quat r = rf_quat_normalize(j[i].rest.r);
        if (p < 0) {
            w->wr[i] = r;
            w->ws[i] = j[i].rest.s;
            w->offset[i] = j[i].rest.t;
        } else {
            w->wr[i] = rf_quat_normalize(rf_quat_mul(w->wr[p], r));
            w->ws[i] = rf_v3_mul(w->ws[p], j[i].rest.s);
            w->offset[i] = rf_quat_rotate(w->wr[p], rf_v3_mul(w->ws[p], j[i].rest.t));
        }
    }
}

/* Position channels go on roots, on joints the source keyed, and on joints whose translation
 * leaves the rest one in some frame. */
static void choose_positions(writer *w)
{
    const rf_animation *a = w->a;
    for (uint32_t i = 0; i < w->n; i++) {
        const rf_joint *j = &w->s->joints[i];
        w->pos[i] =
            w->o.all_positions || j->parent < 0 || (a && (a->channels[i] & RF_CHANNEL_TRANSLATION));
        double tol = 1e-6 * (1 + rf_v3_len(j->rest.t));
        for (uint32_t f = 0; a && !w->pos[i] && f < a->frame_count; f++)
            w->pos[i] = rf_v3_dist(rf_animation_translation(a, f, i), j->rest.t) > tol;
    }
}

static void build_tree(writer *w)
{
    for (uint32_t i = 0; i < w->n; i++)
        w->first_child[i] = w->next_sibling[i] = -1;
    for (uint32_t i = w->n; i-- > 0;) { /* prepend in reverse: children stay in index order */
        int32_t p = w->s->joints[i].parent;
        if (p >= 0) {
            w->next_sibling[i] = w->first_child[p];
            w->first_child[p] = (int32_t)i;
        }
    }
}

/* ---- hierarchy ---- */

static void indent(writer *w, uint32_t depth)
{
    for (uint32_t d = 0; d < depth && d < MAX_INDENT; d++)
        fputc('\t', w->out);
}

/* Formats v with the chosen precision into buf (40 bytes); -0 prints as 0. */
static int fmt_num(char *buf, size_t size, int precision, double v)
{
    return rf_bvh_format_number(buf, size, precision, v);
}

static void write_vec(writer *w, const char *label, rf_vec3 v)
{
    char x[40], y[40], z[40];
    fmt_num(x, sizeof x, w->o.precision, v.x);
    fmt_num(y, sizeof y, w->o.precision, v.y);
    fmt_num(z, sizeof z, w->o.precision, v.z);
    fprintf(w->out, "%s %s %s %s\n", label, x, y, z);
}

static void write_open(writer *w, uint32_t i, uint32_t depth)
{
    static const char *const rot[3] = {"Xrotation", "Yrotation", "Zrotation"};
    const rf_joint *j = &w->s->joints[i];
    indent(w, depth);
    fprintf(w->out, "%s %s\n", j->parent < 0 ? "ROOT" : "JOINT", w->names[i]);
    indent(w, depth);
    fputs("{\n", w->out);
    indent(w, depth + 1);
    write_vec(w, "OFFSET", w->offset[i]);
    indent(w, depth + 1);
    fprintf(w->out, "CHANNELS %d%s %s %s %s\n", w->pos[i] ? 6 : 3,
            w->pos[i] ? " Xposition Yposition Zposition" : "", rot[w->axes[0]], rot[w->axes[1]],
            rot[w->axes[2]]);
    if (j->flags & RF_JOINT_HAS_END_SITE) {
        rf_vec3 e = rf_quat_rotate(w->wr[i], rf_v3_mul(w->ws[i], j->end_site));
        indent(w, depth + 1);
        fputs("End Site\n", w->out);
        indent(w, depth + 1);
        fputs("{\n", w->out);
        indent(w, depth + 2);
        write_vec(w, "OFFSET", e);
        indent(w, depth + 1);
        fputs("}\n", w->out);
    }
}

static void write_close(writer *w, uint32_t depth)
{
    indent(w, depth);
    fputs("}\n", w->out);
}

/* Depth-first without recursion: parent links lead back up, so any depth is fine. */
static void write_hierarchy(writer *w)
{
    uint32_t k = 0;
    fputs("HIERARCHY\n", w->out);
    for (uint32_t r = 0; r < w->n; r++) {
        if (w->s->joints[r].parent >= 0)
            continue;
        uint32_t cur = r, depth = 0;
        for (;;) {
            write_open(w, cur, depth);
            w->order[k++] = cur;
            if (w->first_child[cur] >= 0) {
                cur = (uint32_t)w->first_child[cur];
                depth++;
                continue;
            }
            for (;;) {
                write_close(w, depth);
                if (cur == r)
                    break;
                if (w->next_sibling[cur] >= 0) {
                    cur = (uint32_t)w->next_sibling[cur];
                    break;
                }
                cur = (uint32_t)w->s->joints[cur].parent;
                depth--;
            }
            if (cur == r)
                break;
        }
    }
}

/* ---- motion ---- */

static double wrap_near(double angle, double ref)
{
    return angle + 360.0 * nearbyint((ref - angle) / 360.0);
}

/* Of the two Euler triples for one rotation, (a, b, c) and (a + 180, 180 - b, c + 180), each
 * shifted by whole turns, the one nearest the previous frame's: curves stay continuous. */
static void continuous(double ang[3], double *prev)
{
    double alt[3] = {ang[0] + 180, 180 - ang[1], ang[2] + 180}, d0 = 0, d1 = 0;
    for (int k = 0; k < 3; k++) {
        ang[k] = wrap_near(ang[k], prev[k]);
        alt[k] = wrap_near(alt[k], prev[k]);
        d0 += fabs(ang[k] - prev[k]);
        d1 += fabs(alt[k] - prev[k]);
    }
    for (int k = 0; k < 3; k++)
        prev[k] = ang[k] = d1 < d0 ? alt[k] : ang[k];
}

/* The joint's BVH values for frame f into v (positions first when it has them); returns the
 * count, or -1 for a value that is not finite. */
static int joint_values(writer *w, uint32_t i, uint32_t f, bool first, double *v)
{
    int32_t p = w->s->joints[i].parent;
    rf_quat pr = p < 0 ? rf_quat_identity() : w->wr[p];
    rf_vec3 ps = p < 0 ? rf_v3(1, 1, 1) : w->ws[p];
    rf_quat r = w->a ? rf_animation_rotation(w->a, f, i) : w->s->joints[i].rest.r;
    rf_vec3 t = w->a ? rf_animation_translation(w->a, f, i) : w->s->joints[i].rest.t;
    int n = 0;
    if (!isfinite(r.x + r.y + r.z + r.w) || !rf_v3_isfinite(t))
        return -1; /* before rf_quat_normalize, which would make a NaN the identity */
    if (w->pos[i]) {
        rf_vec3 bt = rf_quat_rotate(pr, rf_v3_mul(ps, t));
        v[n++] = bt.x, v[n++] = bt.y, v[n++] = bt.z;
    }
    rf_quat q = rf_quat_mul(rf_quat_mul(pr, rf_quat_normalize(r)), rf_quat_conj(w->wr[i]));
    double *ang = v + n;
    rf_bvh_quat_to_euler(q, w->o.order, ang);
    if (first)
        memcpy(w->prev + 3 * (size_t)i, ang, 3 * sizeof(double));
    continuous(ang, w->prev + 3 * (size_t)i);
    n += 3;
    for (int k = 0; k < n; k++)
        if (!isfinite(v[k]))
            return -1;
    return n;
}

static bool write_frame(writer *w, uint32_t f)
{
    size_t len = 0;
    for (uint32_t k = 0; k < w->n; k++) {
        uint32_t i = w->order[k];
        double v[6];
        int n = joint_values(w, i, f, f == 0, v);
        if (n < 0) {
            char label[160]; /* the name as written keeps bytes past ASCII: escaped */
            rf_text_escape(w->names[i], label, sizeof label, 0);
            return wfail(w,
                         "frame %" PRIu32 " of joint '%s' is not finite: expected finite "
                         "rotations and translations",
                         f + 1, label);
        }
        for (int c = 0; c < n; c++) {
            if (len)
                w->line[len++] = ' ';
            len += (size_t)fmt_num(w->line + len, 40, w->o.precision, v[c]);
        }
    }
    w->line[len++] = '\n';
    fwrite(w->line, 1, len, w->out);
    return true;
}

static bool write_motion(writer *w)
{
    uint32_t frames = w->a ? w->a->frame_count : 1;
    double fps = w->a ? w->a->fps : 30;
    char ft[40];
    fmt_num(ft, sizeof ft, w->o.precision < 9 ? 9 : w->o.precision, 1.0 / fps);
    fprintf(w->out, "MOTION\nFrames: %" PRIu32 "\nFrame Time: %s\n", frames, ft);
    for (uint32_t f = 0; f < frames; f++) {
        if (!write_frame(w, f))
            return false;
        if ((f + 1) % PROGRESS_FRAMES == 0 && w->o.progress &&
            !w->o.progress(w->o.user, (double)(f + 1) / frames))
            return wfail(w, "cancelled");
    }
    if (w->o.progress && !w->o.progress(w->o.user, 1.0))
        return wfail(w, "cancelled");
    return true;
}

/* ---- entry points ---- */

static bool alloc_writer(writer *w)
{
    size_t n = w->n;
    w->first_child = malloc(n * sizeof *w->first_child);
    w->next_sibling = malloc(n * sizeof *w->next_sibling);
    w->order = malloc(n * sizeof *w->order);
    w->names = calloc(n, sizeof *w->names);
    w->wr = malloc(n * sizeof *w->wr);
    w->ws = malloc(n * sizeof *w->ws);
    w->offset = malloc(n * sizeof *w->offset);
    w->pos = malloc(n * sizeof *w->pos);
    w->prev = malloc(n * 3 * sizeof *w->prev);
    w->line_cap = n * 6 * 40 + 2;
    w->line = malloc(w->line_cap);
    return w->first_child && w->next_sibling && w->order && w->names && w->wr && w->ws &&
           w->offset && w->pos && w->prev && w->line;
}

static void free_writer(writer *w)
{
    for (uint32_t i = 0; w->names && i < w->n; i++)
        free(w->names[i]);
    free(w->names);
    free(w->first_child);
    free(w->next_sibling);
    free(w->order);
    free(w->wr);
    free(w->ws);
    free(w->offset);
    free(w->pos);
    free(w->prev);
    free(w->line);
}

bool rf_bvh_write_stream(FILE *out, const char *name, const rf_skeleton *skeleton,
                         const rf_animation *animation, const rf_bvh_write_opts *opts, char *err,
                         size_t err_size)
{
    writer w = {0};
    w.out = out, w.name = name ? name : "(stream)", w.s = skeleton, w.a = animation;
    w.err = err, w.err_size = err_size;
    if (opts)
        w.o = *opts;
    if (!validate(&w))
        return false;
    w.n = skeleton->joint_count;
    rf_bvh_order_axes(w.o.order, w.axes);
    bool ok = alloc_writer(&w) ? make_names(&w) : wfail(&w, "out of memory");
    if (ok) {
        compute_rest(&w);
        choose_positions(&w);
        build_tree(&w);
        write_hierarchy(&w);
        ok = write_motion(&w);
    }
    free_writer(&w);
    return ok;
}

bool rf_bvh_write_file(const char *path, const char *name, const rf_skeleton *skeleton,
                       const rf_animation *animation, const rf_bvh_write_opts *opts, char *err,
                       size_t err_size)
{
    if (!name)
        name = path;
    FILE *f = fopen(path, "wb");
    if (!f) {
        snprintf(err, err_size, "%s: cannot create: %s", name, strerror(errno));
        return false;
    }
    setvbuf(f, NULL, _IOFBF, 1u << 20);
    bool ok = rf_bvh_write_stream(f, name, skeleton, animation, opts, err, err_size);
    if (ok && (ferror(f) || fflush(f) != 0)) {
        snprintf(err, err_size, "%s: cannot write: %s", name, strerror(errno));
        ok = false;
    }
    if (fclose(f) != 0 && ok) {
        snprintf(err, err_size, "%s: cannot write: %s", name, strerror(errno));
        ok = false;
    }
    if (!ok)
        remove(path); /* no partial file */
    return ok;
}

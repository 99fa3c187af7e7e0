/* Mapping files: parsing and checking the structure (see mapfile.h). */
#include <fcntl.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mapfile-internal.h"

void rf_errs_add(rf_errs *e, const char *fmt, ...)
{
    e->count++;
    if (e->count > RF_ERRS_MAX || !e->buf || e->size == 0)
        return;
    size_t room = e->size - e->used;
    if (room <= 1)
        return;
    int n = snprintf(e->buf + e->used, room, "%s%s: ", e->used ? "\n" : "", e->name);
    if (n > 0 && (size_t)n < room) {
        e->used += (size_t)n, room -= (size_t)n;
        va_list ap;
        va_start(ap, fmt);
        n = vsnprintf(e->buf + e->used, room, fmt, ap);
        va_end(ap);
        e->used += n > 0 ? ((size_t)n < room ? (size_t)n : room - 1) : 0;
    }
}

void rf_errs_finish(rf_errs *e)
{
    if (e->count > RF_ERRS_MAX && e->buf && e->size > e->used + 1)
        snprintf(e->buf + e->used, e->size - e->used, "\n%s: ... and %u more problems", e->name,
                 e->count - RF_ERRS_MAX);
}

/* Every key of `obj` must be one of `allowed`: a typo must not be silently ignored. */
static void check_keys(rf_errs *e, json_t *obj, const char *where, const char *const *allowed)
{
    const char *key;
    json_t *value;
    json_object_foreach(obj, key, value)
    {
        bool known = false;
        for (const char *const *a = allowed; *a && !known; a++)
            known = strcmp(*a, key) == 0;
        if (!known)
            rf_errs_add(e, "at %s/%s: unknown key '%s'", where, key, key);
    }
}

static bool header(rf_errs *e, json_t *root)
{
    static const char *const top[] = {"format",  "version", "description", "comment", "target",
                                      "sources", "metrics", "joints",      NULL};
    if (!json_is_object(root)) {
        rf_errs_add(e, "a mapping file is a JSON object with \"format\": \"%s\"",
                    RF_MAPFILE_FORMAT);
        return false;
    }
    json_t *format = json_object_get(root, "format"), *version = json_object_get(root, "version");
    if (!json_is_string(format) || strcmp(json_string_value(format), RF_MAPFILE_FORMAT) != 0) {
        rf_errs_add(e, "at /format: not a mapping file: expected \"format\": \"%s\"",
                    RF_MAPFILE_FORMAT);
        return false;
    }
    if (!json_is_integer(version)) {
        rf_errs_add(e, "at /version: expected the format version, an integer (%d)",
                    RF_MAPFILE_VERSION);
        return false;
    }
    if (json_integer_value(version) != RF_MAPFILE_VERSION) {
        rf_errs_add(e,
                    "at /version: mapping file version %lld is not supported: this rigflow "
                    "reads version %d",
                    (long long)json_integer_value(version), RF_MAPFILE_VERSION);
        return false;
    }
    check_keys(e, root, "", top);
    return true;
}

static char **string_list(rf_errs *e, json_t *arr, const char *where, uint32_t *count)
{
    *count = 0;
    if (!arr)
        return NULL;
    if (!json_is_array(arr)) {
        rf_errs_add(e, "at %s: expected a list of strings", where);
        return NULL;
    }
    size_t n = json_array_size(arr);
    char **out = calloc(n ? n : 1, sizeof *out);
    for (size_t i = 0; out && i < n; i++) {
        json_t *s = json_array_get(arr, i);
        if (!json_is_string(s))
            rf_errs_add(e, "at %s/%zu: expected a string", where, i);
        else
            out[i] = rf_strdup(json_string_value(s));
    }
    *count = (uint32_t)n;
    return out;
}

static uint32_t metric_index(rf_mapfile *f, const char *name, bool add)
{
    for (uint32_t i = 0; i < f->metric_count; i++)
        if (f->metric_names[i] && strcmp(f->metric_names[i], name) == 0)
            return i;
    if (!add)
        return UINT32_MAX;
    char **names = realloc(f->metric_names, (f->metric_count + 1) * sizeof *names);
    if (!names)
        return UINT32_MAX;
    f->metric_names = names;
    names[f->metric_count] = rf_strdup(name);
    return f->metric_count++;
}

/* Metric names: the "metrics" list when there is one, else every name the joints use. */
static void collect_metrics(rf_errs *e, rf_mapfile *f, json_t *root, json_t *joints)
{
    json_t *list = json_object_get(root, "metrics");
    if (list) {
        f->metric_names = string_list(e, list, "/metrics", &f->metric_count);
        return;
    }
    size_t i;
    json_t *j;
    json_array_foreach(joints, i, j)
    {
        json_t *m = json_is_object(j) ? json_object_get(j, "metrics") : NULL;
        const char *key;
        json_t *v;
        if (json_is_object(m))
            json_object_foreach(m, key, v) metric_index(f, key, true);
    }
}

/* What a mapping file may give as an input's weight and delay. */
#define RF_MAPFILE_WEIGHT_MIN 1e-6
#define RF_MAPFILE_WEIGHT_MAX 1e6
#define RF_MAPFILE_DELAY_MAX 1e6

static bool finite_number(json_t *v, double *out)
{
    if (!json_is_number(v))
        return false;
    *out = json_number_value(v);
    return isfinite(*out);
}

static void parse_input(rf_errs *e, json_t *in, const char *where, rf_mapfile_input *out)
{
    static const char *const keys[] = {"source",  "joint",  "weight", "delay",
                                       "reverse", "mirror", NULL};
    out->weight = 1;
    if (!json_is_object(in)) {
        rf_errs_add(e, "at %s: expected an object {\"source\": N, \"joint\": NAME, ...}", where);
        return;
    }
    check_keys(e, in, where, keys);
    json_t *src = json_object_get(in, "source"), *joint = json_object_get(in, "joint");
    json_t *w = json_object_get(in, "weight"), *d = json_object_get(in, "delay");
    json_t *rev = json_object_get(in, "reverse"), *mir = json_object_get(in, "mirror");
    if (!json_is_integer(src) || json_integer_value(src) < 0 || json_integer_value(src) > INT32_MAX)
        rf_errs_add(e, "at %s/source: expected a source index, an integer from 0", where);
    else
        out->source = (uint32_t)json_integer_value(src);
    if (!json_is_string(joint) || !*json_string_value(joint))
        rf_errs_add(e, "at %s/joint: expected the source joint's name", where);
    else
        out->joint = rf_strdup(json_string_value(joint));
    /* Bounded so that the mapping's float fields hold them: 1e103 would become inf, 1e-300 zero. */
    if (w && (!finite_number(w, &out->weight) || out->weight < RF_MAPFILE_WEIGHT_MIN ||
              out->weight > RF_MAPFILE_WEIGHT_MAX))
        rf_errs_add(e, "at %s/weight: expected a number from %g to %g", where,
                    RF_MAPFILE_WEIGHT_MIN, RF_MAPFILE_WEIGHT_MAX);
    if (d &&
        (!finite_number(d, &out->delay) || out->delay < 0 || out->delay > RF_MAPFILE_DELAY_MAX))
        rf_errs_add(e, "at %s/delay: expected a number of seconds from 0 to %g", where,
                    RF_MAPFILE_DELAY_MAX);
    if (rev && !json_is_boolean(rev))
        rf_errs_add(e, "at %s/reverse: expected true or false", where);
    if (mir && !json_is_boolean(mir))
        rf_errs_add(e, "at %s/mirror: expected true or false", where);
    out->reverse = json_is_true(rev);
    out->mirror = json_is_true(mir);
}

static void parse_metrics(rf_errs *e, rf_mapfile *f, json_t *m, const char *where,
                          rf_mapfile_joint *out)
{
    out->metrics = calloc(f->metric_count ? f->metric_count : 1, sizeof *out->metrics);
    if (!m)
        return;
    if (!json_is_object(m)) {
        rf_errs_add(e, "at %s/metrics: expected an object of metric name to number", where);
        return;
    }
    const char *key;
    json_t *v;
    json_object_foreach(m, key, v)
    {
        uint32_t k = metric_index(f, key, false);
        double x;
        if (k == UINT32_MAX)
            rf_errs_add(e, "at %s/metrics/%s: metric '%s' is not in /metrics", where, key, key);
        else if (!finite_number(v, &x))
            rf_errs_add(e, "at %s/metrics/%s: expected a number", where, key);
        else if (out->metrics)
            out->metrics[k] = x;
    }
}

static void optional_string(rf_errs *e, json_t *v, const char *where, const char *key, char **out)
{
    if (!v)
        return;
    if (!json_is_string(v))
        rf_errs_add(e, "at %s/%s: expected a string", where, key);
    else
        *out = rf_strdup(json_string_value(v));
}

static void parse_joint(rf_errs *e, rf_mapfile *f, json_t *j, size_t i, rf_mapfile_joint *out)
{
    static const char *const keys[] = {"target",  "inputs", "score",   "metrics",
                                       "section", "side",   "comment", NULL};
    char where[48];
    snprintf(where, sizeof where, "/joints/%zu", i);
    if (!json_is_object(j)) {
        rf_errs_add(e, "at %s: expected an object {\"target\": NAME, \"inputs\": [...]}", where);
        return;
    }
    check_keys(e, j, where, keys);
    json_t *t = json_object_get(j, "target"), *ins = json_object_get(j, "inputs");
    json_t *score = json_object_get(j, "score");
    if (!json_is_string(t) || !*json_string_value(t))
        rf_errs_add(e, "at %s/target: expected the target joint's name", where);
    else
        out->target = rf_strdup(json_string_value(t));
    if (!json_is_array(ins)) {
        rf_errs_add(e, "at %s/inputs: expected a list of inputs ([] leaves the joint unmapped)",
                    where);
    } else {
        size_t n = json_array_size(ins);
        out->inputs = calloc(n ? n : 1, sizeof *out->inputs);
        out->input_count = out->inputs ? (uint32_t)n : 0;
        for (size_t k = 0; k < out->input_count; k++) {
            char w2[80];
            snprintf(w2, sizeof w2, "%s/inputs/%zu", where, k);
            parse_input(e, json_array_get(ins, k), w2, &out->inputs[k]);
        }
    }
    if (score && !finite_number(score, &out->score))
        rf_errs_add(e, "at %s/score: expected a number", where);
    parse_metrics(e, f, json_object_get(j, "metrics"), where, out);
    optional_string(e, json_object_get(j, "section"), where, "section", &out->section);
    optional_string(e, json_object_get(j, "side"), where, "side", &out->side);
}

typedef struct rf_named {
    const char *name;
    size_t index;
} rf_named;

static int cmp_named(const void *a, const void *b)
{
    const rf_named *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : (x->index < y->index ? -1 : x->index > y->index);
}

/* A target joint listed twice is a mistake, not a merge. */
static void duplicates(rf_errs *e, const rf_mapfile *f)
{
    rf_named *v = malloc((f->joint_count ? f->joint_count : 1) * sizeof *v);
    size_t n = 0;
    for (uint32_t i = 0; v && i < f->joint_count; i++)
        if (f->joints[i].target)
            v[n++] = (rf_named){f->joints[i].target, i};
    if (v)
        qsort(v, n, sizeof *v, cmp_named);
    for (size_t i = 1; v && i < n; i++)
        if (strcmp(v[i].name, v[i - 1].name) == 0)
            rf_errs_add(e, "at /joints/%zu: joint '%s' is listed again (first at /joints/%zu)",
                        v[i].index, v[i].name, v[i - 1].index);
    free(v);
}

static void body(rf_errs *e, rf_mapfile *f, json_t *root)
{
    json_t *joints = json_object_get(root, "joints"), *target = json_object_get(root, "target");
    if (target && !json_is_null(target))
        optional_string(e, target, "", "target", &f->target);
    f->sources = string_list(e, json_object_get(root, "sources"), "/sources", &f->source_count);
    if (!json_is_array(joints)) {
        rf_errs_add(e, "at /joints: expected the list of joints");
        return;
    }
    collect_metrics(e, f, root, joints);
    size_t n = json_array_size(joints);
    f->joints = calloc(n ? n : 1, sizeof *f->joints);
    f->joint_count = f->joints ? (uint32_t)n : 0;
    for (size_t i = 0; i < f->joint_count; i++)
        parse_joint(e, f, json_array_get(joints, i), i, &f->joints[i]);
    duplicates(e, f);
}

rf_mapfile *rf_mapfile_parse(const char *data, size_t size, const char *name, char *err,
                             size_t err_size)
{
    rf_errs e = {err, err_size, 0, 0, name ? name : "mapping"};
    if (err && err_size)
        err[0] = '\0';
    json_error_t je;
    json_t *root = json_loadb(data ? data : "", data ? size : 0, JSON_REJECT_DUPLICATES, &je);
    if (!root) {
        char where[512]; /* FILE:LINE:COL: like a compiler */
        snprintf(where, sizeof where, "%s:%d:%d", e.name, je.line, je.column);
        e.name = where;
        rf_errs_add(&e, "JSON syntax error: %s", je.text);
        return NULL;
    }
    rf_mapfile *f = calloc(1, sizeof *f);
    if (!f || (name && !(f->name = rf_strdup(name))))
        rf_errs_add(&e, "out of memory");
    else if (header(&e, root))
        body(&e, f, root);
    json_decref(root);
    if (e.count) {
        rf_errs_finish(&e);
        rf_mapfile_free(f);
        return NULL;
    }
    return f;
}

rf_mapfile *rf_mapfile_read(const char *path, char *err, size_t err_size)
{
    /* Regular files only, and O_NONBLOCK so that a FIFO cannot hang the open: a FIFO or a device
     * such as /dev/zero would block, or be read up to the size limit. */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    struct stat st;
    if (fd >= 0 && (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))) {
        close(fd);
        snprintf(err, err_size, "%s: not a regular file", path);
        return NULL;
    }
    FILE *in = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!in) {
        snprintf(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        if (fd >= 0)
            close(fd);
        return NULL;
    }
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, in);
        if (n < cap)
            break;
        char *b = cap < ((size_t)1 << 30) ? realloc(buf, cap * 2) : NULL;
        if (!b)
            free(buf);
        buf = b, cap *= 2;
    }
    bool failed = ferror(in) || !buf;
    fclose(in);
    if (failed) {
        free(buf);
        snprintf(err, err_size, "%s: cannot read (I/O error, or larger than 1 GiB)", path);
        return NULL;
    }
    rf_mapfile *f = rf_mapfile_parse(buf, n, path, err, err_size);
    free(buf);
    return f;
}

void rf_mapfile_free(rf_mapfile *f)
{
    if (!f)
        return;
    for (uint32_t i = 0; i < f->joint_count; i++) {
        rf_mapfile_joint *j = &f->joints[i];
        for (uint32_t k = 0; k < j->input_count; k++)
            free(j->inputs[k].joint);
        free(j->inputs);
        free(j->metrics);
        free(j->target);
        free(j->section);
        free(j->side);
    }
    for (uint32_t i = 0; i < f->source_count; i++)
        free(f->sources[i]);
    for (uint32_t i = 0; i < f->metric_count; i++)
        free(f->metric_names[i]);
    free(f->joints);
    free(f->sources);
    free(f->metric_names);
    free(f->target);
    free(f->name);
    free(f);
}

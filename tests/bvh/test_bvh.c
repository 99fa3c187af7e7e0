/* Tests of the BVH reader and writer (libbvh) and of the bvh plugin's nodes.
 *
 * Expected values come from hand computation or from the files themselves, read here with a few
 * lines of sscanf that share nothing with the reader. Tests that need the shared data read
 * RF_DATA_DIR and skip, saying why, without it; the plugin test needs RIGFLOW_PLUGIN_PATH.
 */
#include <dirent.h>
#include <locale.h>
#include <ltdl.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "bvh-math.h"
#include "bvh-num.h"
#include "rigflow/bvh.h"
#include "rigflow/plugin.h"

#define S2 0.70710678118654752440 /* sqrt(1/2) */

/* ---- helpers ---- */

static char err[2048];

static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    long n = ftell(f);
    rewind(f);
    char *buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    buf[n] = '\0';
    fclose(f);
    *size = (size_t)n;
    return buf;
}

/* A copy of `text` with every `from` replaced by `to` (count: 0 = all, 1 = the first). */
static char *replaced(const char *text, const char *from, const char *to, int count)
{
    size_t lf = strlen(from), lt = strlen(to), n = 0;
    char *out = malloc(strlen(text) * (lt > lf ? lt : 1) + 1);
    assert_non_null(out);
    int done = 0;
    for (const char *p = text; *p;) {
        if ((!count || done < count) && strncmp(p, from, lf) == 0) {
            memcpy(out + n, to, lt);
            n += lt, p += lf, done++;
        } else {
            out[n++] = *p++;
        }
    }
    out[n] = '\0';
    assert_true(done > 0);
    return out;
}

static bool parse(const char *text, rf_skeleton **s, rf_animation **a)
{
    err[0] = '\0';
    return rf_bvh_read_memory(text, strlen(text), "test.bvh", NULL, s, a, err, sizeof err);
}

/* Asserts that `text` is refused with a message naming test.bvh, `line` and `fragment`. */
static void expect_error(const char *text, int line, const char *fragment)
{
    rf_skeleton *s = (rf_skeleton *)1;
    rf_animation *a = (rf_animation *)1;
    char where[64];
    bool ok = parse(text, &s, &a);
    snprintf(where, sizeof where, "test.bvh:%d: ", line);
    print_message("  error: %s\n", err);
    assert_false(ok);
    assert_null(s);
    assert_null(a);
    assert_non_null(strstr(err, where));
    assert_non_null(strstr(err, fragment));
}

static void assert_quat_near(rf_quat q, double x, double y, double z, double w, double tol)
{
    double d = fabs(q.x * x + q.y * y + q.z * z + q.w * w); /* q and -q are one rotation */
    if (!(d > 1 - tol))
        fail_msg("quaternion (%g %g %g %g), expected (%g %g %g %g)", q.x, q.y, q.z, q.w, x, y, z,
                 w);
}

static void assert_vec_near(rf_vec3 v, double x, double y, double z, double tol)
{
    if (!(fabs(v.x - x) <= tol && fabs(v.y - y) <= tol && fabs(v.z - z) <= tol))
        fail_msg("(%.9g %.9g %.9g), expected (%.9g %.9g %.9g)", v.x, v.y, v.z, x, y, z);
}

/* Angle in radians between two rotations, accurate near 0 (acos of a dot product is not). */
static double rot_diff(rf_quat a, rf_quat b)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(rf_quat_normalize(a)), rf_quat_normalize(b));
    return 2 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), fabs(d.w));
}

/* World transforms of every joint in `frame` (scale 1): plain forward kinematics. */
static void world_pose(const rf_skeleton *s, const rf_animation *a, uint32_t frame, rf_xform *w)
{
    for (uint32_t j = 0; j < s->joint_count; j++) {
        rf_xform local = {rf_animation_translation(a, frame, j),
                          rf_quat_normalize(rf_animation_rotation(a, frame, j)), rf_v3(1, 1, 1)};
        int32_t p = s->joints[j].parent;
        w[j] = p < 0 ? local : rf_xform_mul(w[p], local);
    }
}

/* Rotation matrix (row-major m[r][c]) of `deg` degrees about axis 0/1/2: written out by hand. */
static void axis_matrix(int axis, double deg, double m[3][3])
{
    double c = cos(deg * RF_PI / 180), s = sin(deg * RF_PI / 180);
    double x[3][3] = {{1, 0, 0}, {0, c, -s}, {0, s, c}};
    double y[3][3] = {{c, 0, s}, {0, 1, 0}, {-s, 0, c}};
    double z[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
    memcpy(m, axis == 0 ? x : axis == 1 ? y : z, sizeof x);
}

static void mat_mul(double a[3][3], double b[3][3], double out[3][3])
{
    double r[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    memcpy(out, r, sizeof r);
}

/* Asserts that quaternion q rotates like matrix m. */
static void assert_quat_matrix(rf_quat q, double m[3][3], double tol)
{
    for (int c = 0; c < 3; c++) {
        rf_vec3 e = rf_v3(c == 0, c == 1, c == 2);
        rf_vec3 v = rf_quat_rotate(q, e);
        assert_vec_near(v, m[0][c], m[1][c], m[2][c], tol);
    }
}

static char *temp_dir(void)
{
    const char *base = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char *t = malloc(strlen(base) + 32);
    assert_non_null(t);
    sprintf(t, "%s/test_bvh.XXXXXX", base);
    assert_non_null(mkdtemp(t));
    return t;
}

static const char *data_dir(void)
{
    const char *d = getenv("RF_DATA_DIR");
    static char path[4096];
    if (!d || !*d)
        return NULL;
    snprintf(path, sizeof path, "%s/bvh", d);
    DIR *dir = opendir(path);
    if (!dir)
        return NULL;
    closedir(dir);
    return path;
}

#define NEED_DATA(dir)                                                                             \
    const char *dir = data_dir();                                                                  \
    if (!dir) {                                                                                    \
        print_message("  skipped: RF_DATA_DIR/bvh not found (the shared test data is absent)\n");  \
        skip();                                                                                    \
    }

/* ---- the sample file (line numbers matter to the error tests) ---- */

static const char *const sample =
    "HIERARCHY\n"                                                                /* 1 */
    "ROOT Hips\n"                                                                /* 2 */
    "{\n"                                                                        /* 3 */
    "  OFFSET 1 2 3\n"                                                           /* 4 */
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n" /* 5 */
    "  JOINT Chest\n"                                                            /* 6 */
    "  {\n"                                                                      /* 7 */
    "    OFFSET 0 10 0\n"                                                        /* 8 */
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"                             /* 9 */
    "    End Site\n"                                                             /* 10 */
    "    {\n"                                                                    /* 11 */
    "      OFFSET 0 5 0\n"                                                       /* 12 */
    "    }\n"                                                                    /* 13 */
    "  }\n"                                                                      /* 14 */
    "}\n"                                                                        /* 15 */
    "MOTION\n"                                                                   /* 16 */
    "Frames: 2\n"                                                                /* 17 */
    "Frame Time: 0.04\n"                                                         /* 18 */
    "0 0 0 0 0 0 90 0 0\n"                                                       /* 19 */
    "5 6 7 90 90 0 0 0 90\n";                                                    /* 20 */

/* ---- number parser ---- */

#if BVH_TOKEN_AVX2
/* bvh_short_avx2's shuffle table, made once. */
static const uint8_t (*avx2_shuffles(void))[16]
{
    static uint8_t shuf[BVH_SHUFFLES][16];
    static bool made;
    if (!made)
        bvh_shuffles_init(shuf), made = true;
    return (const uint8_t(*)[16])shuf;
}
#endif

static void check_number(const char *text)
{
    double ours = -1, ref;
    char *end;
    const char *e = rf_bvh_parse_double(text, &ours);
    ref = strtod(text, &end);
    assert_non_null(e);
    assert_ptr_equal(e, end);
    if (memcmp(&ours, &ref, sizeof ref) != 0)
        fail_msg("'%s': %.17g, strtod %.17g", text, ours, ref);
    /* the frame-line parsers, on text padded as the reader's buffer is */
    char padded[128 + BVH_PAD] = {0};
    if (strlen(text) < 100) {
        snprintf(padded, 128, "%s ", text);
        double v = -1;
        e = bvh_number_padded(padded, &v);
        assert_ptr_equal(e, padded + (end - text));
        assert_memory_equal(&v, &ref, sizeof ref);
#if BVH_TOKEN
        v = -1;
        const char *next;
        e = bvh_token_number(padded, &v, &next);
        if (e) { /* it may decline; when it answers it must be exact */
            assert_ptr_equal(e, padded + (end - text));
            assert_ptr_equal(next, e + 1); /* the NUL after the space */
            assert_memory_equal(&v, &ref, sizeof ref);
        }
#endif
#if BVH_TOKEN_AVX2
        if (__builtin_cpu_supports("avx2")) { /* the same tokens taken, the same values */
            bvh_avx2_k k;
            bvh_avx2_k_init(&k);
            size_t len = strlen(text);
            double w = -1;
            bool ok = bvh_short_avx2(padded, (unsigned)len, &w, avx2_shuffles(), &k);
            assert_int_equal(ok, e != NULL);
            if (ok)
                assert_memory_equal(&w, &ref, sizeof ref);
            uint32_t pos[BVH_LINE_POS(1)];
            w = -1;
            ok = bvh_line_avx2(padded, padded + len, &w, 1, pos, avx2_shuffles(), &k);
            assert_int_equal(ok, end == text + len && len > 0 && fabs(ref) < 1e15);
            if (ok)
                assert_memory_equal(&w, &ref, sizeof ref);
        }
#endif
    }
}

static void test_number_exact(void **state)
{
    (void)state;
    static const char *const cases[] = {"0",
                                        "-0",
                                        "0.0",
                                        ".5",
                                        "-.5",
                                        "1.",
                                        "123.456",
                                        "-16.4850",
                                        "0.0000",
                                        "1e-5",
                                        "-1.25E+3",
                                        "0.1",
                                        "0.3",
                                        "2.2250738585072014e-308",
                                        "4.9e-324",
                                        "1.7976931348623157e308",
                                        "9007199254740993",
                                        "9007199254740992.5",
                                        "123456789012345678901234567890",
                                        "0.000000000000000000000000000001",
                                        "1.00000000000000011102230246251565404236316680908203125",
                                        "-0.0262972",
                                        "8.68687e-06",
                                        "99999999",
                                        "1234.5678",
                                        "12345678.9",
                                        "+7",
                                        "0.0083333",
                                        ".0083333",
                                        "1e22",
                                        "1e23",
                                        "123456789e-22",
                                        "3.141592653589793238462643383279"};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++)
        check_number(cases[i]);
    /* random decimal strings of every shape the fast paths take or decline */
    srand(7);
    for (int i = 0; i < 200000; i++) {
        char buf[64];
        int n = 0, digits = 1 + rand() % 22, dot = rand() % (digits + 2);
        if (rand() % 2)
            buf[n++] = '-';
        for (int d = 0; d < digits; d++) {
            if (d == dot)
                buf[n++] = '.';
            buf[n++] = (char)('0' + rand() % 10);
        }
        if (rand() % 8 == 0)
            n += sprintf(buf + n, "e%d", rand() % 80 - 40);
        buf[n] = '\0';
        check_number(buf);
    }
}

/* Every number of every frame line of the shared BVH files, read as strtod reads it by each
 * of the frame-line parsers (check_number). */
static void test_number_data(void **state)
{
    (void)state;
    NEED_DATA(dir);
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t numbers = 0;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n <= 4 || strcmp(e->d_name + n - 4, ".bvh") != 0)
            continue;
        char path[4200];
        size_t size;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        char *text = read_all(path, &size);
        char *p = strstr(text, "Frame Time:");
        assert_non_null(p);
        p = strchr(p, '\n');
        for (char *tok = p ? strtok(p, " \t\r\n") : NULL; tok; tok = strtok(NULL, " \t\r\n"))
            check_number(tok), numbers++;
        free(text);
    }
    closedir(d);
    print_message("  %zu numbers\n", numbers);
    assert_true(numbers > 500000);
}

#if BVH_TOKEN_AVX2
static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r';
}

/* What a frame-line reader must answer, found the plain way: the line's blank-separated tokens,
 * each read whole by rf_bvh_parse_double (checked against strtod above, and here again) and of
 * magnitude below 1e15, exactly `count` of them, into v. */
static bool line_reference(const char *line, size_t len, double *v, size_t count)
{
    size_t n = 0;
    for (size_t i = 0, j; i < len; i = j) {
        while (i < len && is_blank(line[i]))
            i++;
        if (i == len)
            break;
        for (j = i; j < len && !is_blank(line[j]);)
            j++;
        char tok[256];
        if (j - i >= sizeof tok || n == count)
            return false;
        memcpy(tok, line + i, j - i);
        tok[j - i] = '\0';
        double x, ref;
        const char *e = rf_bvh_parse_double(tok, &x);
        if (!e || *e || !(fabs(x) < 1e15))
            return false;
        ref = strtod(tok, NULL);
        assert_memory_equal(&x, &ref, sizeof x);
        v[n++] = x;
    }
    return n == count;
}

/* bvh_line_avx2 on line[len] against line_reference; as in the reader's buffer, the line ends
 * in a '\n' and the next line's digits and points follow, which must not change the answer.
 * Returns whether the line was read. */
static bool check_line(const char *text, size_t len, size_t count)
{
    char *line = malloc(len + BVH_PAD + 1);
    uint32_t *pos = malloc(BVH_LINE_POS(count) * sizeof *pos);
    double *v = malloc((count + 1) * sizeof *v), *ref = malloc((count + 1) * sizeof *ref);
    assert_true(line && pos && v && ref);
    memcpy(line, text, len);
    line[len] = '\n';
    for (size_t i = 1; i <= BVH_PAD; i++)
        line[len + i] = "1.5-70"[i % 6];
    bvh_avx2_k k;
    bvh_avx2_k_init(&k);
    bool ok = bvh_line_avx2(line, line + len, v, count, pos, avx2_shuffles(), &k);
    bool want = line_reference(text, len, ref, count);
    if (ok != want)
        fail_msg("'%.*s' (%zu values): read %d, expected %d", (int)len, text, count, ok, want);
    if (ok)
        assert_memory_equal(v, ref, count * sizeof *v);
    free(line), free(pos), free(v), free(ref);
    return ok;
}

/* A random token: mostly numbers of the shapes exporters write, some that the short path
 * declines (long, exponents, '+'), and, unless `clean`, some that are not numbers at all. */
static int random_token(char *buf, bool clean)
{
    static const char junk[] = "+-.eE0x\v\f#,";
    int n = 0, kind = clean ? 1 + rand() % 12 : rand() % 16;
    if (kind == 0) { /* characters that may or may not make a number */
        for (int i = 1 + rand() % 4; i > 0; i--)
            buf[n++] = junk[rand() % (int)(sizeof junk - 1)];
        return n;
    }
    int digits = kind < 12 ? 1 + rand() % 9 : 1 + rand() % 24, dot = rand() % (digits + 2);
    if (rand() % 2)
        buf[n++] = '-';
    for (int d = 0; d < digits; d++) {
        if (d == dot)
            buf[n++] = '.';
        buf[n++] = (char)('0' + rand() % 10);
    }
    if (kind == 12)
        n += sprintf(buf + n, "e%d", rand() % 60 - 30);
    if (kind == 13)
        buf[rand() % n] = "+.eE"[rand() % 4];
    return n;
}

/* Random frame lines for the AVX2 line reader: numbers and stray tokens between runs of
 * spaces, tabs and CRs (some longer than its 32-byte blocks), with the right count of values or
 * one off. */
static void test_line_random(void **state)
{
    (void)state;
    if (!__builtin_cpu_supports("avx2"))
        skip();
    srand(11);
    int read = 0;
    for (int i = 0; i < 40000; i++) {
        char line[4096];
        size_t len = 0, tokens = 0;
        int count = rand() % 40;
        bool clean = rand() % 2; /* half the lines hold only numbers */
        for (int t = 0; t < count; t++) {
            int blanks = rand() % 50 == 0 ? 30 + rand() % 100 : (t ? 1 : 0) + rand() % 3;
            for (int b = 0; b < blanks; b++)
                line[len++] = " \t\r"[rand() % 3 ? 0 : 1 + rand() % 2];
            len += (size_t)random_token(line + len, clean);
            tokens++;
        }
        for (int b = rand() % 4; b > 0; b--)
            line[len++] = rand() % 2 ? ' ' : '\r';
        size_t want = tokens;
        if (rand() % 8 == 0)
            want = rand() % 2 || !want ? want + 1 : want - 1;
        read += check_line(line, len, want);
    }
    print_message("  %d of 40000 random lines read\n", read);
    assert_true(read > 10000); /* the lines of numbers alone below 1e15, of the right count */
}

/* Every frame line of every shared BVH file, read by the AVX2 line reader exactly as strtod
 * reads its numbers. */
static void test_line_data(void **state)
{
    (void)state;
    if (!__builtin_cpu_supports("avx2"))
        skip();
    NEED_DATA(dir);
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t lines = 0;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n <= 4 || strcmp(e->d_name + n - 4, ".bvh") != 0)
            continue;
        char path[4200];
        size_t size;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        char *text = read_all(path, &size);
        const char *p = strstr(text, "Frame Time:");
        assert_non_null(p);
        for (p = strchr(p, '\n'); p && p[1]; p = strchr(p, '\n')) {
            p++;
            size_t len = strcspn(p, "\n"), count = 0;
            for (size_t i = 0; i < len; i++)
                count += !is_blank(p[i]) && (i == 0 || is_blank(p[i - 1]));
            if (count)
                assert_true(check_line(p, len, count)), lines++;
        }
        free(text);
    }
    closedir(d);
    print_message("  %zu frame lines\n", lines);
    assert_true(lines > 5000);
}
#endif

/* A locale whose decimal point is a comma changes nothing, slow path included. */
static void test_number_locale(void **state)
{
    (void)state;
    static const char *const cases[] = {"1.5", "-16.4850", "123456789012345678901234567890.5",
                                        "0.000000000000000000000000000001234", "1e-300"};
    double before[5];
    for (int i = 0; i < 5; i++)
        assert_non_null(rf_bvh_parse_double(cases[i], &before[i]));
    const char *names[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8", "de_DE"};
    const char *loc = NULL;
    for (int i = 0; i < 5 && !loc; i++)
        loc = setlocale(LC_NUMERIC, names[i]);
    char *dir = NULL, cmd[512];
    if (!loc) { /* none installed: build one where glibc's LOCPATH finds it, if localedef can */
        dir = temp_dir();
        snprintf(cmd, sizeof cmd, "localedef -i de_DE -f UTF-8 '%s/de_DE.UTF-8' >/dev/null 2>&1",
                 dir);
        if (system(cmd) == 0 && setenv("LOCPATH", dir, 1) == 0)
            loc = setlocale(LC_NUMERIC, "de_DE.UTF-8");
    }
    if (!loc || strtod("1.5", NULL) == 1.5) {
        print_message("  skipped: no locale with a decimal comma (none installed, no localedef)\n");
        skip();
    }
    for (int i = 0; i < 5; i++) {
        double v;
        const char *e = rf_bvh_parse_double(cases[i], &v);
        assert_ptr_equal(e, cases[i] + strlen(cases[i]));
        assert_memory_equal(&v, &before[i], sizeof v);
    }
    setlocale(LC_NUMERIC, "C");
    if (dir) {
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
        assert_int_equal(system(cmd), 0);
        unsetenv("LOCPATH");
        free(dir);
    }
}

static void test_number_rejects(void **state)
{
    (void)state;
    static const char *const bad[] = {"",    "-",    ".",   "-.", "e5",  "nan",
                                      "inf", "-inf", "abc", "1e", "1e+", "x1"};
    double v;
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        const char *e = rf_bvh_parse_double(bad[i], &v);
        if (e && e != bad[i]) /* "1e" parses as "1" up to the 'e' in strtod; we refuse it */
            fail_msg("'%s' accepted", bad[i]);
    }
}

/* The writer's number formatting is printf's %.*g to the byte (but for -0). */
static void test_format_number(void **state)
{
    (void)state;
    char ours[64], ref[64];
    static const double edge[] = {9.9999999995, 0.00099999999995, 999999999.5, 0.0001,   1e-5,
                                  123456789,    1234567890,       0.1,         0.5,      2.5,
                                  1e15,         99999.99999,      0.0083333,   120.0005, -0.0,
                                  1e300,        -4.9e-324};
    for (size_t i = 0; i < sizeof edge / sizeof *edge; i++)
        for (int p = 3; p <= 17; p++) {
            rf_bvh_format_number(ours, sizeof ours, p, edge[i]);
            snprintf(ref, sizeof ref, "%.*g", p, edge[i] == 0 ? 0.0 : edge[i]);
            assert_string_equal(ours, ref);
        }
    srand(1);
    for (int i = 0; i < 300000; i++) {
        int p = 3 + rand() % 15;
        double v = (double)rand() / RAND_MAX * pow(10, (rand() % 2200) / 100.0 - 6);
        if (i % 3 == 1)
            v = (float)v; /* values that came from floats, as animations hold */
        if (i % 3 == 2)
            v = (rand() % 36000) / 100.0 - 180;
        if (rand() % 2)
            v = -v;
        rf_bvh_format_number(ours, sizeof ours, p, v);
        snprintf(ref, sizeof ref, "%.*g", p, v == 0 ? 0.0 : v); /* we write -0 as 0 */
        if (strcmp(ours, ref) != 0)
            fail_msg("%.17g at %d digits: '%s', printf '%s'", v, p, ours, ref);
    }
}

/* sin and cos of half-angles against libm, over angles a BVH file may hold. */
static void test_sincos(void **state)
{
    (void)state;
    double deg[4001], s[4001], c[4001];
    for (int i = 0; i <= 4000; i++)
        deg[i] = -1000.0 + i * 0.5 + i * 1e-4;
    deg[0] = 1e20, deg[1] = -3e17; /* handled by the libm fallback */
    bvh_sincos_half(deg, s, c, 4001);
    bvh_sincos_half_fix(deg, s, c, 4001);
#if BVH_AVX2
    /* the AVX2 variant gives the very same bits */
    if (__builtin_cpu_supports("avx2")) {
        double s4[4001], c4[4001];
        bvh_sincos_half_avx2(deg, s4, c4, 4001);
        bvh_sincos_half_fix(deg, s4, c4, 4001);
        assert_memory_equal(s4, s, sizeof s);
        assert_memory_equal(c4, c, sizeof c);
    } else {
        print_message("  no AVX2 here: its variant is not checked\n");
    }
#endif
    for (int i = 0; i <= 4000; i++) {
        double h = fmod(deg[i], 720.0) * RF_PI / 360.0;
        if (fabs(s[i] - sin(h)) > 1e-14 || fabs(c[i] - cos(h)) > 1e-14)
            fail_msg("%g degrees: %.17g %.17g, libm %.17g %.17g", deg[i], s[i], c[i], sin(h),
                     cos(h));
    }
}

/* ---- reading: hand-computed values ---- */

static void test_sample_values(void **state)
{
    (void)state;
    rf_skeleton *s;
    rf_animation *a;
    assert_true(parse(sample, &s, &a));
    assert_int_equal(s->joint_count, 2);
    assert_string_equal(s->joints[0].name, "Hips");
    assert_string_equal(s->joints[1].name, "Chest");
    assert_int_equal(s->joints[0].parent, -1);
    assert_int_equal(s->joints[1].parent, 0);
    assert_vec_near(s->joints[0].rest.t, 1, 2, 3, 0);
    assert_vec_near(s->joints[1].rest.t, 0, 10, 0, 0);
    assert_quat_near(s->joints[1].rest.r, 0, 0, 0, 1, 1e-12);
    assert_true(s->joints[1].flags & RF_JOINT_HAS_END_SITE);
    assert_false(s->joints[0].flags & RF_JOINT_HAS_END_SITE);
    assert_vec_near(s->joints[1].end_site, 0, 5, 0, 0);
    assert_int_equal(a->frame_count, 2);
    assert_true(fabs(a->fps - 25) < 1e-9);
    assert_int_equal(a->channels[0], RF_CHANNEL_ROTATION | RF_CHANNEL_TRANSLATION);
    assert_int_equal(a->channels[1], RF_CHANNEL_ROTATION);
    /* frame 1: Hips at the position channels (0 0 0), Chest Rz(90) */
    assert_vec_near(rf_animation_translation(a, 0, 0), 0, 0, 0, 0);
    assert_quat_near(rf_animation_rotation(a, 0, 0), 0, 0, 0, 1, 1e-7);
    assert_vec_near(rf_animation_translation(a, 0, 1), 0, 10, 0, 0);
    assert_quat_near(rf_animation_rotation(a, 0, 1), 0, 0, S2, S2, 1e-7);
    /* frame 2: Hips at (5 6 7), Rz(90) Rx(90) = (0.5 0.5 0.5 0.5) (x -> y -> z -> x); Chest
     * Ry(90) */
    assert_vec_near(rf_animation_translation(a, 1, 0), 5, 6, 7, 0);
    assert_quat_near(rf_animation_rotation(a, 1, 0), 0.5, 0.5, 0.5, 0.5, 1e-7);
    assert_quat_near(rf_animation_rotation(a, 1, 1), 0, S2, 0, S2, 1e-7);
    /* through forward kinematics: Chest at (5 6 7) + (0 0 10); the end site (0 5 0) turned by
     * Ry(90) (no change) then x -> y -> z: (0 0 5) more */
    rf_xform w[2];
    world_pose(s, a, 1, w);
    assert_vec_near(w[1].t, 5, 6, 17, 1e-5);
    assert_vec_near(rf_xform_point(w[1], s->joints[1].end_site), 5, 6, 22, 1e-5);
    assert_string_equal(s->name, "test.bvh");
    assert_string_equal(a->name, "test");
    rf_skeleton_free(s);
    rf_animation_free(a);
}

/* Each of the six orders composes in the order listed: R = R1 R2 R3. */
static void test_channel_orders(void **state)
{
    (void)state;
    static const char *const orders[6] = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};
    const double ang[3] = {30, 45, 60};
    for (int o = 0; o < 6; o++) {
        char text[512];
        int ax[3];
        for (int i = 0; i < 3; i++)
            ax[i] = orders[o][i] - 'X';
        snprintf(text, sizeof text,
                 "HIERARCHY\nROOT r\n{\n OFFSET 0 0 0\n CHANNELS 3 %crotation %crotation "
                 "%crotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n30 45 60\n",
                 orders[o][0], orders[o][1], orders[o][2]);
        rf_skeleton *s;
        rf_animation *a;
        assert_true(parse(text, &s, &a));
        double m[3][3], r[3][3];
        axis_matrix(ax[0], ang[0], m);
        for (int i = 1; i < 3; i++) {
            axis_matrix(ax[i], ang[i], r);
            mat_mul(m, r, m);
        }
        assert_quat_matrix(rf_animation_rotation(a, 0, 0), m, 1e-6);
        rf_skeleton_free(s);
        rf_animation_free(a);
    }
}

/* 6 channels in a mixed order on a child, and a single position channel. */
static void test_six_channels(void **state)
{
    (void)state;
    const char *text = "HIERARCHY\nROOT a\n{\n OFFSET 0 0 0\n CHANNELS 0\n JOINT b\n {\n"
                       "  OFFSET 1 2 3\n"
                       "  CHANNELS 6 Yrotation Xposition Zrotation Yposition Xrotation Zposition\n"
                       "  JOINT c\n  {\n   OFFSET 4 5 6\n   CHANNELS 1 Yposition\n  }\n }\n}\n"
                       "MOTION\nFrames: 1\nFrame Time: 0.5\n"
                       "90 -1 90 -2 0 -3 7\n";
    rf_skeleton *s;
    rf_animation *a;
    assert_true(parse(text, &s, &a));
    assert_int_equal(a->channels[0], 0);
    assert_int_equal(a->channels[1], RF_CHANNEL_ROTATION | RF_CHANNEL_TRANSLATION);
    assert_int_equal(a->channels[2], RF_CHANNEL_TRANSLATION);
    assert_vec_near(rf_animation_translation(a, 0, 0), 0, 0, 0, 0);
    assert_vec_near(rf_animation_translation(a, 0, 1), -1, -2, -3, 0); /* replaces the OFFSET */
    assert_vec_near(rf_animation_translation(a, 0, 2), 4, 7, 6, 0);    /* y from the channel */
    assert_vec_near(s->joints[1].rest.t, 1, 2, 3, 0);
    /* Ry(90) Rz(90) Rx(0): x -> y (Rz) -> y (Ry); y -> -x -> z */
    double m[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
    assert_quat_matrix(rf_animation_rotation(a, 0, 1), m, 1e-6);
    rf_skeleton_free(s);
    rf_animation_free(a);
}

/* CRLF, tabs and odd spacing read the same as the plain sample, bit for bit. */
static void test_line_endings_and_tabs(void **state)
{
    (void)state;
    rf_skeleton *s0, *s1;
    rf_animation *a0, *a1;
    assert_true(parse(sample, &s0, &a0));
    char *crlf = replaced(sample, "\n", "\r\n", 0);
    char *tabs = replaced(sample, " ", "\t", 0);
    char *mixed = replaced(crlf, " ", " \t ", 0);
    char *noeol = strdup(sample);
    noeol[strlen(noeol) - 1] = '\0'; /* no newline after the last frame */
    const char *variants[] = {crlf, tabs, mixed, noeol};
    for (int v = 0; v < 4; v++) {
        assert_true(parse(variants[v], &s1, &a1));
        assert_int_equal(s1->joint_count, s0->joint_count);
        assert_string_equal(s1->joints[1].name, "Chest");
        assert_memory_equal(a1->rotations, a0->rotations, 2 * 2 * 4 * sizeof(float));
        assert_memory_equal(a1->translations, a0->translations, 2 * 2 * 3 * sizeof(float));
        rf_skeleton_free(s1);
        rf_animation_free(a1);
    }
    free(crlf), free(tabs), free(mixed), free(noeol);
    rf_skeleton_free(s0);
    rf_animation_free(a0);
}

/* ---- reading: malformed input ---- */

static void error_case(const char *from, const char *to, int line, const char *fragment)
{
    char *text = replaced(sample, from, to, 1);
    expect_error(text, line, fragment);
    free(text);
}

static void test_errors(void **state)
{
    (void)state;
    /* 3 frames need at least 3 * 18 - 1 bytes: lengthen the values so only the count is wrong */
    char *longer = replaced(sample, "5 6 7 90 90", "5.000000 6.000000 7.000000 90 90", 1);
    char *truncated = replaced(longer, "Frames: 2", "Frames: 3", 1);
    expect_error(truncated, 21, "MOTION is truncated: the file ends after 2 of 3 frames");
    free(longer), free(truncated);
    error_case("5 6 7 90 90 0 0 0 90", "5 6 7 90 90 0 0 0", 20, "frame 2 has 8 values, expected 9");
    error_case("0 0 0 0 0 0 90 0 0", "0 0 0 0 0 0 90 0 0 1", 19,
               "frame 1 has 10 values, expected 9");
    error_case("CHANNELS 3 Zrotation Xrotation", "CHANNELS 3 Zrotation Wrotation", 9,
               "unknown channel 'Wrotation': expected Xposition");
    error_case("JOINT Chest", "JOINT Hips", 6,
               "duplicate joint name 'Hips' (first declared on line 2)");
    error_case("5 6 7 90", "5 6 nan 90", 20,
               "'nan' is not a finite number (frame 2, joint 'Hips', Zposition)");
    error_case("5 6 7 90 90", "5 6 7 90 -inf", 20, "'-inf' is not a finite number");
    error_case("5 6 7 90 90", "5 6 7 90 1e999", 20, "'1e999' is not a finite number");
    error_case("OFFSET 0 10 0", "OFFSET 0 NaN 0", 8, "'NaN' is not a finite number");
    /* finite, but beyond what the model's floats and squared distances hold */
    error_case("OFFSET 0 10 0", "OFFSET 0 1e31 0", 8,
               "'1e31' is out of range: expected the OFFSET's y within +-1e+30");
    error_case("5 6 7 90", "5 6 -2e30 90", 20,
               "'-2e30' is out of range (frame 2, joint 'Hips', Zposition): expected a coordinate");
    error_case("Frames: 2", "Frames: two", 17, "expected a whole number of frames after 'Frames:'");
    error_case("Frames: 2", "Frames: -1", 17, "expected a whole number of frames from 0");
    error_case("Frames: 2", "Frames: 2.5", 17, "expected a whole number of frames from 0");
    error_case("Frames: 2", "Frames: 4000000000", 17, "is more than the rest of the file can hold");
    error_case("Frames: 2", "Frame: 2", 17, "expected 'Frames:'");
    error_case("Frame Time: 0.04", "Frame Time: 0", 18, "expected a positive Frame Time");
    error_case("Frame Time: 0.04", "Frame Time: fast", 18, "expected the seconds per frame");
    error_case("0 0 0 0 0 0 90 0 0", "0 0 12a 0 0 0 90 0 0", 19,
               "expected a number for joint 'Hips' Zposition in frame 1, found '12a'");
    error_case("  {\n    OFFSET 0 10 0", "  (\n    OFFSET 0 10 0", 7,
               "expected { after the joint name, found '('");
    error_case("HIERARCHY", "HIERARCHX", 1,
               "expected HIERARCHY at the start of the file, found 'HIERARCHX'");
    error_case("CHANNELS 3 Zrotation", "CHANNELS 7 Zrotation", 9,
               "expected a channel count from 0 to 6, found '7'");
    error_case("CHANNELS 3 Zrotation Xrotation", "CHANNELS 3 Zrotation Zrotation", 9,
               "channel Zrotation listed twice for joint 'Chest'");
    error_case("MOTION", "MOTON", 16, "expected ROOT or MOTION, found 'MOTON'");
    error_case("      OFFSET 0 5 0\n", "\n", 13, "expected OFFSET in the End Site, found '}'");
    error_case("  OFFSET 1 2 3\n", "  OFFSET 1 2\n", 5,
               "expected the OFFSET's z, found 'CHANNELS'");
    error_case("ROOT Hips", "ROOT", 2, "expected a joint name after ROOT");
    error_case("    End Site\n", "    End Sit\n", 10, "expected Site after End, found 'Sit'");
    error_case("MOTION\n", "MOTION extra\n", 16, "expected the end of the line after MOTION");

    /* the file ends inside the hierarchy */
    char *cut = strdup(sample);
    *strstr(cut, "  }\n}\nMOTION") = '\0'; /* after line 13 */
    expect_error(cut, 14, "the file ends inside joint 'Chest' (opened on line 6): expected '}'");
    *strstr(cut, "    }\n") = '\0'; /* after line 12 */
    expect_error(cut, 13, "expected } closing the End Site, found the end of the file");
    free(cut);
    expect_error("", 1, "expected HIERARCHY");
    expect_error("HIERARCHY\n", 2, "the file ends before MOTION: expected ROOT");
}

/* A Frames count far beyond the data is refused before anything is allocated for it. */
static void test_frames_bound(void **state)
{
    (void)state;
    char *text = replaced(sample, "Frames: 2", "Frames: 4294967294", 1);
    clock_t t0 = clock();
    /* the two frame lines hold 40 bytes: at most (40 + 1) / (2 * 9) = 2 frames */
    expect_error(text, 17, "(40 bytes, at most 2 frames of 9 values)");
    assert_true((double)(clock() - t0) / CLOCKS_PER_SEC < 0.5);
    free(text);
}

/* 100k joints nested in one chain: no recursion, so no stack overflow, both ways. */
static void test_deep_nesting(void **state)
{
    (void)state;
    const int depth = 100000;
    size_t cap = (size_t)depth * 80 + 1000, n = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    n += (size_t)sprintf(text + n, "HIERARCHY\n");
    for (int i = 0; i < depth; i++)
        n += (size_t)sprintf(text + n,
                             "%s j%d\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n",
                             i ? "JOINT" : "ROOT", i);
    n += (size_t)sprintf(text + n, "End Site\n{\nOFFSET 0 1 0\n}\n");
    for (int i = 0; i < depth; i++)
        text[n++] = '}', text[n++] = '\n';
    n += (size_t)sprintf(text + n, "MOTION\nFrames: 1\nFrame Time: 0.1\n");
    for (int i = 0; i < depth; i++)
        n += (size_t)sprintf(text + n, "0 %d 0 ", i == depth - 1 ? 90 : 0);
    text[n++] = '\n';
    text[n] = '\0';
    rf_skeleton *s, *s2;
    rf_animation *a, *a2;
    assert_true(rf_bvh_read_memory(text, n, "deep.bvh", NULL, &s, &a, err, sizeof err));
    assert_int_equal(s->joint_count, depth);
    assert_int_equal(s->joints[depth - 1].parent, depth - 2);
    assert_true(s->joints[depth - 1].flags & RF_JOINT_HAS_END_SITE);
    assert_quat_near(rf_animation_rotation(a, 0, depth - 1), S2, 0, 0, S2, 1e-6);

    char *dir = temp_dir(), path[4200];
    snprintf(path, sizeof path, "%s/deep.bvh", dir);
    assert_true(rf_bvh_write_file(path, NULL, s, a, NULL, err, sizeof err));
    assert_true(rf_bvh_read_file(path, NULL, &s2, &a2, err, sizeof err));
    assert_int_equal(s2->joint_count, depth);
    assert_int_equal(s2->joints[depth - 1].parent, depth - 2);
    assert_quat_near(rf_animation_rotation(a2, 0, depth - 1), S2, 0, 0, S2, 1e-6);
    remove(path);
    rmdir(dir);
    free(dir);

    /* and the file ending inside the deepest joint names it */
    char *cut = strstr(text, "End Site");
    *cut = '\0';
    char msg[64];
    snprintf(msg, sizeof msg, "inside joint 'j%d'", depth - 1);
    rf_skeleton *s3;
    rf_animation *a3;
    assert_false(
        rf_bvh_read_memory(text, strlen(text), "deep.bvh", NULL, &s3, &a3, err, sizeof err));
    assert_non_null(strstr(err, msg));
    free(text);
    rf_skeleton_free(s), rf_skeleton_free(s2);
    rf_animation_free(a), rf_animation_free(a2);
}

static int warnings;
static char last_warning[512];
static void on_warning(void *user, const char *message)
{
    (void)user;
    warnings++;
    snprintf(last_warning, sizeof last_warning, "%s", message);
}

static int progress_calls;
static bool cancel_at_half(void *user, double fraction)
{
    (void)user;
    progress_calls++;
    return fraction < 0.5;
}

/* Lines after the declared frames are ignored with a warning; progress can cancel. */
static void test_trailing_and_cancel(void **state)
{
    (void)state;
    char *text = replaced(sample, "Frames: 2", "Frames: 1", 1);
    rf_bvh_read_opts opts = {.warning = on_warning};
    rf_skeleton *s;
    rf_animation *a;
    warnings = 0;
    assert_true(rf_bvh_read_memory(text, strlen(text), "test.bvh", &opts, &s, &a, err, sizeof err));
    assert_int_equal(a->frame_count, 1);
    assert_int_equal(warnings, 1);
    assert_non_null(strstr(last_warning, "test.bvh:20: 1 line after the 1 frames"));
    rf_skeleton_free(s);
    rf_animation_free(a);
    free(text);

    /* 5000 frames of one joint: progress is reported, and returning false cancels */
    size_t cap = 5000 * 8 + 200, n = 0;
    char *big = malloc(cap);
    n += (size_t)sprintf(big, "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\n"
                              "MOTION\nFrames: 5000\nFrame Time: 0.01\n");
    for (int f = 0; f < 5000; f++)
        n += (size_t)sprintf(big + n, "%d\n", f % 360);
    rf_bvh_read_opts cancel = {.progress = cancel_at_half};
    progress_calls = 0;
    assert_false(rf_bvh_read_memory(big, n, "big.bvh", &cancel, &s, &a, err, sizeof err));
    assert_true(progress_calls >= 1);
    assert_non_null(strstr(err, "cancelled"));
    free(big);
}

/* A 6000-frame, 1.5 MB file: enough for the reader to split frames between two threads. */
static char *big_text(size_t *size)
{
    size_t cap = 6000 * 400 + 4096, n = 0;
    char *t = malloc(cap);
    assert_non_null(t);
    n += (size_t)sprintf(t, "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition "
                            "Zposition Zrotation Yrotation Xrotation\n");
    for (int j = 1; j < 10; j++)
        n += (size_t)sprintf(t + n,
                             "JOINT j%d\n{\nOFFSET 0 %d 0\nCHANNELS 3 Yrotation Xrotation "
                             "Zrotation\n",
                             j, j);
    n += (size_t)sprintf(t + n, "End Site\n{\nOFFSET 0 1 0\n}\n");
    for (int j = 0; j < 10; j++)
        n += (size_t)sprintf(t + n, "}\n");
    n += (size_t)sprintf(t + n, "MOTION\nFrames: 6000\nFrame Time: 0.01\n");
    srand(5);
    for (int f = 0; f < 6000; f++) {
        for (int v = 0; v < 33; v++)
            n += (size_t)sprintf(t + n, "%.6f ", (rand() % 2000000) / 1e4 - 100);
        t[n - 1] = '\n';
    }
    t[n] = '\0';
    *size = n;
    return t;
}

/* The line number of frame `frame` (1-based) in big_text: 5 lines for the root, 4 per joint, 4
 * for the End Site, 10 closing braces and 3 of MOTION header come before. */
static int big_line(int frame)
{
    return 5 + 9 * 4 + 4 + 10 + 3 + frame;
}

static void replace_value(char *text, int line)
{
    char *p = text;
    for (int l = 1; l < line; l++)
        p = strchr(p, '\n') + 1;
    p = strchr(p, ' ') + 1; /* the second value */
    memcpy(p, "nanxxxxxxx", strcspn(p, " "));
}

/* Two threads read exactly what one does, and report the first error in file order. */
static void test_threads(void **state)
{
    (void)state;
    size_t size;
    char *text = big_text(&size);
    rf_bvh_read_opts one = {.threads = 1}, any = {.threads = 0};
    rf_skeleton *s1, *s2;
    rf_animation *a1, *a2;
    assert_true(size > (1u << 20));
    assert_true(rf_bvh_read_memory(text, size, "big.bvh", &one, &s1, &a1, err, sizeof err));
    assert_true(rf_bvh_read_memory(text, size, "big.bvh", &any, &s2, &a2, err, sizeof err));
    assert_int_equal(a1->frame_count, 6000);
    assert_memory_equal(a1->rotations, a2->rotations, 6000 * 10 * 4 * sizeof(float));
    assert_memory_equal(a1->translations, a2->translations, 6000 * 10 * 3 * sizeof(float));
    rf_skeleton_free(s1), rf_animation_free(a1);
    rf_skeleton_free(s2), rf_animation_free(a2);

    /* a value the fast path declines (huge angle) late in a batch: same result */
    char *p = text;
    for (int l = 1; l < big_line(2000); l++)
        p = strchr(p, '\n') + 1;
    size_t len = strcspn(p, " ");
    memset(p, ' ', len);
    memcpy(p, "1e20", 4);
    if (!rf_bvh_read_memory(text, size, "big.bvh", &one, &s1, &a1, err, sizeof err) ||
        !rf_bvh_read_memory(text, size, "big.bvh", &any, &s2, &a2, err, sizeof err))
        fail_msg("%s", err);
    assert_memory_equal(a1->rotations, a2->rotations, 6000 * 10 * 4 * sizeof(float));
    rf_skeleton_free(s1), rf_animation_free(a1);
    rf_skeleton_free(s2), rf_animation_free(a2);

    /* batches are 512 lines from frame 1, split in halves: frames 2561-2816 and 2817-3072. An
     * error in the second half alone, then one in the first half too: the first is named */
    static const int bad[2] = {2900, 2700};
    for (int b = 0; b < 2; b++) {
        replace_value(text, big_line(bad[b]));
        char expect[64], where[64];
        snprintf(where, sizeof where, "big.bvh:%d: 'nanx", big_line(bad[b]));
        snprintf(expect, sizeof expect, "is not a finite number (frame %d, joint 'j0'", bad[b]);
        for (int t = 0; t < 2; t++) {
            assert_false(rf_bvh_read_memory(text, size, "big.bvh", t ? &any : &one, &s1, &a1, err,
                                            sizeof err));
            if (!strstr(err, where) || !strstr(err, expect))
                fail_msg("%s, expected %s ... %s", err, where, expect);
        }
    }
    free(text);
}

/* ---- the shared files ---- */

/* Joint and frame counts read with sscanf: ROOT and JOINT lines, and the Frames: line. */
static void count_in_text(const char *text, uint32_t *joints, uint32_t *frames, uint32_t *six)
{
    *joints = *frames = *six = 0;
    for (const char *p = text; p && *p; p = strchr(p, '\n'), p = p ? p + 1 : p) {
        char word[32];
        unsigned n;
        if (sscanf(p, "%31s", word) != 1)
            continue;
        if (strcmp(word, "ROOT") == 0 || strcmp(word, "JOINT") == 0)
            (*joints)++;
        if (sscanf(p, " CHANNELS %u", &n) == 1 && n == 6)
            (*six)++;
        if (sscanf(p, " Frames: %u", &n) == 1)
            *frames = n;
    }
}

/* The counts in ../shared/data/README.md, to cross-check the text counts above. */
static void readme_counts(const char *name, uint32_t *joints, uint32_t *frames)
{
    static const struct {
        const char *name;
        uint32_t joints, frames;
    } table[] = {{"cmu_01_01.bvh", 31, 2752},  {"dme_example_cmu.bvh", 31, 278},
                 {"dme_rest_cmu.bvh", 31, 1},  {"boxing_toes.bvh", 21, 3069},
                 {"bandai_walk.bvh", 22, 195}, {"bandai_kick.bvh", 22, 358},
                 {"bandai_run.bvh", 22, 68}};
    *joints = *frames = 0;
    for (size_t i = 0; i < sizeof table / sizeof *table; i++)
        if (strcmp(table[i].name, name) == 0)
            *joints = table[i].joints, *frames = table[i].frames;
}

static void compare_motion(const rf_skeleton *s, const rf_animation *a, const rf_skeleton *s2,
                           const rf_animation *a2, const char *name)
{
    rf_xform *w = malloc(s->joint_count * sizeof *w), *w2 = malloc(s->joint_count * sizeof *w);
    double scale = 1;
    for (uint32_t j = 0; j < s->joint_count; j++)
        scale = fmax(scale, rf_v3_len(s->joints[j].rest.t));
    for (uint32_t f = 0; f < a->frame_count; f++) {
        world_pose(s, a, f, w);
        world_pose(s2, a2, f, w2);
        for (uint32_t j = 0; j < s->joint_count; j++) {
            double d = rf_v3_dist(w[j].t, w2[j].t);
            double ang = rot_diff(w[j].r, w2[j].r);
            if (d > 1e-5 * (scale + rf_v3_len(w[j].t)) || ang > 2e-5)
                fail_msg("%s frame %u joint %s: moved %g, turned %g rad", name, f,
                         s->joints[j].name, d, ang);
        }
    }
    free(w), free(w2);
}

static void roundtrip_file(const char *dir, const char *name, const char *tmp)
{
    char path[4200], out[4200];
    size_t size;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(out, sizeof out, "%s/out.bvh", tmp);
    char *text = read_all(path, &size);
    uint32_t joints, frames, six, rj, rf;
    count_in_text(text, &joints, &frames, &six);
    readme_counts(name, &rj, &rf);
    if (rj) { /* the README and the text agree */
        assert_int_equal(rj, joints);
        assert_int_equal(rf, frames);
    }
    rf_skeleton *s, *s2;
    rf_animation *a, *a2;
    warnings = 0;
    rf_bvh_read_opts opts = {.warning = on_warning};
    if (!rf_bvh_read_file(path, &opts, &s, &a, err, sizeof err))
        fail_msg("%s", err);
    print_message("  %s: %u joints, %u frames, %.4g fps%s%s\n", name, s->joint_count,
                  a->frame_count, a->fps, warnings ? "; warning: " : "",
                  warnings ? last_warning : "");
    assert_int_equal(s->joint_count, joints);
    assert_int_equal(a->frame_count, frames);
    uint32_t with_pos = 0;
    for (uint32_t j = 0; j < s->joint_count; j++)
        with_pos += (a->channels[j] & RF_CHANNEL_TRANSLATION) != 0;
    assert_int_equal(with_pos, six); /* only 6-channel joints have position channels here */

    assert_true(rf_bvh_write_file(out, NULL, s, a, NULL, err, sizeof err));
    if (!rf_bvh_read_file(out, NULL, &s2, &a2, err, sizeof err))
        fail_msg("%s", err);
    assert_int_equal(s2->joint_count, s->joint_count);
    assert_int_equal(a2->frame_count, a->frame_count);
    assert_true(fabs(a2->fps - a->fps) < 1e-6 * a->fps);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        const rf_joint *p = &s->joints[j], *q = &s2->joints[j];
        assert_string_equal(p->name, q->name);
        assert_int_equal(p->parent, q->parent);
        assert_int_equal(p->flags, q->flags);
        assert_vec_near(q->rest.t, p->rest.t.x, p->rest.t.y, p->rest.t.z, 1e-6);
        assert_vec_near(q->end_site, p->end_site.x, p->end_site.y, p->end_site.z, 1e-6);
        assert_int_equal(a2->channels[j] & a->channels[j], a->channels[j]);
        for (uint32_t f = 0; f < a->frame_count; f++) {
            rf_quat r = rf_animation_rotation(a, f, j), r2 = rf_animation_rotation(a2, f, j);
            if (rot_diff(rf_quat_normalize(r), rf_quat_normalize(r2)) > 2e-6)
                fail_msg("%s frame %u joint %s: rotation changed", name, f, p->name);
            rf_vec3 t = rf_animation_translation(a, f, j), t2 = rf_animation_translation(a2, f, j);
            assert_vec_near(t2, t.x, t.y, t.z, 1e-5 * (1 + rf_v3_len(t)));
        }
    }
    compare_motion(s, a, s2, a2, name);
    remove(out);
    free(text);
    rf_skeleton_free(s), rf_skeleton_free(s2);
    rf_animation_free(a), rf_animation_free(a2);
}

static void test_roundtrip_shared_files(void **state)
{
    (void)state;
    NEED_DATA(dir);
    char *tmp = temp_dir();
    DIR *d = opendir(dir);
    struct dirent *e;
    int count = 0;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n > 4 && strcmp(e->d_name + n - 4, ".bvh") == 0) {
            roundtrip_file(dir, e->d_name, tmp);
            count++;
        }
    }
    closedir(d);
    rmdir(tmp);
    free(tmp);
    assert_true(count >= 7);
}

/* The numbers of the line after "Frame Time:" (frame 1), read with strtod. */
static int first_frame_values(const char *text, double *v, int max)
{
    const char *p = strstr(text, "Frame Time:");
    assert_non_null(p);
    p = strchr(p, '\n') + 1;
    size_t len = strcspn(p, "\n");
    char *line = strndup(p, len), *q = line, *end;
    int n = 0;
    while (n < max && (v[n] = strtod(q, &end), end != q))
        n++, q = end;
    free(line);
    return n;
}

/* Values of cmu_01_01.bvh read by hand: an OFFSET, and frame 1's rotation of LeftUpLeg. */
static void test_cmu_values(void **state)
{
    (void)state;
    NEED_DATA(dir);
    char path[4200];
    size_t size;
    snprintf(path, sizeof path, "%s/cmu_01_01.bvh", dir);
    char *text = read_all(path, &size);
    /* the OFFSET line after "JOINT LeftUpLeg", and how many channels come before that joint */
    const char *j = strstr(text, "JOINT LeftUpLeg");
    assert_non_null(j);
    double off[3];
    assert_int_equal(sscanf(strstr(j, "OFFSET"), "OFFSET %lf %lf %lf", &off[0], &off[1], &off[2]),
                     3);
    int before = 0;
    unsigned n;
    for (const char *p = strstr(text, "CHANNELS"); p && p < j; p = strstr(p + 1, "CHANNELS"))
        if (sscanf(p, "CHANNELS %u", &n) == 1)
            before += (int)n;
    assert_int_equal(sscanf(strstr(j, "CHANNELS"), "CHANNELS %u", &n), 1);
    assert_int_equal(n, 3);
    assert_non_null(strstr(j, "CHANNELS 3 Zrotation Yrotation Xrotation"));
    double v[200];
    assert_true(first_frame_values(text, v, 200) > before + 3);

    rf_skeleton *s;
    rf_animation *a;
    assert_true(rf_bvh_read_file(path, NULL, &s, &a, err, sizeof err));
    int32_t k = rf_skeleton_find(s, "LeftUpLeg");
    assert_true(k >= 0);
    assert_vec_near(s->joints[k].rest.t, off[0], off[1], off[2], 0);
    double m[3][3], r[3][3];
    axis_matrix(2, v[before], m);
    axis_matrix(1, v[before + 1], r);
    mat_mul(m, r, m);
    axis_matrix(0, v[before + 2], r);
    mat_mul(m, r, m);
    assert_quat_matrix(rf_animation_rotation(a, 0, (uint32_t)k), m, 1e-6);
    /* Hips' position channels are its translation */
    assert_vec_near(rf_animation_translation(a, 0, 0), v[0], v[1], v[2], 1e-5 * (1 + fabs(v[0])));
    rf_skeleton_free(s);
    rf_animation_free(a);
    free(text);
}

/* CRLF and tab versions of a real file read identically. */
static void test_real_file_variants(void **state)
{
    (void)state;
    NEED_DATA(dir);
    char path[4200];
    size_t size;
    snprintf(path, sizeof path, "%s/dme_example_cmu.bvh", dir);
    char *text = read_all(path, &size);
    char *lf = replaced(text, "\r\n", "\n", 0);
    char *crlf = replaced(lf, "\n", "\r\n", 0);
    char *tabs = replaced(lf, " ", "\t", 0);
    rf_skeleton *s[3];
    rf_animation *a[3];
    const char *v[3] = {lf, crlf, tabs};
    for (int i = 0; i < 3; i++)
        assert_true(
            rf_bvh_read_memory(v[i], strlen(v[i]), "x.bvh", NULL, &s[i], &a[i], err, sizeof err));
    size_t n = (size_t)a[0]->frame_count * a[0]->joint_count;
    for (int i = 1; i < 3; i++) {
        assert_int_equal(a[i]->frame_count, a[0]->frame_count);
        assert_memory_equal(a[i]->rotations, a[0]->rotations, n * 4 * sizeof(float));
        assert_memory_equal(a[i]->translations, a[0]->translations, n * 3 * sizeof(float));
    }
    for (int i = 0; i < 3; i++)
        rf_skeleton_free(s[i]), rf_animation_free(a[i]);
    free(text), free(lf), free(crlf), free(tabs);
}

/* The extra motion line of boxing_toes.bvh (3070 lines for 'Frames: 3069') is reported. */
static void test_boxing_extra_line(void **state)
{
    (void)state;
    NEED_DATA(dir);
    char path[4200];
    size_t size;
    snprintf(path, sizeof path, "%s/boxing_toes.bvh", dir);
    char *text = read_all(path, &size);
    int line = 1, time_line = 0;
    uint32_t frames = 0, j, six;
    for (const char *p = text; *p; p++)
        if (*p == '\n') {
            line++;
            if (strncmp(p + 1, "Frame Time", 10) == 0)
                time_line = line;
        }
    count_in_text(text, &j, &frames, &six);
    /* `line` now counts the lines (plus one after the final newline) */
    int data_lines = line - 1 - time_line;
    if (data_lines <= (int)frames) {
        print_message("  skipped: this copy of boxing_toes.bvh has no extra motion line\n");
        free(text);
        skip();
    }
    char expect[128];
    snprintf(expect, sizeof expect, "boxing_toes.bvh:%d: %d line", time_line + (int)frames + 1,
             data_lines - (int)frames);
    rf_bvh_read_opts opts = {.warning = on_warning};
    rf_skeleton *s;
    rf_animation *a;
    warnings = 0;
    assert_true(rf_bvh_read_file(path, &opts, &s, &a, err, sizeof err));
    assert_int_equal(warnings, 1);
    assert_non_null(strstr(last_warning, expect));
    rf_skeleton_free(s);
    rf_animation_free(a);
    free(text);
}

/* ---- writing ---- */

/* Random unit quaternion from a seeded generator. */
static rf_quat random_quat(void)
{
    double v[4], l = 0;
    for (int i = 0; i < 4; i++) {
        v[i] = (double)rand() / RAND_MAX * 2 - 1;
        l += v[i] * v[i];
    }
    l = sqrt(l);
    return rf_quat_make(v[0] / l, v[1] / l, v[2] / l, v[3] / l);
}

/* Euler angles back to the same rotation for every order, gimbal lock included. */
static void test_euler_roundtrip(void **state)
{
    (void)state;
    srand(11);
    for (int o = 0; o < 6; o++) {
        int ax[3];
        rf_bvh_order_axes((rf_bvh_order)o, ax);
        for (int i = 0; i < 3000; i++) {
            rf_quat q;
            if (i < 40) { /* exactly at and next to gimbal lock: middle angle +-90 degrees */
                double mid = (i % 2 ? 90 : -90) + (i % 4 < 2 ? 0 : 1e-7 * (i - 20));
                double deg[3] = {(double)(i * 37 % 360) - 180, mid, (double)(i * 53 % 360)};
                q = rf_bvh_euler_to_quat(ax, deg, 3);
            } else {
                q = random_quat();
            }
            double ang[3];
            rf_bvh_quat_to_euler(q, (rf_bvh_order)o, ang);
            rf_quat b = rf_quat_identity();
            for (int k = 0; k < 3; k++) /* composed with the SDK's axis-angle, not ours */
                b = rf_quat_mul(b,
                                rf_quat_from_axis_angle(rf_v3(ax[k] == 0, ax[k] == 1, ax[k] == 2),
                                                        ang[k] * RF_PI / 180));
            if (rot_diff(q, b) > 1e-12)
                fail_msg("order %d case %d: off by %g rad", o, i, rot_diff(q, b));
        }
    }
}

/* A hand-built rig with rotated rest joints (as glTF and Assimp give): after a write and read the
 * rest rotations are identity, the rest pose and every frame's joint positions are the same. */
static void build_rotated_rig(rf_skeleton **sp, rf_animation **ap, uint32_t frames)
{
    /*   0 root
     *   1  spine (rest turned 90 degrees about X, so its children's offsets are turned)
     *   2   head  (rest turned -30 about Z), end site
     *   3   arm   (rest turned 45 about Y, translation animated)
     *   4  leg    (identity rest) */
    static const int32_t parent[5] = {-1, 0, 1, 1, 0};
    static const char *const names[5] = {"root", "spine", "head", "arm", "leg"};
    const rf_vec3 t[5] = {rf_v3(0, 1, 0), rf_v3(0, 0.2, 0.1), rf_v3(0, 0, 0.5), rf_v3(0.3, 0, 0.4),
                          rf_v3(-0.2, -0.1, 0)};
    const rf_quat r[5] = {rf_quat_from_axis_angle(rf_v3(0, 1, 0), 0.4),
                          rf_quat_from_axis_angle(rf_v3(1, 0, 0), RF_PI / 2),
                          rf_quat_from_axis_angle(rf_v3(0, 0, 1), -RF_PI / 6),
                          rf_quat_from_axis_angle(rf_v3(0, 1, 0), RF_PI / 4), rf_quat_identity()};
    rf_skeleton *s = rf_skeleton_new(5);
    rf_animation *a = rf_animation_new(5, frames, 60);
    for (uint32_t j = 0; j < 5; j++) {
        s->joints[j].name = strdup(names[j]);
        s->joints[j].parent = parent[j];
        s->joints[j].rest.t = t[j];
        s->joints[j].rest.r = r[j];
        a->channels[j] = RF_CHANNEL_ROTATION;
    }
    s->joints[2].flags = RF_JOINT_HAS_END_SITE;
    s->joints[2].end_site = rf_v3(0.05, 0.2, 0);
    a->channels[0] |= RF_CHANNEL_TRANSLATION;
    a->channels[3] |= RF_CHANNEL_TRANSLATION;
    srand(3);
    for (uint32_t f = 0; f < frames; f++)
        for (uint32_t j = 0; j < 5; j++) {
            rf_quat q = f == 0 ? r[j] : rf_quat_mul(r[j], random_quat());
            rf_vec3 tr = t[j];
            if (j == 0 || j == 3)
                tr = rf_v3_add(tr, rf_v3(0.01 * f, -0.02 * f, 0.03 * (f % 3)));
            rf_animation_set_rotation(a, f, j, q);
            rf_animation_set_translation(a, f, j, tr);
        }
    *sp = s, *ap = a;
}

static void test_write_rotated_rest(void **state)
{
    (void)state;
    rf_skeleton *s, *s2;
    rf_animation *a, *a2;
    const uint32_t frames = 40;
    build_rotated_rig(&s, &a, frames);
    char *dir = temp_dir(), path[4200];
    snprintf(path, sizeof path, "%s/rig.bvh", dir);
    for (int o = 0; o < 6; o++) {
        rf_bvh_write_opts opts = {0};
        opts.order = (rf_bvh_order)o;
        assert_true(rf_bvh_write_file(path, "rig.bvh", s, a, &opts, err, sizeof err));
        if (!rf_bvh_read_file(path, NULL, &s2, &a2, err, sizeof err))
            fail_msg("%s", err);
        assert_int_equal(s2->joint_count, 5);
        /* rest: identity rotations, same world positions */
        rf_xform w[5], w2[5];
        rf_skeleton_world_rest(s, w);
        rf_skeleton_world_rest(s2, w2);
        for (uint32_t j = 0; j < 5; j++) {
            assert_string_equal(s2->joints[j].name, s->joints[j].name);
            assert_quat_near(s2->joints[j].rest.r, 0, 0, 0, 1, 1e-12);
            assert_vec_near(w2[j].t, w[j].t.x, w[j].t.y, w[j].t.z, 1e-6);
        }
        assert_true(s2->joints[2].flags & RF_JOINT_HAS_END_SITE);
        rf_vec3 e = rf_xform_point(w[2], s->joints[2].end_site);
        rf_vec3 e2 = rf_xform_point(w2[2], s2->joints[2].end_site);
        assert_vec_near(e2, e.x, e.y, e.z, 1e-6);
        /* every frame: the same world joint positions, and the same rotation relative to rest */
        for (uint32_t f = 0; f < frames; f++) {
            world_pose(s, a, f, w);
            world_pose(s2, a2, f, w2);
            rf_xform rw[5], rw2[5];
            rf_skeleton_world_rest(s, rw);
            rf_skeleton_world_rest(s2, rw2);
            for (uint32_t j = 0; j < 5; j++) {
                assert_vec_near(w2[j].t, w[j].t.x, w[j].t.y, w[j].t.z, 1e-5);
                rf_quat rel = rf_quat_mul(w[j].r, rf_quat_conj(rw[j].r));
                rf_quat rel2 = rf_quat_mul(w2[j].r, rf_quat_conj(rw2[j].r));
                assert_true(rot_diff(rel, rel2) < 1e-5);
            }
        }
        /* frame 0 is the rest pose: all zero rotations in the file */
        for (uint32_t j = 0; j < 5; j++)
            assert_quat_near(rf_animation_rotation(a2, 0, j), 0, 0, 0, 1, 1e-6);
        rf_skeleton_free(s2);
        rf_animation_free(a2);
    }
    remove(path);
    rmdir(dir);
    free(dir);
    rf_skeleton_free(s);
    rf_animation_free(a);
}

/* Names BVH cannot hold are made unique and space-free; no animation writes the rest pose. */
/* A position at the range's limit (1e30) is held as the float nearest it, 1.00000002e+30 when
 * written: the written file reads back (the BVH fuzzer found it refused as out of range), and a
 * value past the limit is still refused. */
static void test_limit_roundtrip(void **state)
{
    (void)state;
    static const char head[] = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition "
                               "Yposition Zposition Zrotation Xrotation Yrotation\n End Site\n {\n"
                               "  OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n";
    char text[512];
    rf_skeleton *s = NULL, *s2 = NULL;
    rf_animation *a = NULL, *a2 = NULL;
    snprintf(text, sizeof text, "%s1e30 -1e30 0 0 0 0\n", head);
    assert_true(parse(text, &s, &a));
    char *out = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&out, &len);
    assert_non_null(f);
    assert_true(rf_bvh_write_stream(f, "limit.bvh", s, a, NULL, err, sizeof err));
    assert_int_equal(fclose(f), 0);
    assert_non_null(strstr(out, "1.00000002e+30"));
    assert_true(rf_bvh_read_memory(out, len, "limit.bvh", NULL, &s2, &a2, err, sizeof err));
    assert_int_equal(a2->frame_count, 1);
    free(out);
    rf_skeleton_free(s), rf_skeleton_free(s2);
    rf_animation_free(a), rf_animation_free(a2);
    snprintf(text, sizeof text, "%s1.0000001e30 0 0 0 0 0\n", head);
    expect_error(text, 14, "out of range");
}

static void test_write_names_and_rest_only(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(4), *s2;
    rf_animation *a2;
    const char *names[4] = {"left arm", "left_arm", "", NULL};
    for (uint32_t j = 0; j < 4; j++) {
        s->joints[j].name = names[j] ? strdup(names[j]) : NULL;
        s->joints[j].parent = (int32_t)j - 1;
        s->joints[j].rest.t = rf_v3(0, j, 0);
    }
    char *dir = temp_dir(), path[4200];
    snprintf(path, sizeof path, "%s/names.bvh", dir);
    assert_true(rf_bvh_write_file(path, NULL, s, NULL, NULL, err, sizeof err));
    assert_true(rf_bvh_read_file(path, NULL, &s2, &a2, err, sizeof err));
    assert_int_equal(s2->joint_count, 4);
    assert_int_equal(a2->frame_count, 1);
    for (uint32_t j = 0; j < 4; j++) {
        assert_null(strpbrk(s2->joints[j].name, " \t"));
        assert_true(s2->joints[j].name[0] != '\0');
        for (uint32_t k = 0; k < j; k++)
            assert_string_not_equal(s2->joints[j].name, s2->joints[k].name);
        assert_vec_near(s2->joints[j].rest.t, 0, j, 0, 0);
    }
    assert_string_equal(s2->joints[0].name, "left_arm");
    rf_skeleton_free(s2);
    rf_animation_free(a2);

    /* a mismatched animation is refused, naming the output and what was expected */
    rf_animation *wrong = rf_animation_new(3, 1, 30);
    assert_false(rf_bvh_write_file(path, "out.bvh", s, wrong, NULL, err, sizeof err));
    assert_non_null(strstr(err, "out.bvh: the animation has 3 joints, the skeleton 4"));
    assert_int_equal(access(path, F_OK), -1); /* no partial file left */
    rf_animation_free(wrong);

    /* values that are not finite are refused, naming the joint */
    rf_animation *nan = rf_animation_new(4, 2, 30);
    rf_animation_set_rotation(nan, 1, 2, rf_quat_make(NAN, 0, 0, 1));
    assert_false(rf_bvh_write_file(path, "out.bvh", s, nan, NULL, err, sizeof err));
    assert_non_null(strstr(err, "out.bvh: frame 2 of joint 'joint2' is not finite"));
    rf_animation_free(nan);
    s->joints[1].rest.t.y = INFINITY;
    assert_false(rf_bvh_write_file(path, "out.bvh", s, NULL, NULL, err, sizeof err));
    assert_non_null(
        strstr(err, "out.bvh: joint 1 ('left_arm') has a rest pose that is not finite"));
    assert_int_equal(access(path, F_OK), -1);
    /* the name comes from a file: a control or a C1 byte in it reaches the message escaped */
    char *keep = s->joints[1].name;
    s->joints[1].name = strdup("arm\x1b]0;x\x07\x9b");
    assert_false(rf_bvh_write_file(path, "out.bvh", s, NULL, NULL, err, sizeof err));
    assert_non_null(strstr(err, "joint 1 ('arm\\x1b]0;x\\x07\\x9b') has a rest pose"));
    free(s->joints[1].name), s->joints[1].name = keep;
    s->joints[1].rest.t.y = 0;
    free(s->joints[2].name); /* a C1 byte, kept by the writer's names (they drop spaces) */
    s->joints[2].name = strdup("\x9bleg");
    nan = rf_animation_new(4, 2, 30);
    rf_animation_set_rotation(nan, 1, 2, rf_quat_make(NAN, 0, 0, 1));
    assert_false(rf_bvh_write_file(path, "out.bvh", s, nan, NULL, err, sizeof err));
    assert_non_null(strstr(err, "frame 2 of joint '\\x9bleg' is not finite"));
    rf_animation_free(nan);
    assert_int_equal(access(path, F_OK), -1);
    /* a parent after its child: both named, escaped */
    s->joints[2].parent = 3;
    assert_false(rf_bvh_write_file(path, "out.bvh", s, NULL, NULL, err, sizeof err));
    assert_non_null(strstr(err, "out.bvh: joint 2 '\\x9bleg' has parent 3 '#3': expected parents "
                                "before children"));
    assert_int_equal(access(path, F_OK), -1);
    s->joints[2].parent = 1;
    rmdir(dir);
    free(dir);
    rf_skeleton_free(s);
}

/* ---- the plugin, through a stand-in host ---- */

typedef struct fake_node {
    const char *path, *target;
    const void *skeleton, *animation;
    void *out_skeleton, *out_animation;
    rf_destroy_fn free_skeleton, free_animation;
    char error[2048];
} fake_node;

static void fake_log(rf_node *node, rf_log_level level, const char *fmt, ...)
{
    (void)node, (void)level, (void)fmt;
}
static void fake_error(rf_node *node, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(((fake_node *)(void *)node)->error, 2048, fmt, ap);
    va_end(ap);
}
static void fake_progress(rf_node *node, double f)
{
    (void)node, (void)f;
}
static bool fake_cancelled(rf_node *node)
{
    return (void)node, false;
}
static const char *fake_id(rf_node *node)
{
    return (void)node, "n";
}
static bool fake_bool(rf_node *node, const char *name)
{
    return (void)node, (void)name, false;
}
static int64_t fake_int(rf_node *node, const char *name)
{
    (void)node;
    return strcmp(name, "precision") == 0 ? 9 : 0;
}
static double fake_float(rf_node *node, const char *name)
{
    return (void)node, (void)name, 0;
}
static const char *fake_string(rf_node *node, const char *name)
{
    fake_node *n = (fake_node *)(void *)node;
    return strcmp(name, "path") == 0 ? n->path : strcmp(name, "rotation_order") == 0 ? "ZXY" : "";
}
static const char *fake_target(rf_node *node, const char *name)
{
    (void)name;
    return ((fake_node *)(void *)node)->target;
}
static uint32_t fake_count(rf_node *node, const char *port)
{
    fake_node *n = (fake_node *)(void *)node;
    return strcmp(port, "skeleton") == 0 ? n->skeleton != NULL : n->animation != NULL;
}
static const void *fake_input(rf_node *node, const char *port, uint32_t i)
{
    fake_node *n = (fake_node *)(void *)node;
    (void)i;
    return strcmp(port, "skeleton") == 0 ? n->skeleton : n->animation;
}
static bool fake_set_output(rf_node *node, const char *port, void *data, rf_destroy_fn destroy)
{
    fake_node *n = (fake_node *)(void *)node;
    if (strcmp(port, "skeleton") == 0)
        n->out_skeleton = data, n->free_skeleton = destroy;
    else
        n->out_animation = data, n->free_animation = destroy;
    return true;
}

static const rf_host fake_host = {.size = sizeof(rf_host),
                                  .abi = RF_ABI_VERSION_INIT,
                                  .log = fake_log,
                                  .error = fake_error,
                                  .progress = fake_progress,
                                  .cancelled = fake_cancelled,
                                  .node_id = fake_id,
                                  .param_bool = fake_bool,
                                  .param_int = fake_int,
                                  .param_float = fake_float,
                                  .param_string = fake_string,
                                  .param_output_target = fake_target,
                                  .input_count = fake_count,
                                  .input = fake_input,
                                  .set_output = fake_set_output};

static const rf_node_desc *find_node(const rf_plugin_entry *e, const char *type)
{
    for (uint32_t i = 0; i < e->node_count; i++)
        if (strcmp(e->nodes[i]->type, type) == 0)
            return e->nodes[i];
    return NULL;
}

static void check_docs(const rf_node_desc *d)
{
    assert_true(d->doc && *d->doc);
    for (uint32_t i = 0; i < d->input_count; i++)
        assert_true(d->inputs[i].doc && *d->inputs[i].doc);
    for (uint32_t i = 0; i < d->output_count; i++)
        assert_true(d->outputs[i].doc && *d->outputs[i].doc);
    for (uint32_t i = 0; i < d->param_count; i++)
        assert_true(d->params[i].doc && *d->params[i].doc);
}

static void test_plugin_nodes(void **state)
{
    (void)state;
    const char *dir = getenv("RIGFLOW_PLUGIN_PATH");
    if (!dir) {
        print_message("  skipped: RIGFLOW_PLUGIN_PATH is not set (run through make check)\n");
        skip();
    }
    char path[4200];
    snprintf(path, sizeof path, "%s/bvh", dir);
    assert_int_equal(lt_dlinit(), 0);
    lt_dlhandle h = lt_dlopenext(path);
    if (!h)
        fail_msg("cannot load %s: %s", path, lt_dlerror());
    const rf_plugin_entry *e = lt_dlsym(h, RF_PLUGIN_ENTRY_SYMBOL);
    assert_non_null(e);
    assert_int_equal(e->abi.major, RF_ABI_VERSION_MAJOR);
    const rf_node_desc *imp = find_node(e, "bvh.import"), *exp = find_node(e, "bvh.export");
    assert_non_null(imp);
    assert_non_null(exp);
    assert_int_equal(imp->kind, RF_KIND_IMPORTER);
    assert_int_equal(exp->kind, RF_KIND_EXPORTER);
    check_docs(imp);
    check_docs(exp);
    assert_string_equal(imp->outputs[0].type, RF_TYPE_SKELETON);
    assert_string_equal(imp->outputs[1].type, RF_TYPE_ANIMATION);
    assert_string_equal(imp->params[0].name, "path");
    assert_int_equal(imp->params[0].type, RF_PARAM_INPUT_PATH);
    assert_true(imp->params[0].flags & RF_PARAM_REQUIRED);
    assert_int_equal(exp->params[0].type, RF_PARAM_OUTPUT_PATH);

    /* the self-test both nodes offer */
    const rf_selftest *st = imp->get_extension(RF_SELFTEST_EXTENSION);
    assert_non_null(st);
    assert_true(st->run(&fake_host, err, sizeof err));

    /* import the sample from a file, export it, import that again */
    char *tmp = temp_dir(), in[4200], out[4200];
    snprintf(in, sizeof in, "%s/in.bvh", tmp);
    snprintf(out, sizeof out, "%s/out.bvh", tmp);
    FILE *f = fopen(in, "w");
    fputs(sample, f);
    fclose(f);
    fake_node n1 = {.path = in};
    assert_true(imp->process(NULL, &fake_host, (rf_node *)(void *)&n1));
    assert_non_null(n1.out_skeleton);
    assert_non_null(n1.out_animation);
    fake_node n2 = {.path = out,
                    .target = "final.bvh",
                    .skeleton = n1.out_skeleton,
                    .animation = n1.out_animation};
    assert_true(exp->process(NULL, &fake_host, (rf_node *)(void *)&n2));
    fake_node n3 = {.path = out};
    assert_true(imp->process(NULL, &fake_host, (rf_node *)(void *)&n3));
    compare_motion(n1.out_skeleton, n1.out_animation, n3.out_skeleton, n3.out_animation, "plugin");
    /* the rotation_order param (ZXY from the fake host) shapes the channels */
    size_t size;
    char *written = read_all(out, &size);
    assert_non_null(strstr(written, "CHANNELS 3 Zrotation Xrotation Yrotation"));
    free(written);

    /* errors name the file */
    fake_node n4 = {.path = "/nonexistent/x.bvh"};
    assert_false(imp->process(NULL, &fake_host, (rf_node *)(void *)&n4));
    assert_non_null(strstr(n4.error, "/nonexistent/x.bvh: cannot open"));
    f = fopen(in, "w");
    fputs("HIERARCHY\nROOT\n", f);
    fclose(f);
    fake_node n5 = {.path = in};
    assert_false(imp->process(NULL, &fake_host, (rf_node *)(void *)&n5));
    assert_non_null(strstr(n5.error, "in.bvh:2: expected a joint name after ROOT"));

    n1.free_skeleton(n1.out_skeleton), n1.free_animation(n1.out_animation);
    n3.free_skeleton(n3.out_skeleton), n3.free_animation(n3.out_animation);
    remove(in), remove(out), rmdir(tmp);
    free(tmp);
    lt_dlclose(h);
    lt_dlexit();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_number_exact),
        cmocka_unit_test(test_number_locale),
        cmocka_unit_test(test_number_data),
#if BVH_TOKEN_AVX2
        cmocka_unit_test(test_line_random),
        cmocka_unit_test(test_line_data),
#endif
        cmocka_unit_test(test_number_rejects),
        cmocka_unit_test(test_sincos),
        cmocka_unit_test(test_format_number),
        cmocka_unit_test(test_sample_values),
        cmocka_unit_test(test_channel_orders),
        cmocka_unit_test(test_six_channels),
        cmocka_unit_test(test_line_endings_and_tabs),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_frames_bound),
        cmocka_unit_test(test_deep_nesting),
        cmocka_unit_test(test_trailing_and_cancel),
        cmocka_unit_test(test_threads),
        cmocka_unit_test(test_roundtrip_shared_files),
        cmocka_unit_test(test_cmu_values),
        cmocka_unit_test(test_real_file_variants),
        cmocka_unit_test(test_boxing_extra_line),
        cmocka_unit_test(test_euler_roundtrip),
        cmocka_unit_test(test_write_rotated_rest),
        cmocka_unit_test(test_limit_roundtrip),
        cmocka_unit_test(test_write_names_and_rest_only),
        cmocka_unit_test(test_plugin_nodes),
    };
    return cmocka_run_group_tests_name("bvh", tests, NULL, NULL);
}

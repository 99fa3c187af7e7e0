/* Retargeting benchmark and peer comparison, run by bench/retarget/run.sh.
 *
 *   bench_retarget speed [--reps N] [--min-ms MS] FILE.bvh...
 *       joint-frames per second of libretarget (no contact pass) onto the same kind of target
 *       the three.js bench builds: a copy of the source skeleton with every offset scaled by
 *       0.8-1.2 and every rest rotation jittered by up to 0.1 rad per Euler axis (seeded LCG 7),
 *       mapped joint for joint. Times the clip alone and with the per-clip set-up.
 *   bench_retarget export SOURCE.bvh TARGET MAP OUT.json
 *       the target skeleton, the names map and the hip for bench/retarget/three_retarget.mjs.
 *   bench_retarget measure SOURCE.bvh TARGET MAP [THREE.bin]
 *       direction fidelity, foot skate and ground of our clip without and with the contact pass
 *       (two-bone solver), and of three.js retargetClip's clips when given (THREE.bin with its
 *       defaults, THREE.bin.scaled with its hip motion scaled by our leg ratio), all measured by
 *       rf_retarget_measure.
 *
 * Every figure is printed as a RESULT {json} line (as the peers' scripts do).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "rigflow/aimport.h"
#include "rigflow/bvh.h"
#include "retarget.h"
#include "rt-maps.h"
#include "twobone.h"

static double rb_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int rb_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double rb_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, rb_cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Loads a BVH natively or anything else through Assimp. */
static bool rb_load(const char *path, rf_skeleton **s, rf_animation **a)
{
    char err[1024];
    const char *ext = strrchr(path, '.');
    if (ext && strcasecmp(ext, ".bvh") == 0) {
        if (rf_bvh_read_file(path, NULL, s, a, err, sizeof err))
            return true;
    } else {
        rf_ai_result r;
        if (rf_ai_import(path, NULL, &r, NULL, NULL, err, sizeof err)) {
            *s = r.skeleton, *a = r.animation;
            r.skeleton = NULL, r.animation = NULL;
            rf_ai_result_clear(&r);
            return true;
        }
    }
    fprintf(stderr, "bench_retarget: %s\n", err);
    return false;
}

/* ---- speed ---- */

static double rb_lcg(uint32_t *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return *seed / 4294967296.0;
}

/* The three.js bench's target: offsets scaled by 0.8-1.2, rests turned by Euler angles of up to
 * 0.1 rad (XYZ order, as three's default). */
static rf_skeleton *rb_jittered_copy(const rf_skeleton *s)
{
    rf_skeleton *t = rf_skeleton_new(s->joint_count);
    uint32_t seed = 7;
    for (uint32_t j = 0; t && j < s->joint_count; j++) {
        t->joints[j].parent = s->joints[j].parent;
        t->joints[j].flags = s->joints[j].flags;
        t->joints[j].end_site = s->joints[j].end_site;
        t->joints[j].rest.t = rf_v3_scale(s->joints[j].rest.t, 0.8 + 0.4 * rb_lcg(&seed));
        double ex = 0.2 * (rb_lcg(&seed) - 0.5), ey = 0.2 * (rb_lcg(&seed) - 0.5);
        double ez = 0.2 * (rb_lcg(&seed) - 0.5);
        t->joints[j].rest.r = rf_quat_mul(rf_quat_mul(rf_quat_from_axis_angle(rf_v3(1, 0, 0), ex),
                                                      rf_quat_from_axis_angle(rf_v3(0, 1, 0), ey)),
                                          rf_quat_from_axis_angle(rf_v3(0, 0, 1), ez));
    }
    return t;
}

static rf_mapping *rb_same(uint32_t n)
{
    rf_mapping *m = rf_mapping_new(n, 1);
    for (uint32_t j = 0; m && j < n; j++) {
        m->entries[j].inputs = calloc(1, sizeof *m->entries[j].inputs);
        m->entries[j].input_count = 1;
        m->entries[j].inputs[0] = (rf_map_input){0, j, 1, 0, 0};
    }
    return m;
}

/* Times `what` (0: the clip on a plan made once, 1: set-up and clip) until min_ms, reps
 * times; the median milliseconds per call. */
static double rb_time(const rf_rt_source *src, const rf_skeleton *t, const rf_mapping *m, int what,
                      int reps, double min_ms)
{
    char err[512];
    double ms[64];
    rf_retarget *plan = rf_retarget_new(src, 1, t, m, NULL, err, sizeof err);
    for (int r = 0; r < reps && r < 64; r++) {
        int k = 0;
        double t0 = rb_now(), el;
        do {
            rf_retarget *rt = what ? rf_retarget_new(src, 1, t, m, NULL, err, sizeof err) : plan;
            rf_animation_free(rf_retarget_clip(rt, NULL, NULL, err, sizeof err));
            if (what)
                rf_retarget_free(rt);
            k++;
            el = (rb_now() - t0) * 1e3;
        } while (el < min_ms);
        ms[r] = el / k;
    }
    rf_retarget_free(plan);
    return rb_median(ms, reps < 64 ? reps : 64);
}

static int rb_speed(int argc, char **argv)
{
    int reps = 5;
    double min_ms = 300;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc) {
            reps = atoi(argv[++i]);
            continue;
        }
        if (strcmp(argv[i], "--min-ms") == 0 && i + 1 < argc) {
            min_ms = atof(argv[++i]);
            continue;
        }
        rf_skeleton *s;
        rf_animation *a;
        if (!rb_load(argv[i], &s, &a))
            return 1;
        rf_skeleton *t = rb_jittered_copy(s);
        rf_mapping *m = rb_same(s->joint_count);
        rf_rt_source src = {s, a};
        double clip = rb_time(&src, t, m, 0, reps, min_ms);
        double all = rb_time(&src, t, m, 1, reps, min_ms);
        double jf = (double)a->frame_count * s->joint_count;
        printf("%s: %u frames x %u joints: clip %.3f ms -> %.3g joint-frames/s; with set-up "
               "%.3f ms -> %.3g\n",
               argv[i], a->frame_count, s->joint_count, clip, jf / clip * 1e3, all, jf / all * 1e3);
        printf("RESULT {\"file\": \"%s\", \"metric\": \"retarget\", \"ms\": %.6g, \"jfps\": %.6g, "
               "\"frames\": %u, \"joints\": %u}\n",
               argv[i], clip, jf / clip * 1e3, a->frame_count, s->joint_count);
        printf("RESULT {\"file\": \"%s\", \"metric\": \"retarget+setup\", \"ms\": %.6g, \"jfps\": "
               "%.6g, \"frames\": %u, \"joints\": %u}\n",
               argv[i], all, jf / all * 1e3, a->frame_count, s->joint_count);
        fflush(stdout);
        rf_mapping_free(m), rf_skeleton_free(t), rf_skeleton_free(s), rf_animation_free(a);
    }
    return 0;
}

/* ---- the three.js side ---- */

static rf_animation *rb_read_three(const char *path, uint32_t joints);

static void rb_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; s && *s; s++)
        if (*s == '"' || *s == '\\')
            fprintf(f, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(f, "\\u%04x", *s);
        else
            fputc(*s, f);
    fputc('"', f);
}

/* The target for three.js: joints in our order with their rest transforms, the names map
 * (target to source) and the source joint of the top mapped target joint (three's "hip"). */
static int rb_export(int argc, char **argv)
{
    rf_skeleton *s, *t;
    rf_animation *a, *ta;
    char err[512] = "";
    if (argc != 4 || !rb_load(argv[0], &s, &a) || !rb_load(argv[1], &t, &ta))
        return 1;
    rf_mapping *m = rt_map_read(argv[2], t, s, err, sizeof err);
    FILE *f = m ? fopen(argv[3], "w") : NULL;
    if (!f) {
        fprintf(stderr, "bench_retarget: %s\n", m ? argv[3] : err);
        return 1;
    }
    fprintf(f, "{\"joints\": [");
    const char *hip = NULL;
    for (uint32_t j = 0; j < t->joint_count; j++) {
        const rf_joint *jt = &t->joints[j];
        fprintf(f, "%s\n {\"name\": ", j ? "," : "");
        rb_json_string(f, jt->name);
        fprintf(f,
                ", \"parent\": %d, \"t\": [%.9g, %.9g, %.9g], \"r\": [%.9g, %.9g, %.9g, %.9g], "
                "\"s\": [%.9g, %.9g, %.9g]",
                jt->parent, jt->rest.t.x, jt->rest.t.y, jt->rest.t.z, jt->rest.r.x, jt->rest.r.y,
                jt->rest.r.z, jt->rest.r.w, jt->rest.s.x, jt->rest.s.y, jt->rest.s.z);
        if (m->entries[j].input_count) {
            const char *src = s->joints[m->entries[j].inputs[0].joint].name;
            fprintf(f, ", \"source\": ");
            rb_json_string(f, src);
            bool top = true;
            for (int32_t p = jt->parent; p >= 0 && top; p = t->joints[p].parent)
                top = m->entries[p].input_count == 0;
            if (top && !hip)
                hip = src;
        }
        fprintf(f, "}");
    }
    /* Our root scale (the legs' ratio), for a run of three.js with its hip scaled by it. */
    rf_rt_source src = {s, a};
    rf_retarget *rt = rf_retarget_new(&src, 1, t, m, NULL, err, sizeof err);
    rf_rt_info info = {0};
    if (rt)
        rf_retarget_info(rt, &info);
    rf_retarget_free(rt);
    fprintf(f, "],\n\"hip\": ");
    rb_json_string(f, hip ? hip : "");
    fprintf(f, ",\n\"scale\": %.9g}\n", info.root_scale > 0 ? info.root_scale : 1);
    fclose(f);
    rf_mapping_free(m), rf_skeleton_free(s), rf_skeleton_free(t);
    rf_animation_free(a), rf_animation_free(ta);
    return 0;
}

/* three_retarget.mjs's output: "RFT1", frames, joints (uint32), fps (double), then
 * frames x joints x (qx qy qz qw tx ty tz) floats, joints in our order. */
static rf_animation *rb_read_three(const char *path, uint32_t joints)
{
    FILE *f = fopen(path, "rb");
    char magic[4];
    uint32_t frames = 0, n = 0;
    double fps = 0;
    if (!f || fread(magic, 1, 4, f) != 4 || memcmp(magic, "RFT1", 4) != 0 ||
        fread(&frames, 4, 1, f) != 1 || fread(&n, 4, 1, f) != 1 || fread(&fps, 8, 1, f) != 1 ||
        n != joints) {
        fprintf(stderr, "bench_retarget: %s: not a three_retarget.mjs output for %u joints\n", path,
                joints);
        if (f)
            fclose(f);
        return NULL;
    }
    rf_animation *a = rf_animation_new(n, frames, fps);
    float v[7];
    for (uint32_t i = 0; a && i < frames * n; i++) {
        if (fread(v, sizeof v, 1, f) != 1) {
            rf_animation_free(a);
            a = NULL;
            break;
        }
        memcpy(a->rotations + (size_t)i * 4, v, 4 * sizeof *v);
        memcpy(a->translations + (size_t)i * 3, v + 4, 3 * sizeof *v);
    }
    fclose(f);
    return a;
}

static void rb_report(const char *pair, const char *tool, const rf_rt_report *r)
{
    printf("%-28s %-22s fidelity %7.3f deg (p95 %7.3f) over %2u bones; skate %.4f leg/s "
           "(source %.4f, %u contact frames); ground %.3f leg\n",
           pair, tool, r->fidelity_mean, r->fidelity_p95, r->fidelity_bones, r->skate_target,
           r->skate_source, r->contact_frames, r->ground_error);
    printf("RESULT {\"pair\": \"%s\", \"tool\": \"%s\", \"metric\": \"quality\", "
           "\"fidelity_mean\": %.6g, \"fidelity_p95\": %.6g, \"fidelity_max\": %.6g, \"bones\": "
           "%u, \"skate\": %.6g, \"skate_source\": %.6g, \"contact_frames\": %u, \"ground\": "
           "%.6g}\n",
           pair, tool, r->fidelity_mean, r->fidelity_p95, r->fidelity_max, r->fidelity_bones,
           r->skate_target, r->skate_source, r->contact_frames, r->ground_error);
}

static const char *rb_base(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static int rb_measure(int argc, char **argv)
{
    rf_skeleton *s, *t;
    rf_animation *a, *ta;
    char err[512] = "", pair[256];
    if ((argc != 3 && argc != 4) || !rb_load(argv[0], &s, &a) || !rb_load(argv[1], &t, &ta))
        return 1;
    snprintf(pair, sizeof pair, "%s>%s", rb_base(argv[0]), rb_base(argv[1]));
    rf_mapping *m = rt_map_read(argv[2], t, s, err, sizeof err);
    rf_rt_source src = {s, a};
    rf_retarget *rt = m ? rf_retarget_new(&src, 1, t, m, NULL, err, sizeof err) : NULL;
    rf_animation *out = rt ? rf_retarget_clip(rt, NULL, NULL, err, sizeof err) : NULL;
    rf_rt_report r;
    if (!out || !rf_retarget_measure(rt, out, rf_retarget_start_time(rt), &r, err, sizeof err)) {
        fprintf(stderr, "bench_retarget: %s\n", err);
        return 1;
    }
    rb_report(pair, "rigflow", &r);
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    rf_rt_contact_stats st;
    if (rf_retarget_contacts(rt, out, solver, &st, err, sizeof err) &&
        rf_retarget_measure(rt, out, rf_retarget_start_time(rt), &r, err, sizeof err))
        rb_report(pair, "rigflow+contact", &r);
    rf_ik_solver_free(solver);
    rf_animation *three = argc == 4 ? rb_read_three(argv[3], t->joint_count) : NULL;
    if (three && rf_retarget_measure(rt, three, 0, &r, err, sizeof err))
        rb_report(pair, "three.js retargetClip", &r);
    /* The same with its hip motion scaled by our leg ratio (three's `scale` option). */
    char scaled[4096];
    snprintf(scaled, sizeof scaled, "%s.scaled", argc == 4 ? argv[3] : "");
    rf_animation *three2 = argc == 4 ? rb_read_three(scaled, t->joint_count) : NULL;
    if (three2 && rf_retarget_measure(rt, three2, 0, &r, err, sizeof err))
        rb_report(pair, "three.js, hip scaled", &r);
    rf_animation_free(three2);
    fflush(stdout);
    rf_animation_free(three), rf_animation_free(out), rf_retarget_free(rt), rf_mapping_free(m);
    rf_skeleton_free(s), rf_skeleton_free(t), rf_animation_free(a), rf_animation_free(ta);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "speed") == 0)
        return rb_speed(argc - 2, argv + 2);
    if (argc >= 2 && strcmp(argv[1], "export") == 0)
        return rb_export(argc - 2, argv + 2);
    if (argc >= 2 && strcmp(argv[1], "measure") == 0)
        return rb_measure(argc - 2, argv + 2);
    fprintf(stderr, "usage: bench_retarget speed [--reps N] [--min-ms MS] FILE.bvh...\n"
                    "       bench_retarget export SOURCE.bvh TARGET MAP OUT.json\n"
                    "       bench_retarget measure SOURCE.bvh TARGET MAP [THREE.bin]\n");
    return 2;
}

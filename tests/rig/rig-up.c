/* rig-up [-s] FILE...: each mesh (its rig ignored) unmoved, tipped over both ways (a quarter
 * turn about x: +y to +z, as a Z-up scan reads, and back), laid on its side (a quarter turn
 * about z: +y to -x) and upside down, and the up the rigger finds from the body for each
 * (rf_rig_body_up), against the true one (the file's, turned); the time each took (processor
 * time, so other work on the machine does not count); last, how many were found right, kept
 * +y wrongly, or turned to a wrong axis. -s: also the unmoved body's standing margin along each
 * of the file's six axis directions (rf_rig_support). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <rigflow/aimport.h>

#include "rig-internal.h"

static void turn(const rf_mesh *m, float *out, rf_quat q)
{
    for (size_t i = 0; i < (size_t)m->vertex_count * 3; i += 3) {
        rf_vec3 p =
            rf_quat_rotate(q, rf_v3(m->positions[i], m->positions[i + 1], m->positions[i + 2]));
        out[i] = (float)p.x, out[i + 1] = (float)p.y, out[i + 2] = (float)p.z;
    }
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + t.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    int wrong = 0, found = 0, stayed = 0, runs = 0;
    double time = 0, slowest = 0;
    const double h = 3.14159265358979323846 / 2;
    const struct {
        const char *name;
        rf_vec3 axis;
        double angle;
    } turns[] = {{"unmoved", {1, 0, 0}, 0},
                 {"x90", {1, 0, 0}, h},
                 {"z90", {0, 0, 1}, h},
                 {"x-90", {1, 0, 0}, -h},
                 {"x180", {1, 0, 0}, 2 * h}};
    bool margins = argc > 1 && strcmp(argv[1], "-s") == 0;
    for (int i = 1 + margins; i < argc; i++) {
        rf_ai_options o = {.ignore_rig = true};
        rf_ai_result r;
        char err[1024];
        if (!rf_ai_import(argv[i], &o, &r, NULL, NULL, err, sizeof err)) {
            fprintf(stderr, "rig-up: %s\n", err);
            continue;
        }
        const char *base = strrchr(argv[i], '/') ? strrchr(argv[i], '/') + 1 : argv[i];
        rf_vec3 up0 = r.skeleton && rf_v3_len(r.skeleton->up) > 0 ? r.skeleton->up : rf_v3(0, 1, 0);
        static const rf_vec3 axes[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                        {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
        for (int a = 0; margins && a < 6; a++) {
            double s = NAN;
            if (!rf_rig_support(r.mesh, axes[a], &s))
                return 1;
            printf("%s%s %+.0f %+.0f %+.0f %6.3f%s", a ? "" : "margins ", a ? "" : base, axes[a].x,
                   axes[a].y, axes[a].z, s, a == 5 ? "\n" : ";");
        }
        float *pos = malloc((size_t)r.mesh->vertex_count * 3 * sizeof *pos);
        for (size_t t = 0; t < sizeof turns / sizeof *turns; t++) {
            rf_quat q = rf_quat_from_axis_angle(turns[t].axis, turns[t].angle);
            rf_mesh m = *r.mesh;
            turn(r.mesh, pos, q);
            m.positions = pos;
            rf_rig_up u;
            double t0 = now();
            if (!rf_rig_body_up(&m, NULL, &u)) {
                fprintf(stderr, "rig-up: %s: out of memory\n", argv[i]);
                return 1;
            }
            double dt = now() - t0;
            time += dt, slowest = fmax(slowest, dt), runs++;
            rf_vec3 truth = rf_quat_rotate(q, up0);
            rf_vec3 up = u.found ? u.axis : rf_v3(0, 1, 0);
            bool ok = rf_v3_dot(up, truth) > 0.99;
            wrong += !ok;
            found += u.found && ok, stayed += !u.found && !ok;

            printf("%-28s %-8s true %5.2f %5.2f %5.2f found %5.2f %5.2f %5.2f read %6.3f %6.3f "
                   "%6.3f conf %.3f %-8s support %6.3f %5.2f s %s %s\n",
                   base, turns[t].name, truth.x, truth.y, truth.z, up.x, up.y, up.z, u.read.x,
                   u.read.y, u.read.z, u.confidence, u.source, u.support, dt,
                   u.found ? "found" : "assumed", ok ? "ok" : "WRONG");
        }
        free(pos);
        rf_ai_result_clear(&r);
    }
    printf("wrong: %d\n", wrong);
    printf("runs %d: found right %d, kept +y wrongly %d, turned to a wrong axis %d; "
           "time mean %.2f s, slowest %.2f s\n",
           runs, found, stayed, wrong - stayed, runs ? time / runs : 0, slowest);
    return 0;
}

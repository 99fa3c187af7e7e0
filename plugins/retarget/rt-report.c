/* retarget.measure's JSON report (doc/retargeting.md, "Measures"), written with jansson: a figure
 * that is not a finite number (a mean over nothing, an overflow) is JSON's null, as printf's
 * "nan" or "inf" would not be JSON at all and a reader would refuse the whole report. */
#include <jansson.h>
#include <math.h>

#include <rigflow/text.h>

#include "retarget.h"

/* A figure: null when it is not finite. */
static json_t *rt_num(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

/* A joint's name as text: escaped for a terminal first (rf_text_escape: no control byte, valid
 * UTF-8), jansson escaping its quotes and backslashes. */
static json_t *rt_name(const rf_skeleton *s, uint32_t j)
{
    char name[128], shown[256];
    rf_text_escape(rf_joint_label(s, j, name, sizeof name), shown, sizeof shown, 0);
    return json_string(shown);
}

/* Sets key to v in o; false when v is NULL (out of memory) or cannot be set. */
static bool rt_set(json_t *o, const char *key, json_t *v)
{
    return v && json_object_set_new(o, key, v) == 0;
}

/* The mesh measures of one clip (`s`: the skeleton the mesh is skinned to); NULL when out of
 * memory. */
static json_t *rt_mesh_json(const rf_rt_mesh_report *m, const rf_skeleton *s)
{
    json_t *o = json_object();
    bool ok =
        o && rt_set(o, "frames", json_integer(m->frames)) &&
        rt_set(o, "height", rt_num(m->height)) && rt_set(o, "seams", json_integer(m->seams)) &&
        rt_set(o, "seam_p99", rt_num(m->seam_p99)) && rt_set(o, "seam_max", rt_num(m->seam_max)) &&
        rt_set(o, "floor_median", rt_num(m->floor_median)) &&
        rt_set(o, "floor_p95", rt_num(m->floor_p95)) &&
        rt_set(o, "floating", rt_num(m->floating)) && rt_set(o, "sinking", rt_num(m->sinking)) &&
        rt_set(o, "parts_below", rt_num(m->parts_below)) &&
        rt_set(o, "parts_depth", rt_num(m->parts_depth)) &&
        rt_set(o, "edges", json_integer(m->edges)) &&
        rt_set(o, "stretch_p99", rt_num(m->stretch_p99)) &&
        rt_set(o, "rigid", json_boolean(m->rigid));
    if (ok && m->parts)
        ok = rt_set(o, "parts", json_integer(m->parts)) &&
             rt_set(o, "part_stretch_p99", rt_num(m->part_stretch_p99)) &&
             rt_set(o, "part_joint", json_integer(m->part_joint)) &&
             rt_set(o, "part_edges", json_integer(m->part_edges)) &&
             rt_set(o, "part_joint_name", rt_name(s, m->part_joint));
    if (ok && m->seam_parts)
        ok = rt_set(o, "seam_parts", json_integer(m->seam_parts)) &&
             rt_set(o, "seam_part_p99", rt_num(m->seam_part_p99)) &&
             rt_set(o, "seam_joints",
                    json_pack("[I, I]", (json_int_t)m->seam_joints[0],
                              (json_int_t)m->seam_joints[1])) &&
             rt_set(o, "seam_part_seams", json_integer(m->seam_part_seams)) &&
             rt_set(
                 o, "seam_joint_names",
                 json_pack("[o, o]", rt_name(s, m->seam_joints[0]), rt_name(s, m->seam_joints[1])));
    if (ok && m->volume_parts)
        ok = rt_set(o, "volume_parts", json_integer(m->volume_parts)) &&
             rt_set(o, "volume_p95", rt_num(m->volume_p95)) &&
             rt_set(o, "volume_joint", json_integer(m->volume_joint)) &&
             rt_set(o, "volume_joint_name", rt_name(s, m->volume_joint));
    if (!ok)
        json_decref(o);
    return ok ? o : NULL;
}

/* The skate foot by foot: [{"joint": I, "name": "N", "skate": S, "contact_frames": C}]. */
static json_t *rt_feet_json(const rf_rt_report *r, const rf_skeleton *s)
{
    json_t *feet = json_array();
    for (uint32_t e = 0; feet && e < r->effectors && e < RF_RT_REPORT_FEET; e++) {
        json_t *f = json_object();
        bool ok = f && rt_set(f, "joint", json_integer(r->foot_joint[e])) &&
                  rt_set(f, "name", rt_name(s, r->foot_joint[e])) &&
                  rt_set(f, "skate", rt_num(r->foot_skate[e])) &&
                  rt_set(f, "contact_frames", json_integer(r->foot_frames[e]));
        if (!ok || json_array_append_new(feet, f) != 0) {
            if (!ok)
                json_decref(f);
            json_decref(feet);
            feet = NULL;
        }
    }
    return feet;
}

json_t *rf_rt_report_json(const rf_rt_report *r, const rf_rt_mesh_report *clip,
                          const rf_rt_mesh_report *ref, const rf_skeleton *s)
{
    json_t *o = json_object();
    bool ok = o && rt_set(o, "fidelity_mean_deg", rt_num(r->fidelity_mean)) &&
              rt_set(o, "fidelity_p95_deg", rt_num(r->fidelity_p95)) &&
              rt_set(o, "fidelity_max_deg", rt_num(r->fidelity_max)) &&
              rt_set(o, "bones", json_integer(r->fidelity_bones)) &&
              rt_set(o, "skate_target", rt_num(r->skate_target)) &&
              rt_set(o, "skate_source", rt_num(r->skate_source)) &&
              rt_set(o, "contact_frames", json_integer(r->contact_frames)) &&
              rt_set(o, "ground_error", rt_num(r->ground_error)) &&
              rt_set(o, "frames", json_integer(r->frames)) &&
              rt_set(o, "feet", rt_feet_json(r, s)) &&
              rt_set(o, "feet_count", json_integer(r->effectors)) &&
              rt_set(o, "source_feet", json_integer(r->source_feet)) &&
              (!clip || rt_set(o, "mesh", rt_mesh_json(clip, s))) &&
              (!ref || rt_set(o, "mesh_reference", rt_mesh_json(ref, s)));
    if (!ok)
        json_decref(o);
    return ok ? o : NULL;
}

bool rf_rt_report_write(FILE *f, const rf_rt_report *r, const rf_rt_mesh_report *clip,
                        const rf_rt_mesh_report *ref, const rf_skeleton *s)
{
    json_t *o = rf_rt_report_json(r, clip, ref, s);
    /* the figures' 6 significant digits, one line, keys in the order above */
    bool ok = o && json_dumpf(o, f, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(6)) == 0 &&
              fputc('\n', f) != EOF;
    json_decref(o);
    return ok;
}

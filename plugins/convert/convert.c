/* Format-dispatching import and export nodes, so one pipeline converts between any formats.
 *
 *   import: .bvh through libbvh (the native reader), everything else through Assimp
 *           (librfassimp, in a module loaded on first use: convert-assimp.c); the same outputs
 *           either way: skeleton, animation, mesh (empty for BVH), clips (one for BVH).
 *   export: by the output's extension: .glb / .gltf through our glTF writer (librfgltf), .bvh
 *           through libbvh's writer (rest rotations baked in, so the zero-rotation pose is the
 *           rest pose).
 *
 * The format-specific nodes (bvh.import, assimp.import, bvh.export) stay for pipelines that want
 * one format's options; these two only choose. doc/formats.md and doc/formats/gltf.md describe
 * what each format keeps.
 */
#define _GNU_SOURCE /* dladdr: where this plugin's file is */
#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <rigflow/rigflow.h>

#include "rigflow/aimport-node.h"
#include "rigflow/bvh.h"
#include "rigflow/gltf-write.h"
#include "rigflow/model-copy.h"

#include "bone-mesh.h"
#include "convert-assimp.h"

static const char *rf_cv_ext(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) ? dot : "";
}

/* ---- import ---- */

static void rf_cv_bvh_warning(void *user, const char *message)
{
    void **ctx = user;
    const rf_host *host = ctx[0];
    host->log(ctx[1], RF_LOG_WARNING, "%s", message);
}

static bool rf_cv_import_bvh(const rf_host *host, rf_node *node, const char *path)
{
    void *ctx[2] = {(void *)host, node};
    rf_bvh_read_opts opts = {.warning = rf_cv_bvh_warning, .user = ctx};
    rf_ai_result r = {.selected_clip = -1};
    char err[1024];
    if (!rf_bvh_read_file(path, &opts, &r.skeleton, &r.animation, err, sizeof err)) {
        host->error(node, "%s", err);
        return false;
    }
    rf_ai_clip clip = {.name = NULL, .fps = r.animation->fps, .frames = r.animation->frame_count};
    clip.duration = r.animation->frame_count > 1 ? (r.animation->frame_count - 1) / clip.fps : 0;
    const char *name = r.animation->name ? r.animation->name : "motion";
    clip.name = rf_strdup(name);
    if (clip.name)
        r.clips = malloc(sizeof *r.clips);
    if (!clip.name || !r.clips) {
        free(clip.name);
        rf_ai_result_clear(&r);
        host->error(node, "out of memory");
        return false;
    }
    r.clips[0] = clip, r.clip_count = 1, r.selected_clip = 0;
    return rf_ai_node_outputs_set(host, node, &r);
}

/* The Assimp import is loaded on first use (convert-assimp.c says why), once for the process,
 * from beside this plugin's file; imports on several threads wait for the one load. */
static pthread_once_t rf_cv_assimp_once = PTHREAD_ONCE_INIT;
static rf_cv_assimp_import_fn rf_cv_assimp;
static char rf_cv_assimp_error[8192]; /* holds the module's path and the loader's reason */

static void rf_cv_assimp_load(void)
{
    Dl_info self;
    if (!dladdr((void *)&rf_cv_assimp_error, &self) || !self.dli_fname) {
        snprintf(rf_cv_assimp_error, sizeof rf_cv_assimp_error,
                 "cannot load the Assimp import: the convert plugin's own file is unknown");
        return;
    }
    const char *slash = strrchr(self.dli_fname, '/');
    char path[4096];
    snprintf(path, sizeof path, "%.*s%s", slash ? (int)(slash - self.dli_fname + 1) : 0,
             self.dli_fname, RF_CV_ASSIMP_MODULE);
    void *module = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    void *fn = module ? dlsym(module, RF_CV_ASSIMP_SYMBOL) : NULL;
    if (!fn) {
        snprintf(rf_cv_assimp_error, sizeof rf_cv_assimp_error,
                 "cannot load the Assimp import (%s, installed with the convert plugin): %s", path,
                 dlerror());
        return;
    }
    memcpy(&rf_cv_assimp, &fn, sizeof fn); /* POSIX: a function's address, as an object pointer */
}

static bool rf_cv_import(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const char *path = host->param_string(node, "path");
    if (strcasecmp(rf_cv_ext(path), ".bvh") == 0)
        return rf_cv_import_bvh(host, node, path);
    pthread_once(&rf_cv_assimp_once, rf_cv_assimp_load);
    if (!rf_cv_assimp) {
        host->error(node, "%s", rf_cv_assimp_error);
        return false;
    }
    return rf_cv_assimp(host, node);
}

static const rf_importer_info rf_cv_importer = {sizeof(rf_importer_info), "*", "path"};

static const void *rf_cv_import_extension(const char *id)
{
    return strcmp(id, RF_IMPORTER_EXTENSION) == 0 ? &rf_cv_importer : NULL;
}

static const rf_node_desc rf_cv_import_desc = {
    .size = sizeof(rf_node_desc),
    .type = "import",
    .kind = RF_KIND_IMPORTER,
    .doc = "Imports any supported file, choosing by extension: .bvh with the native BVH reader "
           "(clip, rest_pose and require_skeleton do not apply), everything else through Assimp "
           "as assimp.import does. Outputs are the same for every format.",
    RF_NODE_OUTPUTS(rf_ai_node_outputs),
    RF_NODE_PARAMS(rf_ai_node_params),
    .process = rf_cv_import,
    .get_extension = rf_cv_import_extension,
    .flags = RF_NODE_CONCURRENT,
};

/* ---- export ---- */

static const rf_port_desc rf_cv_export_inputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0, "the skeleton to write"),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL | RF_PORT_MULTIPLE,
                 "its motion, one or more clips (glTF writes each as a named animation; BVH takes "
                 "one); without it: the rest pose"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, RF_PORT_OPTIONAL,
                 "a mesh skinned to the skeleton, with its materials and textures (glTF only; BVH "
                 "has no meshes)"),
    RF_PORT_DESC("clips", RF_TYPE_CLIPS, RF_PORT_OPTIONAL,
                 "an importer's clip list: when it holds every clip's motion (clip *), those clips "
                 "are written instead of the animation input"),
};

/* The clips to write: the clip list's motions when it holds any, else the animation inputs.
 * (transfer container: the array is the caller's, the clips are borrowed) */
static const rf_animation **rf_cv_export_clips(const rf_host *host, rf_node *node, uint32_t *count)
{
    const rf_clip_list *l = host->input_count(node, "clips") ? host->input(node, "clips", 0) : NULL;
    bool from_list = l && RF_HAS_FIELD(l, rf_clip_list, animations) && l->animations;
    uint32_t n = from_list ? l->count : host->input_count(node, "animation");
    const rf_animation **a = calloc(n ? n : 1, sizeof *a);
    *count = 0;
    for (uint32_t i = 0; a && i < n; i++) {
        const rf_animation *clip = from_list ? l->animations[i] : host->input(node, "animation", i);
        if (clip)
            a[(*count)++] = clip;
    }
    return a;
}

static const rf_param_desc rf_cv_export_params[] = {
    RF_PARAM_DESC_OUTPUT_PATH(
        "path", RF_PARAM_REQUIRED,
        "the file to write; its extension picks the format: .glb, .gltf or .bvh"),
    RF_PARAM_DESC_BOOL("bone_mesh", false,
                       "glTF without a mesh input: write a mesh of one thin double pyramid per "
                       "bone, skinned to it, so viewers that draw only meshes show the motion"),
};

/* Refuses an unknown extension when the pipeline is set up, before any import runs. */
static bool rf_cv_export_create(const rf_host *host, rf_node *node, void **self)
{
    const char *target = host->param_output_target(node, "path");
    const char *ext = rf_cv_ext(target);
    *self = NULL;
    if (strcasecmp(ext, ".glb") == 0 || strcasecmp(ext, ".gltf") == 0 ||
        strcasecmp(ext, ".bvh") == 0)
        return true;
    host->error(node, "%s: unknown output format '%s': expected .glb, .gltf or .bvh", target, ext);
    return false;
}

/* How far a rest hanging from the origin reaches under it along up: 0 unless the skeleton has
 * one root resting at the origin and no bind pose (BVH files hang the body from the origin and
 * their clips place the hips over the origin's plane, the floor they stand on); NAN when out of
 * memory. */
static double rf_cv_rest_depth(const rf_skeleton *s, rf_vec3 up)
{
    uint32_t roots = 0;
    for (uint32_t j = 0; j < s->joint_count; j++)
        roots += s->joints[j].parent < 0;
    bool bind = RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind;
    if (roots != 1 || bind)
        return 0;
    rf_xform *w = malloc(s->joint_count * sizeof *w);
    if (!w)
        return NAN;
    rf_skeleton_world_rest(s, w);
    double low = 0, high = 0;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        double h = rf_v3_dot(w[j].t, up);
        low = fmin(low, h), high = fmax(high, h);
    }
    bool at_origin = rf_v3_len(w[0].t) <= 1e-6 * fmax(high - low, 1e-12);
    free(w);
    return at_origin ? -low : 0;
}

/* A copy of `s` whose rest stands on the origin's plane when it hangs under it (see
 * rf_cv_rest_depth), else NULL: the bone mesh is bound in the rest, and drawn hanging from the
 * origin it put the rest's floor (a viewer's or a contact sheet's) a leg under where every clip
 * walks. The clips' root translations are keyed, so they move as before. */
static rf_skeleton *rf_cv_standing(const rf_skeleton *s, bool *failed)
{
    rf_vec3 up = rf_v3_len(s->up) > 0 ? rf_v3_normalize(s->up) : (rf_vec3){0, 1, 0};
    double depth = rf_cv_rest_depth(s, up);
    *failed = isnan(depth);
    if (!(depth > 0))
        return NULL;
    rf_skeleton *c = rf_skeleton_copy(s);
    *failed = !c;
    if (c)
        c->joints[0].rest.t = rf_v3_add(c->joints[0].rest.t, rf_v3_scale(up, depth));
    return c;
}

/* glTF, with the bones drawn as a mesh when asked for and no mesh is given. */
static bool rf_cv_export_gltf(const rf_host *host, rf_node *node, const char *path,
                              const char *target, const rf_skeleton *s, const rf_animation **a,
                              uint32_t n, const rf_mesh *m)
{
    char err[1024];
    rf_mesh *bones = NULL;
    rf_skeleton *standing = NULL;
    if (host->param_bool(node, "bone_mesh") && !(m && m->vertex_count && m->triangle_count)) {
        bool failed;
        standing = rf_cv_standing(s, &failed);
        if (failed) {
            host->error(node, "%s: out of memory", target);
            return false;
        }
        s = standing ? standing : s;
        m = bones = rf_cv_bone_mesh(s, a, n, err, sizeof err);
        if (!bones) {
            host->error(node, "%s: bone_mesh: %s", target, err);
            rf_skeleton_free(standing);
            return false;
        }
    } else if (host->param_bool(node, "bone_mesh")) {
        host->log(node, RF_LOG_INFO, "%s: the given mesh is written; bone_mesh draws none", target);
    }
    rf_gltf_write_opts o = {
        .binary = strcasecmp(rf_cv_ext(target && *target ? target : path), ".glb") == 0};
    bool ok = rf_gltf_write_clips(path, target, s, a, n, m, &o, err, sizeof err);
    if (!ok)
        host->error(node, "%s", err);
    rf_mesh_free(bones);
    rf_skeleton_free(standing);
    return ok;
}

static bool rf_cv_export(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const char *path = host->param_string(node, "path");
    const char *target = host->param_output_target(node, "path");
    const char *ext = rf_cv_ext(target && *target ? target : path);
    const rf_skeleton *s = host->input(node, "skeleton", 0);
    const rf_mesh *m = host->input_count(node, "mesh") ? host->input(node, "mesh", 0) : NULL;
    char err[1024];
    bool ok;
    if (!s) {
        host->error(node, "no skeleton on input 'skeleton'");
        return false;
    }
    uint32_t n;
    const rf_animation **a = rf_cv_export_clips(host, node, &n);
    if (!a) {
        host->error(node, "out of memory");
        return false;
    }
    if (strcasecmp(ext, ".glb") == 0 || strcasecmp(ext, ".gltf") == 0) {
        ok = rf_cv_export_gltf(host, node, path, target, s, a, n, m);
        free(a);
        return ok;
    } else if (strcasecmp(ext, ".bvh") == 0) {
        if (m && m->vertex_count)
            host->log(node, RF_LOG_INFO, "%s: BVH keeps no mesh; the mesh is left out", target);
        if (n > 1)
            host->log(node, RF_LOG_WARNING,
                      "%s: BVH holds one clip; the first of %u is written, the others are left "
                      "out (write .glb to keep them all)",
                      target, n);
        ok = rf_bvh_write_file(path, target, s, n ? a[0] : NULL, NULL, err, sizeof err);
    } else {
        host->error(node, "%s: unknown output format '%s': expected .glb, .gltf or .bvh", target,
                    ext);
        free(a);
        return false;
    }
    free(a);
    if (!ok)
        host->error(node, "%s", err);
    return ok;
}

static const rf_node_desc rf_cv_export_desc = {
    .size = sizeof(rf_node_desc),
    .type = "export",
    .kind = RF_KIND_EXPORTER,
    .doc = "Writes a skeleton with its motion (and mesh, for glTF) in the format the output's "
           "extension names: .glb or .gltf (glTF 2.0: nodes, skin, skinned mesh with materials "
           "and embedded images, one named animation per clip) or .bvh (one clip; rest "
           "rotations baked in: the zero-rotation pose is the rest pose).",
    RF_NODE_INPUTS(rf_cv_export_inputs),
    RF_NODE_PARAMS(rf_cv_export_params),
    .create = rf_cv_export_create,
    .process = rf_cv_export,
    .flags = RF_NODE_CONCURRENT,
};

static const rf_node_desc *const rf_cv_nodes[] = {&rf_cv_import_desc, &rf_cv_export_desc};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.convert",
    .name = "Format conversion",
    .version = "0.1.0",
    .description = "import and export nodes that pick the format by the file's extension",
    .node_count = 2,
    .nodes = rf_cv_nodes,
};

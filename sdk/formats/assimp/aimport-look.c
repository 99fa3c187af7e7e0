/* Assimp import: the materials of the merged mesh in glTF's metallic-roughness terms, and the
 * images their textures use, as bytes.
 *
 * Every format's material maps onto rf_material: the base colour is Assimp's "$clr.base" where
 * the format has one (glTF), else the diffuse colour; the base colour texture is the BASE_COLOR
 * texture, else the DIFFUSE one. Metallic and roughness come from glTF's factors; formats
 * without them (Phong-style .x, FBX, B3D, Ogre) get metallic 0 and roughness 1, a plain
 * non-metal surface, since their specular terms have no faithful counterpart (doc/formats.md).
 *
 * Images: an embedded texture ("*N" or a name matching an embedded file) is taken as stored; a
 * texture named by a path is read through the import's confinement (aimport-io.c), so only files
 * inside the model's folder are ever read. Only PNG and JPEG, recognised by their signatures, are
 * kept (the two formats glTF carries). A texture that is missing, refused, unreadable or not such
 * an image is left out with a warning naming it and its material; the model imports without it.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>

#include "aimport-internal.h"

#define RF_AI_IMAGE_MAX ((size_t)256 << 20) /* bytes: larger files are refused, not read */

/* Distinct texture names read at most: a real model names a few dozen, a hostile one could name a
 * file per material and have each looked up. */
#define RF_AI_TEXTURE_NAMES_MAX 1024u

/* A texture name seen before: the image it became, or -1 when it was left out. */
typedef struct rf_ai_seen {
    char *key;
    int32_t image;
} rf_ai_seen;

typedef struct rf_ai_look {
    rf_ai_ctx *c;
    rf_mesh *m;
    rf_ai_seen seen[RF_AI_TEXTURE_NAMES_MAX * 2]; /* open addressing, at most half full */
    unsigned seen_count;
    bool capped; /* names past the bound were left out (warned once) */
} rf_ai_look;

static rf_ai_seen *rf_ai_seen_slot(rf_ai_look *L, const char *name)
{
    uint64_t h = 1469598103934665603u; /* FNV-1a */
    for (const unsigned char *p = (const unsigned char *)name; *p; p++)
        h = (h ^ *p) * 1099511628211u;
    size_t mask = RF_AI_TEXTURE_NAMES_MAX * 2 - 1, i = (size_t)h & mask;
    while (L->seen[i].key && strcmp(L->seen[i].key, name) != 0)
        i = (i + 1) & mask;
    return &L->seen[i];
}

static const char *rf_ai_sniff_mime(const unsigned char *b, size_t n)
{
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n >= 8 && memcmp(b, png, 8) == 0)
        return "image/png";
    if (n >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff)
        return "image/jpeg";
    return NULL;
}

/* Appends an image (a copy of the bytes) when they are a PNG or JPEG; -1 with a warning else. */
static int32_t rf_ai_add_image(rf_ai_look *L, const char *name, const char *label,
                               const char *material, const unsigned char *bytes, size_t n)
{
    const char *mime = rf_ai_sniff_mime(bytes, n);
    if (!mime) {
        rf_ai_logf(L->c, 1,
                   "%s: material '%s': texture '%s' is not a PNG or JPEG image (the formats glTF "
                   "carries): left out",
                   L->c->path, material, label);
        return -1;
    }
    rf_mesh *m = L->m;
    rf_image **grown = realloc(m->images, (m->image_count + 1) * sizeof *grown);
    if (!grown)
        return -1;
    m->images = grown;
    rf_image *im = rf_image_new(name, mime, bytes, n);
    if (!im)
        return -1;
    m->images[m->image_count] = im;
    return (int32_t)m->image_count++;
}

static int rf_ai_embedded_index(const rf_ai_ctx *c, const char *name)
{
    const struct aiScene *s = c->scene;
    if (name[0] == '*') {
        char *end;
        long i = strtol(name + 1, &end, 10);
        return *end == '\0' && i >= 0 && (unsigned long)i < s->mNumTextures ? (int)i : -1;
    }
    const char *base = strrchr(name, '/');
    base = base ? base + 1 : name;
    for (unsigned i = 0; i < s->mNumTextures; i++) {
        const char *f = s->mTextures[i]->mFilename.data, *fb = strrchr(f, '/');
        if (f[0] && (strcmp(f, name) == 0 || strcmp(fb ? fb + 1 : f, base) == 0))
            return (int)i;
    }
    return -1;
}

static int32_t rf_ai_embedded_image(rf_ai_look *L, int t, const char *name, const char *material)
{
    const struct aiTexture *tex = L->c->scene->mTextures[t];
    if (tex->mHeight != 0) {
        rf_ai_logf(L->c, 1,
                   "%s: material '%s': embedded texture '%s' is raw texels, not an image file: "
                   "left out",
                   L->c->path, material, name);
        return -1;
    }
    /* Compressed: mWidth is the byte count of the file held in pcData. */
    return rf_ai_add_image(L, tex->mFilename.data[0] ? tex->mFilename.data : NULL, name, material,
                           (const unsigned char *)tex->pcData, tex->mWidth);
}

/* The file name at the end of a texture path written on any system ('/', '\\' or a drive's ':'). */
static const char *rf_ai_base_name(const char *name)
{
    const char *base = name;
    for (const char *p = name; *p; p++)
        if (*p == '/' || *p == '\\' || *p == ':')
            base = p + 1;
    return base;
}

/* The texture file's path: relative names are relative to the model's folder; Windows
 * separators are read as '/'. (transfer full) */
static char *rf_ai_texture_path(const rf_ai_ctx *c, const char *name)
{
    const char *slash = strrchr(c->path, '/');
    size_t dir = name[0] == '/' ? 0 : slash ? (size_t)(slash - c->path) + 1 : 0;
    char *p = malloc(dir + strlen(name) + 1);
    if (!p)
        return NULL;
    memcpy(p, c->path, dir);
    strcpy(p + dir, name);
    for (char *q = p + dir; *q; q++)
        if (*q == '\\')
            *q = '/';
    return p;
}

static unsigned char *rf_ai_read_all(struct aiFileIO *io, struct aiFile *f, size_t *n)
{
    size_t size = f->FileSizeProc(f);
    unsigned char *b = size && size <= RF_AI_IMAGE_MAX ? malloc(size) : NULL;
    if (b && f->ReadProc(f, (char *)b, 1, size) != size) {
        free(b);
        b = NULL;
    }
    io->CloseProc(io, f);
    *n = size;
    return b;
}

/* Opens a texture named `name`: as written, relative to the model's folder; when that file is
 * missing (not refused) and the name has folders, by its file name beside the model, which is
 * where a model carried from its author's machine (an FBX naming D:\\art\\skin.png) has it; a
 * warning says so, since it is not the path the file names. NULL when neither is had.
 * *path is the path opened or tried first. (transfer full: *path) */
static struct aiFile *rf_ai_texture_open(rf_ai_look *L, const char *name, const char *material,
                                         char **path)
{
    rf_ai_ctx *c = L->c;
    unsigned refused = c->confine.refused_count;
    struct aiFile *f =
        (*path = rf_ai_texture_path(c, name)) ? c->io.OpenProc(&c->io, *path, "rb") : NULL;
    const char *base = rf_ai_base_name(name);
    if (f || !*path || c->confine.refused_count != refused || base == name || !*base)
        return f;
    char *beside = rf_ai_texture_path(c, base);
    f = beside ? c->io.OpenProc(&c->io, beside, "rb") : NULL;
    if (f) {
        rf_ai_logf(c, 1,
                   "%s: material '%s': texture '%s' is not where it says: its file name %s was "
                   "found beside the model and is used",
                   c->path, material, name, base);
        free(*path);
        *path = beside;
    } else {
        free(beside);
    }
    return f;
}

static int32_t rf_ai_file_image(rf_ai_look *L, const char *name, const char *material)
{
    rf_ai_ctx *c = L->c;
    unsigned refused = c->confine.refused_count;
    char before[sizeof c->confine.refused];
    memcpy(before, c->confine.refused, sizeof before);
    c->confine.refused[0] = '\0'; /* to hear this texture's own refusal */
    char *path = NULL;
    struct aiFile *f = rf_ai_texture_open(L, name, material, &path);
    if (!path) {
        memcpy(c->confine.refused, before, sizeof before);
        return -1;
    }
    int32_t image = -1;
    if (!f && c->confine.refused_count != refused)
        rf_ai_logf(c, 1, "%s: material '%s': texture '%s' left out: %s", c->path, material, name,
                   c->confine.refused);
    else if (!f)
        rf_ai_logf(
            c, 1,
            "%s: material '%s': texture '%s' left out: not found beside the model, or not readable",
            c->path, material, name);
    size_t n = 0;
    unsigned char *bytes = f ? rf_ai_read_all(&c->io, f, &n) : NULL;
    if (f && !bytes)
        rf_ai_logf(c, 1, "%s: material '%s': texture '%s' left out: %s", c->path, material, name,
                   n > RF_AI_IMAGE_MAX ? "larger than 256 MiB" : "empty or unreadable");
    if (bytes) {
        const char *base = strrchr(path, '/');
        image = rf_ai_add_image(L, base ? base + 1 : path, name, material, bytes, n);
    }
    free(bytes);
    free(path);
    memcpy(c->confine.refused, before, sizeof before);
    return image;
}

/* The image a texture name stands for, read once per name. */
static int32_t rf_ai_image_for(rf_ai_look *L, const char *name, const char *material)
{
    rf_ai_seen *slot = rf_ai_seen_slot(L, name);
    if (slot->key)
        return slot->image;
    if (L->seen_count == RF_AI_TEXTURE_NAMES_MAX) {
        if (!L->capped)
            rf_ai_logf(L->c, 1, "%s: more than %u texture names: '%s' and later ones left out",
                       L->c->path, RF_AI_TEXTURE_NAMES_MAX, name);
        L->capped = true;
        return -1;
    }
    int t = rf_ai_embedded_index(L->c, name);
    int32_t image =
        t >= 0 ? rf_ai_embedded_image(L, t, name, material) : rf_ai_file_image(L, name, material);
    if ((slot->key = rf_strdup(name)))
        slot->image = image, L->seen_count++;
    return image;
}

static uint16_t rf_ai_wrap(enum aiTextureMapMode mode)
{
    switch (mode) {
    case aiTextureMapMode_Clamp:
        return RF_TEX_CLAMP_TO_EDGE;
    case aiTextureMapMode_Mirror:
        return RF_TEX_MIRRORED_REPEAT;
    default:
        return RF_TEX_REPEAT;
    }
}

static uint16_t rf_ai_filter(const struct aiMaterial *am, const char *key, enum aiTextureType type)
{
    int v = 0;
    if (aiGetMaterialIntegerArray(am, key, type, 0, &v, NULL) != aiReturn_SUCCESS)
        return 0;
    /* only the values glTF allows (a file may carry anything here) */
    return v == 9728 || v == 9729 || (v >= 9984 && v <= 9987) ? (uint16_t)v : 0;
}

/* The first of `types` the material has a texture of, as a reference (image -1 when none). */
static rf_texture_ref rf_ai_texture(rf_ai_look *L, const struct aiMaterial *am,
                                    const enum aiTextureType *types, int ntypes,
                                    const char *material)
{
    rf_texture_ref t = rf_texture_ref_none();
    for (int k = 0; k < ntypes; k++) {
        struct aiString path;
        unsigned uv = 0;
        enum aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
        if (aiGetMaterialTexture(am, types[k], 0, &path, NULL, &uv, NULL, NULL, modes, NULL) !=
                aiReturn_SUCCESS ||
            !path.data[0])
            continue;
        t.image = rf_ai_image_for(L, path.data, material);
        if (t.image < 0)
            return t;
        t.uv_set = uv;
        t.wrap_s = rf_ai_wrap(modes[0]), t.wrap_t = rf_ai_wrap(modes[1]);
        t.mag_filter = rf_ai_filter(am, _AI_MATKEY_GLTF_MAPPINGFILTER_MAG_BASE, types[k]);
        t.min_filter = rf_ai_filter(am, _AI_MATKEY_GLTF_MAPPINGFILTER_MIN_BASE, types[k]);
        float f;
        if (aiGetMaterialFloatArray(am, _AI_MATKEY_GLTF_SCALE_BASE, types[k], 0, &f, NULL) ==
                aiReturn_SUCCESS ||
            aiGetMaterialFloatArray(am, _AI_MATKEY_GLTF_STRENGTH_BASE, types[k], 0, &f, NULL) ==
                aiReturn_SUCCESS)
            t.scale = f;
        return t;
    }
    return t;
}

static float rf_ai_unit(float v)
{
    return v > 0 ? (v < 1 ? v : 1) : 0; /* also NaN to 0 */
}

static void rf_ai_factors(const struct aiMaterial *am, rf_material *m)
{
    struct aiColor4D col;
    if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &col) == aiReturn_SUCCESS ||
        aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &col) == aiReturn_SUCCESS) {
        m->base_color[0] = rf_ai_unit(col.r), m->base_color[1] = rf_ai_unit(col.g);
        m->base_color[2] = rf_ai_unit(col.b), m->base_color[3] = rf_ai_unit(col.a);
    }
    float f;
    m->metallic =
        aiGetMaterialFloatArray(am, AI_MATKEY_METALLIC_FACTOR, &f, NULL) == aiReturn_SUCCESS
            ? rf_ai_unit(f)
            : 0.0f;
    m->roughness =
        aiGetMaterialFloatArray(am, AI_MATKEY_ROUGHNESS_FACTOR, &f, NULL) == aiReturn_SUCCESS
            ? rf_ai_unit(f)
            : 1.0f;
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &col) == aiReturn_SUCCESS)
        m->emissive[0] = rf_ai_unit(col.r), m->emissive[1] = rf_ai_unit(col.g),
        m->emissive[2] = rf_ai_unit(col.b);
    int two = 0;
    if (aiGetMaterialIntegerArray(am, AI_MATKEY_TWOSIDED, &two, NULL) == aiReturn_SUCCESS)
        m->double_sided = two != 0;
    struct aiString mode;
    if (aiGetMaterialString(am, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS) {
        m->alpha_mode = strcmp(mode.data, "MASK") == 0    ? RF_ALPHA_MASK
                        : strcmp(mode.data, "BLEND") == 0 ? RF_ALPHA_BLEND
                                                          : RF_ALPHA_OPAQUE;
        if (aiGetMaterialFloatArray(am, AI_MATKEY_GLTF_ALPHACUTOFF, &f, NULL) == aiReturn_SUCCESS)
            m->alpha_cutoff = f >= 0 ? f : 0.5f;
    } else if (aiGetMaterialFloatArray(am, AI_MATKEY_OPACITY, &f, NULL) == aiReturn_SUCCESS &&
               f < 1) {
        /* Phong-style formats give transparency as an opacity */
        m->base_color[3] = rf_ai_unit(f);
        m->alpha_mode = RF_ALPHA_BLEND;
    }
}

static rf_material *rf_ai_material(rf_ai_look *L, const struct aiMaterial *am)
{
    static const enum aiTextureType base[] = {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE};
    static const enum aiTextureType mr[] = {aiTextureType_UNKNOWN};
    static const enum aiTextureType normal[] = {aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA};
    static const enum aiTextureType occl[] = {aiTextureType_LIGHTMAP,
                                              aiTextureType_AMBIENT_OCCLUSION};
    static const enum aiTextureType emis[] = {aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR};
    rf_material *m = rf_material_new();
    struct aiString name;
    if (!m)
        return NULL;
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.data[0])
        m->name = rf_strdup(name.data);
    const char *label = m->name ? m->name : "";
    rf_ai_factors(am, m);
    m->base_color_texture = rf_ai_texture(L, am, base, 2, label);
    m->metallic_roughness_texture = rf_ai_texture(L, am, mr, 1, label);
    m->normal_texture = rf_ai_texture(L, am, normal, 2, label);
    m->occlusion_texture = rf_ai_texture(L, am, occl, 2, label);
    m->emissive_texture = rf_ai_texture(L, am, emis, 2, label);
    if (m->emissive_texture.image >= 0 && !(m->emissive[0] + m->emissive[1] + m->emissive[2] > 0))
        m->emissive[0] = m->emissive[1] = m->emissive[2] = 1.0f; /* else the texture shows black */
    return m;
}

bool rf_ai_build_materials(rf_ai_ctx *c, rf_mesh *m, const unsigned *part_mesh)
{
    const struct aiScene *s = c->scene;
    rf_ai_look *L = calloc(1, sizeof *L); /* 16 KiB of slots: not on the stack */
    if (!L)
        return rf_ai_fail(c, "out of memory for the materials");
    L->c = c, L->m = m;
    int32_t *of = malloc((s->mNumMaterials + 1) * sizeof *of); /* scene material to ours */
    m->part_material = calloc(m->part_count ? m->part_count : 1, sizeof *m->part_material);
    m->materials = calloc(s->mNumMaterials + 1, sizeof *m->materials);
    bool ok = of && m->part_material && m->materials;
    for (unsigned i = 0; ok && i <= s->mNumMaterials; i++)
        of[i] = -1;
    /* Only the materials the parts use, in the order they are first used. */
    for (uint32_t p = 0; ok && p < m->part_count; p++) {
        unsigned mi = s->mMeshes[part_mesh[p]]->mMaterialIndex;
        if (mi >= s->mNumMaterials) {
            m->part_material[p] = -1;
            continue;
        }
        if (of[mi] < 0) {
            rf_material *mat = rf_ai_material(L, s->mMaterials[mi]);
            if (!mat) {
                ok = false;
                break;
            }
            of[mi] = (int32_t)m->material_count;
            m->materials[m->material_count++] = mat;
        }
        m->part_material[p] = of[mi];
    }
    for (unsigned i = 0; i < RF_AI_TEXTURE_NAMES_MAX * 2; i++)
        free(L->seen[i].key);
    free(L);
    free(of);
    return ok ? true : rf_ai_fail(c, "out of memory for the materials");
}

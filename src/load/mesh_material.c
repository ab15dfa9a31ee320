#include "mesh_material.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include "core/error.h"
#include "io/image.h"
#include "load/assimp_load.h"

typedef enum format { FORMAT_OTHER, FORMAT_GLTF, FORMAT_COLLADA, FORMAT_PLAIN } format;

static format format_of(const char *name)
{
    const char *dot = strrchr(name, '.'), *slash = strrchr(name, '/');
    if (!dot || (slash && dot < slash))
        return FORMAT_OTHER;
    if (strcasecmp(dot, ".gltf") == 0 || strcasecmp(dot, ".glb") == 0)
        return FORMAT_GLTF;
    if (strcasecmp(dot, ".dae") == 0 || strcasecmp(dot, ".zae") == 0)
        return FORMAT_COLLADA;
    if (strcasecmp(dot, ".ply") == 0 || strcasecmp(dot, ".off") == 0 ||
        strcasecmp(dot, ".stl") == 0)
        return FORMAT_PLAIN;
    return FORMAT_OTHER;
}

static mesh_mat matte_white(void)
{
    return (mesh_mat){{1, 1, 1}, {0, 0, 0}, 0, 1, -1};
}

static float unit(float x, float fallback)
{
    return isfinite(x) ? fminf(fmaxf(x, 0), 1) : fallback;
}

typedef struct texs {
    mesh_data *md;
    uint32_t cap;
    int32_t *embedded; /* scene texture i -> index in md->texs, or -1 */
} texs;

static int32_t add_tex(texs *t, mesh_tex tex)
{
    mesh_data *md = t->md;
    if (md->ntexs == t->cap) {
        uint32_t cap = t->cap ? 2 * t->cap : 8;
        mesh_tex *n = realloc(md->texs, cap * sizeof *n);
        if (!n)
            return -2;
        md->texs = n;
        t->cap = cap;
    }
    tex.bytes = malloc(tex.size ? tex.size : 1);
    if (!tex.bytes)
        return -2;
    md->texs[md->ntexs] = tex;
    return (int32_t)md->ntexs++;
}

/* A texture held in the file: the encoded file's bytes, or BGRA texels. */
static int32_t embedded_tex(texs *t, const struct aiScene *sc, unsigned i)
{
    if (t->embedded[i] != -1)
        return t->embedded[i];
    const struct aiTexture *tx = sc->mTextures[i];
    mesh_tex m = {0};
    if (!tx->pcData || tx->mWidth == 0)
        return -1;
    if (tx->mHeight == 0) {
        m.kind = MESH_TEX_ENCODED;
        m.size = tx->mWidth;
    } else {
        if ((uint64_t)tx->mWidth * tx->mHeight > IMAGE_MAX_PIXELS)
            return -1;
        m = (mesh_tex){MESH_TEX_TEXELS, tx->mWidth, tx->mHeight, tx->mWidth * tx->mHeight * 4,
                       NULL};
    }
    int32_t k = add_tex(t, m);
    if (k >= 0)
        memcpy(t->md->texs[k].bytes, tx->pcData, m.size);
    t->embedded[i] = k;
    return k;
}

static const char *base_name(const char *p)
{
    const char *s = strrchr(p, '/'), *b = strrchr(p, '\\');
    if (b && (!s || b > s))
        s = b;
    return s ? s + 1 : p;
}

/* The diffuse (or base colour) texture: -1 none, -2 out of memory. */
static int32_t material_tex(texs *t, const struct aiScene *sc, const struct aiMaterial *am)
{
    struct aiString path;
    if (aiGetMaterialTexture(am, aiTextureType_DIFFUSE, 0, &path, NULL, NULL, NULL, NULL, NULL,
                             NULL) != aiReturn_SUCCESS &&
        aiGetMaterialTexture(am, aiTextureType_BASE_COLOR, 0, &path, NULL, NULL, NULL, NULL, NULL,
                             NULL) != aiReturn_SUCCESS)
        return -1;
    size_t len = strnlen(path.data, path.length < MAXLEN ? path.length : MAXLEN - 1);
    if (len == 0)
        return -1;
    path.data[len] = 0;
    if (path.data[0] == '*') {
        char *end;
        unsigned long i = strtoul(path.data + 1, &end, 10);
        return *end == 0 && end != path.data + 1 && i < sc->mNumTextures ? embedded_tex(t, sc, (unsigned)i)
                                                                       : -1;
    }
    for (unsigned i = 0; i < sc->mNumTextures; i++) {
        const char *f = sc->mTextures[i]->mFilename.data;
        if (sc->mTextures[i]->mFilename.length > 0 && strcmp(base_name(f), base_name(path.data)) == 0)
            return embedded_tex(t, sc, i);
    }
    for (uint32_t i = 0; i < t->md->ntexs; i++)
        if (t->md->texs[i].kind == MESH_TEX_FILE && t->md->texs[i].size == len &&
            memcmp(t->md->texs[i].bytes, path.data, len) == 0)
            return (int32_t)i;
    int32_t k = add_tex(t, (mesh_tex){MESH_TEX_FILE, 0, 0, (uint32_t)len, NULL});
    if (k >= 0)
        memcpy(t->md->texs[k].bytes, path.data, len);
    return k;
}

/* The material's opacity, or -1 when the file gives none (fix_opacity). */
static float opacity_of(const struct aiMaterial *am, format fmt, float alpha)
{
    ai_real f;
    float o = aiGetMaterialFloatArray(am, AI_MATKEY_OPACITY, &f, NULL) == aiReturn_SUCCESS
                  ? (float)f
                  : -1.0f;
    if (fmt == FORMAT_GLTF) {
        struct aiString mode;
        bool blend = aiGetMaterialString(am, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS &&
                     strcmp(mode.data, "BLEND") == 0;
        return blend ? unit(o < 0 ? alpha : fminf(o, alpha), 1) : 1.0f;
    }
    return o < 0 ? -1.0f : unit(o, 1);
}

static glint_rc one_material(texs *t, const struct aiScene *sc, const struct aiMaterial *am,
                             format fmt, mesh_mat *m)
{
    *m = matte_white();
    /* assimp's stand-ins: "DefaultMaterial", and whatever it makes for PLY,
     * OFF and STL, which have no materials */
    struct aiString name;
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
        name.data[0] = 0;
    if (strcmp(name.data, AI_DEFAULT_MATERIAL_NAME) == 0 || fmt == FORMAT_PLAIN)
        return GLINT_OK;
    struct aiColor4D c;
    float alpha = 1;
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS ||
        aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS) {
        m->diffuse[0] = unit(c.r, 1), m->diffuse[1] = unit(c.g, 1), m->diffuse[2] = unit(c.b, 1);
        alpha = unit(c.a, 1);
    }
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_SPECULAR, &c) == aiReturn_SUCCESS)
        m->specular[0] = unit(c.r, 0), m->specular[1] = unit(c.g, 0), m->specular[2] = unit(c.b, 0);
    ai_real f;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_SHININESS, &f, NULL) == aiReturn_SUCCESS &&
        isfinite(f) && f > 0)
        m->shininess = fminf((float)f, 1e4f);
    m->opacity = opacity_of(am, fmt, alpha);
    m->texture = material_tex(t, sc, am);
    if (m->texture == -2)
        return GLINT_ERR_NOMEM;
    if (m->texture >= 0 && fmt != FORMAT_GLTF)
        m->diffuse[0] = m->diffuse[1] = m->diffuse[2] = 1;
    return GLINT_OK;
}

/* Opacity 0 is the mark of the inverted convention (see the header);
 * materials that gave no opacity (-1) are opaque either way. */
static void fix_opacity(mesh_data *md, format fmt)
{
    bool invisible = false;
    for (uint32_t i = 0; i < md->nmats; i++)
        invisible = invisible || md->mats[i].opacity == 0;
    for (uint32_t i = 0; i < md->nmats; i++) {
        mesh_mat *m = &md->mats[i];
        if (m->opacity < 0)
            m->opacity = 1;
        else if (invisible && fmt == FORMAT_COLLADA)
            m->opacity = 1 - m->opacity;
        else if (m->opacity == 0 && fmt != FORMAT_GLTF)
            m->opacity = 1;
    }
}

glint_rc mesh_material_gather(const struct aiScene *sc, const char *name, mesh_data *md,
                              glint_error *err)
{
    format fmt = format_of(name);
    md->nmats = sc->mNumMaterials ? sc->mNumMaterials : 1;
    md->mats = calloc(md->nmats, sizeof *md->mats);
    texs t = {md, 0, calloc(sc->mNumTextures ? sc->mNumTextures : 1, sizeof(int32_t))};
    if (!md->mats || !t.embedded) {
        free(t.embedded);
        return err_nomem(err);
    }
    for (unsigned i = 0; i < sc->mNumTextures; i++)
        t.embedded[i] = -1;
    md->mats[0] = matte_white();
    glint_rc rc = GLINT_OK;
    for (unsigned i = 0; rc == GLINT_OK && i < sc->mNumMaterials; i++)
        rc = one_material(&t, sc, sc->mMaterials[i], fmt, &md->mats[i]);
    free(t.embedded);
    if (rc != GLINT_OK)
        return err_nomem(err);
    fix_opacity(md, fmt);
    return GLINT_OK;
}

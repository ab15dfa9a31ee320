#include "mesh_import.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/error.h"
#include "load/load.h"
#include "scene/scene.h"

/* Meshes larger than this are refused before allocating. */
#define MESH_MAX_TRIANGLES (1 << 27)

static material import_material(const struct aiMaterial *am)
{
    material m = material_default();
    struct aiColor4D c;
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS)
        m.color = v3(c.r, c.g, c.b);
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_SPECULAR, &c) == aiReturn_SUCCESS)
        m.specular = fmaxf(c.r, fmaxf(c.g, c.b));
    ai_real f;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_SHININESS, &f, NULL) == aiReturn_SUCCESS && f > 0)
        m.shininess = (float)f;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_OPACITY, &f, NULL) == aiReturn_SUCCESS && f >= 0 &&
        f < 1)
        m.transmit = 1.0f - (float)f;
    if (!v3_is_finite(m.color) || !isfinite(m.specular) || !isfinite(m.shininess))
        m = material_default();
    return m;
}

/* Only triangles are kept. Triangulation marks meshes that held polygons
 * with aiPrimitiveType_NGONEncodingFlag (assimp 5.1 and later), which says
 * how they were made, not what they are. */
static bool is_triangle_mesh(const struct aiMesh *am)
{
    return (am->mPrimitiveTypes & ~(unsigned)aiPrimitiveType_NGONEncodingFlag) ==
           aiPrimitiveType_TRIANGLE;
}

static const unsigned import_flags =
    aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
    aiProcess_GenSmoothNormals | aiProcess_SortByPType | aiProcess_ValidateDataStructure;

/* Flattens what assimp read into one glint mesh; releases sc. */
static glint_rc convert(const struct aiScene *sc, const char *path, mesh_file *out,
                        glint_error *err)
{
    glint_rc rc = GLINT_OK;
    mesh *m = calloc(1, sizeof *m);
    if (!m) {
        rc = err_nomem(err);
        goto out;
    }
    /* Count what will be kept: triangle meshes only (points and lines,
     * which SortByPType puts in meshes of their own, are skipped). */
    uint64_t nv = 0, nt = 0;
    bool any_normals = false, any_uv = false;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        if (!is_triangle_mesh(am))
            continue;
        nv += am->mNumVertices;
        nt += am->mNumFaces;
        any_normals = any_normals || am->mNormals;
        any_uv = any_uv || am->mTextureCoords[0];
    }
    if (nt == 0) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: mesh has no triangles", path);
        goto out;
    }
    if (nt > MESH_MAX_TRIANGLES || nv > UINT32_MAX / 2) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: mesh is too large (%llu triangles, limit %d)", path,
                     (unsigned long long)nt, MESH_MAX_TRIANGLES);
        goto out;
    }
    m->nverts = (int)nv;
    m->ntris = (int)nt;
    m->pos = malloc(sizeof *m->pos * nv);
    m->nrm = any_normals ? calloc(nv, sizeof *m->nrm) : NULL;
    m->uv = any_uv ? calloc(nv, sizeof *m->uv) : NULL;
    m->tri = malloc(sizeof *m->tri * nt);
    m->tri_material = malloc(sizeof *m->tri_material * nt);
    out->nmaterials = (int)sc->mNumMaterials;
    out->materials = malloc(sizeof *out->materials * (sc->mNumMaterials ? sc->mNumMaterials : 1));
    if (!m->pos || (any_normals && !m->nrm) || (any_uv && !m->uv) || !m->tri ||
        !m->tri_material || !out->materials) {
        rc = err_nomem(err);
        goto out;
    }
    for (unsigned i = 0; i < sc->mNumMaterials; i++)
        out->materials[i] = import_material(sc->mMaterials[i]);
    if (sc->mNumMaterials == 0) {
        out->materials[0] = material_default();
        out->nmaterials = 1;
    }

    uint32_t vbase = 0, t = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        if (!is_triangle_mesh(am))
            continue;
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            const struct aiVector3D *p = &am->mVertices[v];
            m->pos[vbase + v] = v3((float)p->x, (float)p->y, (float)p->z);
            if (am->mNormals) {
                vec3 n = v3((float)am->mNormals[v].x, (float)am->mNormals[v].y,
                            (float)am->mNormals[v].z);
                m->nrm[vbase + v] = v3_is_finite(n) ? v3_norm(n) : v3s(0.0f);
            }
            if (am->mTextureCoords[0]) {
                m->uv[vbase + v][0] = (float)am->mTextureCoords[0][v].x;
                m->uv[vbase + v][1] = (float)am->mTextureCoords[0][v].y;
            }
        }
        int mat = am->mMaterialIndex < (unsigned)out->nmaterials ? (int)am->mMaterialIndex : 0;
        for (unsigned f = 0; f < am->mNumFaces; f++) {
            const struct aiFace *face = &am->mFaces[f];
            if (face->mNumIndices != 3) {
                m->tri[t][0] = m->tri[t][1] = m->tri[t][2] = UINT32_MAX; /* dropped by mesh_init */
            } else {
                for (int k = 0; k < 3; k++)
                    m->tri[t][k] = vbase + face->mIndices[k];
            }
            m->tri_material[t++] = mat;
        }
        vbase += am->mNumVertices;
    }
    rc = mesh_init(m, path, &out->dropped, err);
out:
    aiReleaseImport(sc);
    if (rc != GLINT_OK) {
        mesh_free(m);
        free(m);
        free(out->materials);
        memset(out, 0, sizeof *out);
        return rc;
    }
    out->mesh = m;
    return GLINT_OK;
}

/* assimp's validation of a file without faces or meshes speaks of its own
 * structures ("Mesh  contains no faces", "aiScene::mNumMeshes is 0"); the
 * user is told what the documentation says. Memory running out in assimp
 * is out of memory (exit 1), not bad input. */
static glint_rc import_error(const char *name, const char *why, glint_error *err)
{
    if (strstr(why, "contains no faces") || strstr(why, "mNumMeshes is 0"))
        return err_set(err, GLINT_ERR_INPUT, "%s: mesh has no triangles", name);
    if (strstr(why, "bad_alloc")) /* a C++ allocation failed inside assimp */
        return err_nomem(err);
    return err_set(err, GLINT_ERR_INPUT, "%s: cannot import mesh: %s", name, why);
}

/* assimp keeps the reason for the last failure in one process-wide string,
 * so imports are serialised: the message read after a failed import is that
 * import's own, whatever other threads load at the same time. This lock is
 * the library's only shared state; it holds no data. */
static pthread_mutex_t import_lock = PTHREAD_MUTEX_INITIALIZER;

/* Imports the file at name (data NULL) or the size bytes at data (with the
 * format hint) into *sc, or sets err. */
static glint_rc import_locked(const char *name, const void *data, size_t size, const char *hint,
                              const struct aiScene **sc, glint_error *err)
{
    glint_rc rc = GLINT_OK;
    pthread_mutex_lock(&import_lock);
    *sc = data ? aiImportFileFromMemory(data, (unsigned)size, import_flags, hint)
               : aiImportFile(name, import_flags);
    if (!*sc)
        rc = import_error(name, aiGetErrorString(), err);
    pthread_mutex_unlock(&import_lock);
    return rc;
}

glint_rc mesh_import(const char *path, mesh_file *out, glint_error *err)
{
    memset(out, 0, sizeof *out);
    int probe;
    glint_error perr = {0};
    if (load_open_regular(path, &probe, &perr) != GLINT_OK)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot open mesh: %s", path, perr.msg);
    close(probe);
    const struct aiScene *sc;
    glint_rc rc = import_locked(path, NULL, 0, NULL, &sc, err);
    return rc == GLINT_OK ? convert(sc, path, out, err) : rc;
}

glint_rc mesh_import_memory(const void *data, size_t size, const char *name, mesh_file *out,
                            glint_error *err)
{
    memset(out, 0, sizeof *out);
    const char *dot = strrchr(name, '.');
    const char *slash = strrchr(name, '/');
    const char *hint = dot && (!slash || dot > slash) ? dot + 1 : "";
    if (size == 0 || size > UINT_MAX)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot import mesh: %s", name,
                       size ? "file too large" : "file is empty");
    const struct aiScene *sc;
    glint_rc rc = import_locked(name, data, size, hint, &sc, err);
    return rc == GLINT_OK ? convert(sc, name, out, err) : rc;
}

glint_rc mesh_file_add(scene *s, mesh_file *f, int *index, glint_error *err)
{
    int base = scene_material_count(s);
    for (int i = 0; i < f->nmaterials; i++)
        if (scene_add_material(s, &f->materials[i]) < 0)
            return err_nomem(err);
    for (int t = 0; t < f->mesh->ntris; t++)
        f->mesh->tri_material[t] += base;
    *index = scene_add_mesh(s, f->mesh);
    if (*index < 0)
        return err_nomem(err);
    f->mesh = NULL;
    return GLINT_OK;
}

void mesh_file_free(mesh_file *f)
{
    if (f->mesh) {
        mesh_free(f->mesh);
        free(f->mesh);
    }
    free(f->materials);
    memset(f, 0, sizeof *f);
}

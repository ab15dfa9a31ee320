#include "mesh_assimp.h"

#include <fcntl.h>
#include <limits.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/error.h"
#include "load/assimp_load.h"
#include "load/mesh_join.h"
#include "load/mesh_material.h"
#include "load/mesh_normals.h"

/* Deepest node hierarchy followed; a deeper one is refused. */
#define NODE_DEPTH_MAX 256

/* ---- files: regular files only, opened without blocking --------------- */

static size_t f_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    return fread(buf, size, count, (FILE *)f->UserData);
}

static size_t f_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0;
}

static size_t f_tell(struct aiFile *f)
{
    long at = ftell((FILE *)f->UserData);
    return at < 0 ? 0 : (size_t)at;
}

static size_t f_size(struct aiFile *f)
{
    struct stat st;
    return fstat(fileno((FILE *)f->UserData), &st) == 0 ? (size_t)st.st_size : 0;
}

static enum aiReturn f_seek(struct aiFile *f, size_t off, enum aiOrigin origin)
{
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    if (off > LONG_MAX)
        return aiReturn_FAILURE;
    return fseek((FILE *)f->UserData, (long)off, whence) == 0 ? aiReturn_SUCCESS
                                                               : aiReturn_FAILURE;
}

static void f_flush(struct aiFile *f) { (void)f; }

/* io->UserData points at a bool set when an open failed for want of memory. */
static struct aiFile *f_open(struct aiFileIO *io, const char *name, const char *mode)
{
    if (strpbrk(mode, "wa+"))
        return NULL;
    int fd = open(name, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0)
        return NULL;
    struct stat st;
    int fl = fcntl(fd, F_GETFL);
    FILE *fp = NULL;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && fl >= 0 &&
        fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) == 0)
        fp = fdopen(fd, "rb");
    struct aiFile *f = fp ? calloc(1, sizeof *f) : NULL;
    if (!f) {
        if (fp)
            fclose(fp);
        else
            close(fd);
        if (fp)
            *(bool *)io->UserData = true;
        return NULL;
    }
    *f = (struct aiFile){f_read, f_write, f_tell, f_size, f_seek, f_flush, (aiUserData)fp};
    return f;
}

static void f_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (f) {
        fclose((FILE *)f->UserData);
        free(f);
    }
}

/* ---- transforms --------------------------------------------------------- */

typedef struct xf {
    double m[3][4]; /* rows of an affine map */
    double n[3][3]; /* its normal matrix: the inverse transpose, up to a positive scale */
} xf;

static void xf_from(xf *x, const struct aiMatrix4x4 *a)
{
    const ai_real r[3][4] = {{a->a1, a->a2, a->a3, a->a4},
                             {a->b1, a->b2, a->b3, a->b4},
                             {a->c1, a->c2, a->c3, a->c4}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            x->m[i][j] = r[i][j];
    /* cofactors of the 3x3 part, times the sign of its determinant */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            x->n[i][j] = x->m[i1][j1] * x->m[i2][j2] - x->m[i1][j2] * x->m[i2][j1];
        }
    double det = x->m[0][0] * x->n[0][0] + x->m[0][1] * x->n[0][1] + x->m[0][2] * x->n[0][2];
    if (det < 0)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                x->n[i][j] = -x->n[i][j];
}

static void xf_point(const xf *x, const struct aiVector3D *p, double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = x->m[i][0] * p->x + x->m[i][1] * p->y + x->m[i][2] * p->z + x->m[i][3];
}

static void xf_normal(const xf *x, const struct aiVector3D *v, double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = x->n[i][0] * v->x + x->n[i][1] * v->y + x->n[i][2] * v->z;
}

static void mat_mul(struct aiMatrix4x4 *dst, const struct aiMatrix4x4 *a,
                    const struct aiMatrix4x4 *b)
{
    const ai_real *pa = &a->a1, *pb = &b->a1;
    ai_real r[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[i * 4 + j] = pa[i * 4] * pb[j] + pa[i * 4 + 1] * pb[4 + j] +
                           pa[i * 4 + 2] * pb[8 + j] + pa[i * 4 + 3] * pb[12 + j];
    memcpy(&dst->a1, r, sizeof r);
}

/* The node's transform to the scene's root, through at most NODE_DEPTH_MAX parents. */
static void node_global(const struct aiNode *n, struct aiMatrix4x4 *out)
{
    *out = n->mTransformation;
    n = n->mParent;
    for (int d = 0; n && d < NODE_DEPTH_MAX; d++, n = n->mParent)
        mat_mul(out, &n->mTransformation, out);
}

static const struct aiNode *find_node(const struct aiNode *n, const struct aiString *name,
                                      int depth)
{
    if (n->mName.length == name->length && memcmp(n->mName.data, name->data, name->length) == 0)
        return n;
    for (unsigned i = 0; depth < NODE_DEPTH_MAX && i < n->mNumChildren; i++) {
        const struct aiNode *f = find_node(n->mChildren[i], name, depth + 1);
        if (f)
            return f;
    }
    return NULL;
}

/* ---- meshes ------------------------------------------------------------- */

typedef struct walk {
    const struct aiScene *sc;
    mesh_data *md;
    uint64_t nverts, ntris; /* counted, then filled */
    uint32_t flags;
    float smooth_angle;
    bool fill, too_deep;
    double (*skin_p)[4];    /* scratch for skinned meshes: position and weight */
    double (*skin_n)[3];
} walk;

/* Only triangles are kept. Triangulation marks meshes that held polygons
 * with aiPrimitiveType_NGONEncodingFlag (assimp 5.1 and later), which says
 * how they were made, not what they are. */
static bool is_triangle_mesh(const struct aiMesh *am)
{
    return (am->mPrimitiveTypes & ~(unsigned)aiPrimitiveType_NGONEncodingFlag) ==
           aiPrimitiveType_TRIANGLE;
}

static void put3(float out[3], const double v[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = isfinite(v[k]) && fabs(v[k]) < 3.0e38 ? (float)v[k] : NAN;
}

/* Poses a skinned mesh: each vertex is the weighted sum of its bones'
 * transforms (the bone node's place times the bone's offset) applied to it.
 * Vertices no bone holds stay with the mesh's node. Returns false when the
 * scratch arrays cannot be had. */
static bool skin(walk *w, const struct aiMesh *am, const xf *node)
{
    unsigned nv = am->mNumVertices;
    w->skin_p = calloc(nv, sizeof *w->skin_p);
    w->skin_n = calloc(nv, sizeof *w->skin_n);
    if (!w->skin_p || !w->skin_n)
        return false;
    for (unsigned b = 0; b < am->mNumBones; b++) {
        const struct aiBone *bone = am->mBones[b];
        const struct aiNode *bn = find_node(w->sc->mRootNode, &bone->mName, 0);
        if (!bn)
            continue;
        struct aiMatrix4x4 g;
        node_global(bn, &g);
        mat_mul(&g, &g, &bone->mOffsetMatrix);
        xf x;
        xf_from(&x, &g);
        for (unsigned i = 0; i < bone->mNumWeights; i++) {
            unsigned v = bone->mWeights[i].mVertexId;
            double wt = bone->mWeights[i].mWeight, p[3], n[3] = {0, 0, 0};
            if (v >= nv || !(wt > 0) || !isfinite(wt))
                continue;
            xf_point(&x, &am->mVertices[v], p);
            if (am->mNormals)
                xf_normal(&x, &am->mNormals[v], n);
            for (int k = 0; k < 3; k++) {
                w->skin_p[v][k] += wt * p[k];
                w->skin_n[v][k] += wt * n[k];
            }
            w->skin_p[v][3] += wt;
        }
    }
    for (unsigned v = 0; v < nv; v++) {
        double p[3], n[3] = {0, 0, 0};
        if (w->skin_p[v][3] > 0)
            continue;
        xf_point(node, &am->mVertices[v], p);
        if (am->mNormals)
            xf_normal(node, &am->mNormals[v], n);
        memcpy(w->skin_p[v], p, sizeof p);
        memcpy(w->skin_n[v], n, sizeof n);
        w->skin_p[v][3] = 1;
    }
    return true;
}

static void fill_vertex(walk *w, const struct aiMesh *am, const xf *x, unsigned v, uint32_t at)
{
    mesh_data *md = w->md;
    double p[3], n[3] = {0, 0, 0};
    if (w->skin_p) {
        for (int k = 0; k < 3; k++) {
            p[k] = w->skin_p[v][k] / w->skin_p[v][3];
            n[k] = w->skin_n[v][k];
        }
    } else {
        xf_point(x, &am->mVertices[v], p);
        if (am->mNormals)
            xf_normal(x, &am->mNormals[v], n);
    }
    put3(md->pos[at], p);
    if (md->nrm) {
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++)
            n[k] = len > 0 && isfinite(len) ? n[k] / len : 0;
        put3(md->nrm[at], n);
    }
    if (md->uv) { /* (0, 0) where this mesh has none: the slot may hold another's */
        const struct aiVector3D *t = am->mTextureCoords[0] ? &am->mTextureCoords[0][v] : NULL;
        md->uv[at][0] = t ? (float)t->x : 0.0f;
        md->uv[at][1] = t ? (float)t->y : 0.0f;
    }
    if (md->col) {
        const struct aiColor4D *c = am->mColors[0] ? &am->mColors[0][v] : NULL;
        float rgb[3] = {c ? c->r : 1, c ? c->g : 1, c ? c->b : 1};
        for (int k = 0; k < 3; k++)
            md->col[at][k] = isfinite(rgb[k]) ? fminf(fmaxf(rgb[k], 0), 1) : 1;
    }
}

/* One placement of one mesh: counted, or copied with its transform. */
static bool visit_mesh(walk *w, const struct aiMesh *am, const struct aiMatrix4x4 *g)
{
    if (!is_triangle_mesh(am))
        return true;
    if (!w->fill) {
        /* room for the vertices split by mesh_normals_crease */
        uint64_t room = am->mNormals ? 0 : 3ull * am->mNumFaces;
        w->nverts += room > am->mNumVertices ? room : am->mNumVertices;
        w->ntris += am->mNumFaces;
        w->flags |= MESH_HAS_NORMALS | (am->mTextureCoords[0] ? MESH_HAS_UV : 0) |
                    (am->mColors[0] ? MESH_HAS_COLORS : 0);
        return true;
    }
    mesh_data *md = w->md;
    xf x;
    xf_from(&x, g);
    if (am->mNumBones > 0) {
        md->skinned++;
        if (!skin(w, am, &x))
            return false;
    }
    uint32_t base = (uint32_t)w->nverts;
    for (unsigned v = 0; v < am->mNumVertices; v++)
        fill_vertex(w, am, &x, v, base + v);
    uint32_t mat = am->mMaterialIndex < md->nmats ? am->mMaterialIndex : 0;
    uint32_t t0 = (uint32_t)w->ntris, nv = am->mNumVertices;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3 || face->mIndices[0] >= am->mNumVertices ||
            face->mIndices[1] >= am->mNumVertices || face->mIndices[2] >= am->mNumVertices) {
            md->dropped++;
            continue;
        }
        for (int k = 0; k < 3; k++)
            md->tri[w->ntris][k] = base + face->mIndices[k];
        md->tri_mat[w->ntris++] = mat;
    }
    if (!mesh_join_vertices(md, base, &nv, t0, (uint32_t)w->ntris))
        return false;
    if (!am->mNormals &&
        !mesh_normals_crease(md, base, &nv, t0, (uint32_t)w->ntris, w->smooth_angle))
        return false;
    w->nverts += nv;
    free(w->skin_p);
    free(w->skin_n);
    w->skin_p = NULL;
    w->skin_n = NULL;
    return true;
}

static bool walk_node(walk *w, const struct aiNode *n, const struct aiMatrix4x4 *parent,
                      int depth)
{
    if (depth > NODE_DEPTH_MAX) {
        w->too_deep = true;
        return false;
    }
    struct aiMatrix4x4 g;
    mat_mul(&g, parent, &n->mTransformation);
    for (unsigned i = 0; i < n->mNumMeshes; i++)
        if (n->mMeshes[i] < w->sc->mNumMeshes && !visit_mesh(w, w->sc->mMeshes[n->mMeshes[i]], &g))
            return false;
    for (unsigned i = 0; i < n->mNumChildren; i++)
        if (!walk_node(w, n->mChildren[i], &g, depth + 1))
            return false;
    return true;
}

static glint_rc gather(const struct aiScene *sc, const char *name, const mesh_assimp_opts *opts,
                       mesh_data *md, glint_error *err)
{
    struct aiMatrix4x4 id;
    aiIdentityMatrix4(&id);
    walk w = {.sc = sc, .md = md, .smooth_angle = opts->smooth_angle};
    if (!sc->mRootNode || !walk_node(&w, sc->mRootNode, &id, 0))
        return err_set(err, GLINT_ERR_INPUT, "%s: the node hierarchy is deeper than %d", name,
                       NODE_DEPTH_MAX);
    if (w.ntris == 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: mesh has no triangles", name);
    if (w.ntris > opts->max_triangles || w.nverts > UINT32_MAX / 2)
        return err_set(err, GLINT_ERR_INPUT,
                       "%s: mesh is too large (%llu triangles, limit %llu; GLINT_MESH_TRIANGLES "
                       "raises it)",
                       name, (unsigned long long)w.ntris, (unsigned long long)opts->max_triangles);
    md->nverts = (uint32_t)w.nverts;
    md->ntris = (uint32_t)w.ntris;
    md->flags = w.flags;
    glint_rc rc = mesh_material_gather(sc, name, md, err);
    if (rc == GLINT_OK)
        rc = mesh_data_alloc(md, err);
    if (rc != GLINT_OK)
        return rc;
    w.fill = true;
    w.nverts = w.ntris = 0;
    if (!walk_node(&w, sc->mRootNode, &id, 0)) {
        free(w.skin_p);
        free(w.skin_n);
        return err_nomem(err);
    }
    md->ntris = (uint32_t)w.ntris;
    md->nverts = (uint32_t)w.nverts;
    return GLINT_OK;
}

/* Normals are not asked of assimp: mesh_normals computes them with a
 * crease angle where the file has none. */
/* assimp's validation of a file without faces or meshes speaks of its own
 * structures ("Mesh  contains no faces", "aiScene::mNumMeshes is 0"); the
 * user is told what the documentation says. Memory running out in assimp
 * is out of memory, not bad input. */
static glint_rc import_error(const char *name, const char *why, glint_error *err)
{
    if (strstr(why, "contains no faces") || strstr(why, "mNumMeshes is 0"))
        return err_set(err, GLINT_ERR_INPUT, "%s: mesh has no triangles", name);
    if (strstr(why, "bad_alloc")) /* a C++ allocation failed inside assimp */
        return err_nomem(err);
    return err_set(err, GLINT_ERR_INPUT, "%s: cannot import mesh: %s", name, why);
}

/* Vertices are joined by mesh_join, not assimp's JoinIdenticalVertices
 * (which took a third of the bunny's import). */
static const unsigned import_flags =
    aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;

glint_rc mesh_assimp_read(const char *name, const void *data, size_t size,
                          const mesh_assimp_opts *opts, mesh_data *out, glint_error *err)
{
    memset(out, 0, sizeof *out);
    const char *why_not = NULL;
    if (!assimp_load(&why_not))
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot import meshes: %s", name, why_not);
    struct aiPropertyStore *props = aiCreatePropertyStore();
    if (!props)
        return err_nomem(err);
    const struct aiScene *sc;
    bool nomem = false;
    if (data) {
        const char *dot = strrchr(name, '.'), *slash = strrchr(name, '/');
        const char *hint = dot && (!slash || dot > slash) ? dot + 1 : "";
        sc = size == 0 || size > UINT_MAX
                 ? NULL
                 : aiImportFileFromMemoryWithProperties(data, (unsigned)size, import_flags, hint,
                                                        props);
    } else {
        struct aiFileIO io = {f_open, f_close, (aiUserData)&nomem};
        sc = aiImportFileExWithProperties(name, import_flags, &io, props);
    }
    aiReleasePropertyStore(props);
    if (!sc && nomem)
        return err_nomem(err);
    if (!sc) {
        const char *why = data && size == 0 ? "file is empty"
                          : data && size > UINT_MAX ? "file too large"
                                                    : aiGetErrorString();
        return import_error(name, why, err);
    }
    glint_rc rc = gather(sc, name, opts, out, err);
    aiReleaseImport(sc);
    if (rc != GLINT_OK)
        mesh_data_free(out);
    return rc;
}

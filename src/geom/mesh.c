#include "mesh.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "geom/shape.h"
#include "geom/watertight.h"

static bool degenerate(vec3 a, vec3 b, vec3 c)
{
    if (!v3_is_finite(a) || !v3_is_finite(b) || !v3_is_finite(c))
        return true;
    vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    return !(v3_len2(n) > 0.0f);
}

glint_rc mesh_init(mesh *m, const char *name, int *dropped, glint_error *err)
{
    int kept = 0;
    for (int i = 0; i < m->ntris; i++) {
        const uint32_t *t = m->tri[i];
        if (t[0] >= (uint32_t)m->nverts || t[1] >= (uint32_t)m->nverts ||
            t[2] >= (uint32_t)m->nverts || degenerate(m->pos[t[0]], m->pos[t[1]], m->pos[t[2]]))
            continue;
        memmove(m->tri[kept], m->tri[i], sizeof m->tri[i]);
        if (m->tri_material)
            m->tri_material[kept] = m->tri_material[i];
        kept++;
    }
    if (dropped)
        *dropped = m->ntris - kept;
    m->ntris = kept;
    if (kept == 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: mesh has no usable triangles", name);

    aabb *boxes = malloc(sizeof *boxes * (size_t)kept);
    if (!boxes)
        return err_nomem(err);
    m->bounds = aabb_empty();
    for (int i = 0; i < kept; i++) {
        const uint32_t *t = m->tri[i];
        aabb b = aabb_point(m->pos[t[0]]);
        b = aabb_grow(aabb_grow(b, m->pos[t[1]]), m->pos[t[2]]);
        boxes[i] = b;
        m->bounds = aabb_union(m->bounds, b);
    }
    bvh bin;
    glint_rc rc = bvh_build(&bin, boxes, kept, err);
    free(boxes);
    if (rc != GLINT_OK)
        return rc;
    /* Store triangles in leaf order so a leaf's corners are read in sequence. */
    uint32_t(*tri)[3] = malloc(sizeof *tri * (size_t)kept);
    int32_t *tmat = m->tri_material ? malloc(sizeof *tmat * (size_t)kept) : NULL;
    if (!tri || (m->tri_material && !tmat)) {
        free(tri);
        free(tmat);
        bvh_free(&bin);
        return err_nomem(err);
    }
    for (int i = 0; i < kept; i++) {
        memcpy(tri[i], m->tri[bin.prims[i]], sizeof tri[i]);
        if (tmat)
            tmat[i] = m->tri_material[bin.prims[i]];
        bin.prims[i] = i;
    }
    free(m->tri);
    free(m->tri_material);
    m->tri = tri;
    m->tri_material = tmat;
    return bvh4_from_bvh(&m->bvh, &bin, err);
}

void mesh_free(mesh *m)
{
    if (!m)
        return;
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->tri);
    free(m->tri_material);
    bvh4_free(&m->bvh);
    memset(m, 0, sizeof *m);
}

size_t mesh_bytes(const mesh *m)
{
    size_t n = (size_t)m->nverts * sizeof(vec3) + (size_t)m->ntris * sizeof m->tri[0];
    if (m->nrm)
        n += (size_t)m->nverts * sizeof(vec3);
    if (m->uv)
        n += (size_t)m->nverts * sizeof m->uv[0];
    if (m->tri_material)
        n += (size_t)m->ntris * sizeof(int32_t);
    n += (size_t)m->bvh.nnodes * sizeof(bvh4_node) + (size_t)m->bvh.nprims * sizeof(int32_t);
    return n;
}

typedef struct leaf_ctx {
    const mesh *m;
    tri_ray tr;
    shape_hit *hit;
} leaf_ctx;

/* Triangles of a leaf are consecutive (mesh_init stored them in leaf
 * order), so prims[0] is the first and the rest follow. */
__attribute__((always_inline)) static inline bool leaf_closest(void *ctx, const int32_t *prims, uint32_t count, float tmin,
                                float *tmax)
{
    leaf_ctx *c = ctx;
    bool found = false;
    for (int32_t i = prims[0]; i < prims[0] + (int32_t)count; i++) {
        const uint32_t *t = c->m->tri[i];
        float tt, b1, b2;
        if (tri_intersect(&c->tr, c->m->pos[t[0]], c->m->pos[t[1]], c->m->pos[t[2]], tmin, *tmax,
                          &tt, &b1, &b2)) {
            *tmax = tt;
            c->hit->t = tt;
            c->hit->part = i;
            c->hit->b1 = b1;
            c->hit->b2 = b2;
            found = true;
        }
    }
    return found;
}

__attribute__((always_inline)) static inline bool leaf_any(void *ctx, const int32_t *prims, uint32_t count, float tmin,
                            float *tmax)
{
    leaf_ctx *c = ctx;
    for (int32_t i = prims[0]; i < prims[0] + (int32_t)count; i++) {
        const uint32_t *t = c->m->tri[i];
        float tt, b1, b2;
        if (tri_intersect(&c->tr, c->m->pos[t[0]], c->m->pos[t[1]], c->m->pos[t[2]], tmin, *tmax,
                          &tt, &b1, &b2))
            return true;
    }
    return false;
}

bool mesh_intersect(const mesh *m, const ray *r, shape_hit *hit)
{
    leaf_ctx c = {m, tri_ray_make(r), hit};
    float tmax = r->tmax;
    return bvh4_traverse(&m->bvh, r->o, r->d, r->tmin, &tmax, false, leaf_closest, &c);
}

bool mesh_occluded(const mesh *m, const ray *r)
{
    leaf_ctx c = {m, tri_ray_make(r), NULL};
    float tmax = r->tmax;
    return bvh4_traverse(&m->bvh, r->o, r->d, r->tmin, &tmax, true, leaf_any, &c);
}

void mesh_surface(const mesh *m, vec3 p, const shape_hit *hit, surface *out)
{
    const uint32_t *t = m->tri[hit->part];
    float b1 = hit->b1, b2 = hit->b2, b0 = 1.0f - b1 - b2;
    vec3 p0 = m->pos[t[0]], p1 = m->pos[t[1]], p2 = m->pos[t[2]];
    out->p = p;
    out->ng = v3_norm(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
    out->n = out->ng;
    if (m->nrm) {
        vec3 n = v3_add(v3_add(v3_scale(m->nrm[t[0]], b0), v3_scale(m->nrm[t[1]], b1)),
                        v3_scale(m->nrm[t[2]], b2));
        if (v3_len2(n) > 0.0f)
            out->n = v3_norm(n);
    }
    if (m->uv) {
        out->u = b0 * m->uv[t[0]][0] + b1 * m->uv[t[1]][0] + b2 * m->uv[t[2]][0];
        out->v = b0 * m->uv[t[0]][1] + b1 * m->uv[t[1]][1] + b2 * m->uv[t[2]][1];
    } else {
        out->u = b1;
        out->v = b2;
    }
}

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
    glint_rc rc = bvh_build(&m->bvh, boxes, kept, err);
    free(boxes);
    if (rc != GLINT_OK)
        return rc;
    /* Store triangles in leaf order so a leaf's corners are read in sequence. */
    uint32_t(*tri)[3] = malloc(sizeof *tri * (size_t)kept);
    int32_t *tmat = m->tri_material ? malloc(sizeof *tmat * (size_t)kept) : NULL;
    if (!tri || (m->tri_material && !tmat)) {
        free(tri);
        free(tmat);
        return err_nomem(err);
    }
    for (int i = 0; i < kept; i++) {
        memcpy(tri[i], m->tri[m->bvh.prims[i]], sizeof tri[i]);
        if (tmat)
            tmat[i] = m->tri_material[m->bvh.prims[i]];
        m->bvh.prims[i] = i;
    }
    free(m->tri);
    free(m->tri_material);
    m->tri = tri;
    m->tri_material = tmat;
    return GLINT_OK;
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
    bvh_free(&m->bvh);
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
    n += (size_t)m->bvh.nnodes * sizeof(bvh_node) + (size_t)m->bvh.nprims * sizeof(int32_t);
    return n;
}

/* The same ordered traversal as the scene's (scene.c); triangles in a leaf
 * are consecutive because mesh_init stored them in leaf order. */
bool mesh_intersect(const mesh *m, const ray *r, shape_hit *hit)
{
    tri_ray tr = tri_ray_make(r);
    vec3 inv_d = v3(1.0f / r->d.x, 1.0f / r->d.y, 1.0f / r->d.z);
    bool neg[3] = {inv_d.x < 0.0f, inv_d.y < 0.0f, inv_d.z < 0.0f};
    float tmax = r->tmax;
    bool found = false;
    int stack[BVH_MAX_DEPTH];
    int sp = 0, node = 0;
    for (;;) {
        const bvh_node *nd = &m->bvh.nodes[node];
        if (aabb_hit(nd->box, r->o, inv_d, r->tmin, tmax)) {
            if (nd->count) {
                for (int i = nd->index; i < nd->index + nd->count; i++) {
                    const uint32_t *t = m->tri[i];
                    float tt, b1, b2;
                    if (tri_intersect(&tr, m->pos[t[0]], m->pos[t[1]], m->pos[t[2]], r->tmin, tmax,
                                      &tt, &b1, &b2)) {
                        tmax = tt;
                        hit->t = tt;
                        hit->part = i;
                        hit->b1 = b1;
                        hit->b2 = b2;
                        found = true;
                    }
                }
            } else if (neg[nd->axis]) {
                stack[sp++] = node + 1;
                node = nd->index;
                continue;
            } else {
                stack[sp++] = nd->index;
                node = node + 1;
                continue;
            }
        }
        if (sp == 0)
            return found;
        node = stack[--sp];
    }
}

bool mesh_occluded(const mesh *m, const ray *r)
{
    tri_ray tr = tri_ray_make(r);
    vec3 inv_d = v3(1.0f / r->d.x, 1.0f / r->d.y, 1.0f / r->d.z);
    int stack[BVH_MAX_DEPTH];
    int sp = 0, node = 0;
    for (;;) {
        const bvh_node *nd = &m->bvh.nodes[node];
        if (aabb_hit(nd->box, r->o, inv_d, r->tmin, r->tmax)) {
            if (nd->count == 0) {
                stack[sp++] = nd->index;
                node = node + 1;
                continue;
            }
            for (int i = nd->index; i < nd->index + nd->count; i++) {
                const uint32_t *t = m->tri[i];
                float tt, b1, b2;
                if (tri_intersect(&tr, m->pos[t[0]], m->pos[t[1]], m->pos[t[2]], r->tmin, r->tmax,
                                  &tt, &b1, &b2))
                    return true;
            }
        }
        if (sp == 0)
            return false;
        node = stack[--sp];
    }
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

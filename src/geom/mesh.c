#include "mesh.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "geom/shape.h"
#include "geom/tri4.h"

static bool degenerate(vec3 a, vec3 b, vec3 c)
{
    if (!v3_is_finite(a) || !v3_is_finite(b) || !v3_is_finite(c))
        return true;
    vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    return !(v3_len2(n) > 0.0f);
}

/* Copies each leaf's triangles into tri4 blocks, in node order, and
 * renumbers the leaf to its first block, so traversal reaches the corners
 * without going through prims (which is then freed). */
static glint_rc make_blocks(mesh *m, glint_error *err)
{
    bvh4 *b = &m->bvh;
    size_t n = 0;
    for (int i = 0; i < b->nnodes; i++)
        for (int k = 0; k < 4; k++)
            if (b->nodes[i].child[k] < 0)
                n += (b->nodes[i].count[k] + 3) / 4;
    m->blocks = aligned_alloc(16, (n ? n : 1) * sizeof *m->blocks);
    if (!m->blocks)
        return err_nomem(err);
    memset(m->blocks, 0, (n ? n : 1) * sizeof *m->blocks);
    m->nblocks = (int)n;
    int next = 0;
    for (int i = 0; i < b->nnodes; i++)
        for (int k = 0; k < 4; k++) {
            int32_t c = b->nodes[i].child[k];
            uint32_t count = b->nodes[i].count[k];
            if (c >= 0 || count == 0)
                continue;
            int32_t t0 = b->prims[-1 - c]; /* triangles are in leaf order: t0 .. t0 + count */
            b->nodes[i].child[k] = -1 - next;
            for (uint32_t j = 0; j < count; j += 4, next++) {
                tri4 *blk = &m->blocks[next];
                for (int lane = 0; lane < 4; lane++) {
                    blk->id[lane] = j + (uint32_t)lane < count ? t0 + (int32_t)(j + lane) : -1;
                    if (blk->id[lane] < 0)
                        continue;
                    for (int corner = 0; corner < 3; corner++) {
                        vec3 p = m->pos[m->tri[blk->id[lane]][corner]];
                        blk->p[corner][0][lane] = p.x;
                        blk->p[corner][1][lane] = p.y;
                        blk->p[corner][2][lane] = p.z;
                    }
                }
            }
        }
    free(b->prims);
    b->prims = NULL;
    b->nprims = 0;
    return GLINT_OK;
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
    glint_rc rc = bvh_build_blocked(&bin, boxes, kept, 4, err);
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
    glint_rc rc2 = bvh4_from_bvh(&m->bvh, &bin, err);
    return rc2 == GLINT_OK ? make_blocks(m, err) : rc2;
}

void mesh_free(mesh *m)
{
    if (!m)
        return;
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->col);
    free(m->tri);
    free(m->tri_material);
    free(m->blocks);
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
    if (m->col)
        n += (size_t)m->nverts * sizeof(vec3);
    if (m->tri_material)
        n += (size_t)m->ntris * sizeof(int32_t);
    n += (size_t)m->bvh.nnodes * sizeof(bvh4_node) + (size_t)m->bvh.nprims * sizeof(int32_t);
    n += (size_t)m->nblocks * sizeof(tri4);
    return n;
}

typedef struct leaf_ctx {
    const mesh *m;
    tri4_ray q;
    shape_hit *hit;
} leaf_ctx;

/* A leaf's count triangles fill (count + 3) / 4 blocks from block first. */
__attribute__((always_inline)) static inline bool leaf_closest(void *ctx, uint32_t first,
                                                               uint32_t count, float tmin,
                                                               float *tmax)
{
    leaf_ctx *c = ctx;
    const tri4 *blk = &c->m->blocks[first];
    bool found = false;
    for (uint32_t j = 0; j < count; j += 4, blk++) {
        float t[4], b1[4], b2[4];
        int mask = tri4_intersect(&c->q, blk, tmin, *tmax, t, b1, b2);
        for (int k = 0; mask; k++, mask >>= 1)
            if ((mask & 1) && t[k] < *tmax) {
                *tmax = t[k];
                c->hit->t = t[k];
                c->hit->part = blk->id[k];
                c->hit->b1 = b1[k];
                c->hit->b2 = b2[k];
                found = true;
            }
    }
    return found;
}

__attribute__((always_inline)) static inline bool leaf_any(void *ctx, uint32_t first,
                                                           uint32_t count, float tmin, float *tmax)
{
    leaf_ctx *c = ctx;
    const tri4 *blk = &c->m->blocks[first];
    for (uint32_t j = 0; j < count; j += 4, blk++) {
        float t[4], b1[4], b2[4];
        if (tri4_intersect(&c->q, blk, tmin, *tmax, t, b1, b2))
            return true;
    }
    return false;
}

bool mesh_intersect(const mesh *m, const ray *r, shape_hit *hit)
{
    leaf_ctx c = {m, tri4_ray_make(r), hit};
    float tmax = r->tmax;
    return bvh4_traverse(&m->bvh, r->o, r->d, r->tmin, &tmax, false, leaf_closest, &c);
}

bool mesh_occluded(const mesh *m, const ray *r)
{
    leaf_ctx c = {m, tri4_ray_make(r), NULL};
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
    if (m->col)
        out->color = v3_add(v3_add(v3_scale(m->col[t[0]], b0), v3_scale(m->col[t[1]], b1)),
                            v3_scale(m->col[t[2]], b2));
    if (m->uv) {
        out->u = b0 * m->uv[t[0]][0] + b1 * m->uv[t[1]][0] + b2 * m->uv[t[2]][0];
        out->v = b0 * m->uv[t[0]][1] + b1 * m->uv[t[1]][1] + b2 * m->uv[t[2]][1];
    } else {
        out->u = b1;
        out->v = b2;
    }
}

#include "mesh.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "geom/shape.h"
#include "geom/tri4.h"
#include "mesh_trace.h"


/* Copies each leaf's triangles into tri4 blocks, in node order, and
 * renumbers the leaf to its first block, so traversal reaches the corners
 * without going through prims (which is then freed). */
static glint_rc make_blocks(mesh *m, glint_error *err)
{
    bvhw *b = &m->bvh;
    size_t n = 0;
    for (int i = 0; i < b->nnodes; i++)
        for (int k = 0; k < b->width; k++)
            if (*bvhw_child(b, i, k) < 0)
                n += (bvhw_count(b, i, k) + 3) / 4;
    /* On a cache line, so that each block lies in the three lines the walk
     * fetches ahead (aligned_alloc wants a whole number of alignments). */
    size_t bytes = (n ? n : 1) * sizeof *m->blocks;
    m->blocks = aligned_alloc(64, (bytes + 63) / 64 * 64);
    if (!m->blocks)
        return err_nomem(err);
    memset(m->blocks, 0, bytes);
    m->nblocks = (int)n;
    b->leaf_data = m->blocks;
    b->leaf_stride = sizeof *m->blocks;
    int next = 0;
    for (int i = 0; i < b->nnodes; i++)
        for (int k = 0; k < b->width; k++) {
            int32_t *c = bvhw_child(b, i, k);
            uint32_t count = bvhw_count(b, i, k);
            if (*c >= 0 || count == 0)
                continue;
            int32_t t0 = b->prims[-1 - *c]; /* triangles are in leaf order: t0 .. t0 + count */
            *c = -1 - next;
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

glint_rc mesh_init(mesh *m, const char *name, int threads, int *dropped, glint_error *err)
{
    int kept = 0;
    for (int i = 0; i < m->ntris; i++) {
        const uint32_t *t = m->tri[i];
        if (t[0] >= (uint32_t)m->nverts || t[1] >= (uint32_t)m->nverts ||
            t[2] >= (uint32_t)m->nverts)
            continue;
        triangle_fit fit = triangle_check(m->pos[t[0]], m->pos[t[1]], m->pos[t[2]]);
        if (fit == TRIANGLE_TOO_LARGE) /* dropping it silently would leave a hole */
            return err_set(err, GLINT_ERR_INPUT,
                           "%s: triangle %d is too large for single precision (its normal "
                           "overflows); scale the model down",
                           name, i + 1);
        if (fit == TRIANGLE_DEGENERATE)
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
    glint_rc rc = bvh_build_threads(&bin, boxes, kept, 4, threads, err);
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
    glint_rc rc2 = bvhw_from_bvh(&m->bvh, &bin, accel_isa_active(), true, err);
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
    bvhw_free(&m->bvh);
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
    n += bvhw_node_bytes(&m->bvh) + (size_t)m->bvh.nprims * sizeof(int32_t);
    n += (size_t)m->nblocks * sizeof(tri4);
    return n;
}

MESH_KERNELS(sse, 4)

bool mesh_intersect(const mesh *m, const ray *r, shape_hit *hit)
{
    accel_isa isa = m->bvh.isa;
#if defined(GLINT_WIDE_KERNELS)
    if (isa == ACCEL_AVX512)
        return mesh_intersect_avx512(m, r, hit);
    if (isa == ACCEL_AVX2)
        return mesh_intersect_avx2(m, r, hit);
#endif
    return isa == ACCEL_SCALAR ? mesh_intersect_scalar(m, r, hit) : mesh_intersect_sse(m, r, hit);
}

int mesh_intersect8(const mesh *m, const ray8 *r, int active, shape_hit *hit)
{
    int found = -1;
#if defined(GLINT_WIDE_KERNELS)
    if (m->bvh.isa == ACCEL_AVX512)
        found = mesh_intersect8_avx512(m, r, active, hit);
    else if (m->bvh.isa == ACCEL_AVX2)
        found = mesh_intersect8_avx2(m, r, active, hit);
#endif
    if (found >= 0)
        return found;
    found = 0;
    for (int k = 0; k < 8; k++) {
        if (!(active >> k & 1))
            continue;
        ray one = ray8_get(r, k);
        if (mesh_intersect(m, &one, &hit[k]))
            found |= 1 << k;
    }
    return found;
}

bool mesh_occluded(const mesh *m, const ray *r)
{
    accel_isa isa = m->bvh.isa;
#if defined(GLINT_WIDE_KERNELS)
    if (isa == ACCEL_AVX512)
        return mesh_occluded_avx512(m, r);
    if (isa == ACCEL_AVX2)
        return mesh_occluded_avx2(m, r);
#endif
    return isa == ACCEL_SCALAR ? mesh_occluded_scalar(m, r) : mesh_occluded_sse(m, r);
}

int mesh_crossings(const mesh *m, const ray *r, crossing *out, int max, bool *more)
{
    accel_isa isa = m->bvh.isa;
#if defined(GLINT_WIDE_KERNELS)
    if (isa == ACCEL_AVX512)
        return mesh_crossings_avx512(m, r, out, max, more);
    if (isa == ACCEL_AVX2)
        return mesh_crossings_avx2(m, r, out, max, more);
#endif
    return isa == ACCEL_SCALAR ? mesh_crossings_scalar(m, r, out, max, more)
                               : mesh_crossings_sse(m, r, out, max, more);
}

void mesh_surface(const mesh *m, vec3 p, const shape_hit *hit, surface *out)
{
    const uint32_t *t = m->tri[hit->part];
    float b1 = hit->b1, b2 = hit->b2, b0 = 1.0f - b1 - b2;
    vec3 p0 = m->pos[t[0]], p1 = m->pos[t[1]], p2 = m->pos[t[2]];
    (void)p; /* the point from the barycentrics, on the triangle (geom/shape.h) */
    out->p = v3_madd(v3_madd(p0, v3_sub(p1, p0), b1), v3_sub(p2, p0), b2);
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

/* ---- closedness --------------------------------------------------------- */

static int vec_cmp(const void *pa, const void *pb)
{
    const vec3 *a = *(const vec3 *const *)pa, *b = *(const vec3 *const *)pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    return (a->z > b->z) - (a->z < b->z);
}

typedef struct medge {
    uint32_t lo, hi;
    int dir; /* +1: lo -> hi, -1: hi -> lo */
} medge;

static int medge_cmp(const void *pa, const void *pb)
{
    const medge *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return (a->hi > b->hi) - (a->hi < b->hi);
}

/* Vertices at the same position count as one (files often repeat them
 * where normals or texture coordinates change), so each vertex is renamed
 * to the first of its position. */
static uint32_t *weld(const mesh *m)
{
    const vec3 **order = malloc(sizeof *order * (size_t)m->nverts);
    uint32_t *id = malloc(sizeof *id * (size_t)m->nverts);
    if (!order || !id) {
        free(order);
        free(id);
        return NULL;
    }
    for (int i = 0; i < m->nverts; i++)
        order[i] = &m->pos[i];
    qsort(order, (size_t)m->nverts, sizeof *order, vec_cmp);
    for (int i = 0; i < m->nverts; i++) {
        bool same = i > 0 && vec_cmp(&order[i], &order[i - 1]) == 0;
        id[order[i] - m->pos] = same ? id[order[i - 1] - m->pos] : (uint32_t)(order[i] - m->pos);
    }
    free(order);
    return id;
}

int mesh_open_edges(const mesh *m)
{
    uint32_t *id = weld(m);
    medge *e = malloc(sizeof *e * (size_t)m->ntris * 3);
    if (!id || !e) {
        free(id);
        free(e);
        return -1;
    }
    int n = 0;
    for (int t = 0; t < m->ntris; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = id[m->tri[t][k]], b = id[m->tri[t][(k + 1) % 3]];
            e[n++] = a < b ? (medge){a, b, 1} : (medge){b, a, -1};
        }
    qsort(e, (size_t)n, sizeof *e, medge_cmp);
    int bad = 0;
    for (int i = 0; i < n;) {
        int j = i, sum = 0;
        for (; j < n && e[j].lo == e[i].lo && e[j].hi == e[i].hi; j++)
            sum += e[j].dir;
        bad += j - i != 2 || sum != 0;
        i = j;
    }
    free(id);
    free(e);
    return bad;
}

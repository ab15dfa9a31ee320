/* scene_intersect8: eight rays' nearest hits at once. In a flat scene (one
 * leaf of objects, plus the unbounded ones) each object is tested in the
 * order scene_intersect tests it, a mesh against all eight rays in one
 * walk of its BVH (mesh_intersect8), any other object against each ray on
 * its own; a tree of one node likewise, leaf by leaf for the rays that
 * enter each; in a deeper scene each ray goes through scene_intersect. Either
 * way every ray gets the hit scene_intersect gives it, to the bit. */
#include <string.h>
#include "geom/mesh.h"
#include "scene_trace.h"

/* Object i's hits h[k] for the rays of `any`, kept by scene_hit_object's
 * rule; returns the rays whose hit it is now. */
static int packet_keep(int i, int any, const shape_hit h[8], float best[8], scene_hit hit[8])
{
    int found = 0;
    for (int m = any; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        if (h[k].t < best[k] || (h[k].t == best[k] && i < hit[k].object)) {
            best[k] = h[k].t;
            hit[k] = (scene_hit){h[k], i};
            found |= 1 << k;
        }
    }
    return found;
}

/* shape8_hit on the scene's path; -1 where it has none. */
static int shape8_hit(const scene *s, const shape *sh, const ray8 *r, const float lim[8],
                      int active, shape_hit h[8])
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return shape8_hit_avx512(sh, r, lim, active, h);
    if (s->bvh.isa == ACCEL_AVX2)
        return shape8_hit_avx2(sh, r, lim, active, h);
#endif
    (void)s, (void)sh, (void)r, (void)lim, (void)active, (void)h;
    return -1;
}

/* Object i against the rays of active, each searched up to best[k]: a
 * mesh against three or more of them in one walk, a sphere or a quad in
 * one test, anything else ray by ray. */
static int packet_object(const scene *s, int i, const ray8 *r, int active, float best[8],
                         scene_hit hit[8])
{
    const object *o = &s->objects[i];
    int found = 0;
    if (o->shape.kind == SHAPE_MESH && !o->moving && __builtin_popcount((unsigned)active) > 2) {
        ray8 lr;
        int first = __builtin_ctz((unsigned)active);
        for (int k = first; k < 8; k++) {
            if (!(active >> k & 1))
                continue;
            ray one = {v3(r->ox[k], r->oy[k], r->oz[k]), v3(r->dx[k], r->dy[k], r->dz[k]),
                       r->tmin[k], next_up(best[k]), 0.0f}; /* as scene_hit_object */
            ray l = scene_object_ray(s, o, &one);
            lr.ox[k] = l.o.x, lr.oy[k] = l.o.y, lr.oz[k] = l.o.z;
            lr.dx[k] = l.d.x, lr.dy[k] = l.d.y, lr.dz[k] = l.d.z;
            lr.tmin[k] = l.tmin, lr.tmax[k] = l.tmax;
        }
        for (int k = 0; k < 8; k++) /* idle lanes repeat an active ray */
            if (!(active >> k & 1)) {
                lr.ox[k] = lr.ox[first], lr.oy[k] = lr.oy[first], lr.oz[k] = lr.oz[first];
                lr.dx[k] = lr.dx[first], lr.dy[k] = lr.dy[first], lr.dz[k] = lr.dz[first];
                lr.tmin[k] = lr.tmin[first], lr.tmax[k] = lr.tmax[first];
            }
        shape_hit h[8];
        return packet_keep(i, mesh_intersect8(o->shape.mesh, &lr, active, h), h, best, hit);
    }
    if (o->xform < 0 && __builtin_popcount((unsigned)active) > 2) {
        float lim[8];
        for (int k = 0; k < 8; k++)
            lim[k] = next_up(best[k]); /* as scene_hit_object */
        shape_hit h[8];
        int any = shape8_hit(s, &o->shape, r, lim, active, h);
        if (any >= 0)
            return packet_keep(i, any, h, best, hit);
    }
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = {v3(r->ox[k], r->oy[k], r->oz[k]), v3(r->dx[k], r->dy[k], r->dz[k]),
                   r->tmin[k], best[k], r->time[k]};
        if (scene_hit_object(s, i, &one, one.tmin, &best[k], &hit[k]))
            found |= 1 << k;
    }
    return found;
}

/* The objects of leaf lane l of node 0 (none for an empty lane). */
static uint32_t node_leaf(const scene *s, int l, uint32_t *first)
{
    const bvhw *b = &s->bvh;
    int32_t c = b->width == 8 ? b->n8[0].child[l] : b->n4[0].child[l];
    uint32_t n = b->width == 8 ? b->n8[0].count[l] : b->n4[0].count[l];
    *first = c < 0 ? (uint32_t)(-1 - c) : 0;
    return c < 0 ? n : 0;
}

/* Whether the scene's tree is a single node, whose lanes are all leaves
 * (or the whole tree one leaf: flat). */
static bool one_node(const scene *s) { return !s->flat && s->bvh.nnodes == 1; }

static int node_leaves(const scene *s, const ray8 *r, int active, uint32_t first[8],
                       uint32_t count[8], int rays[8])
{
    accel_isa isa = s->bvh.isa;
#if defined(GLINT_WIDE_KERNELS)
    if (isa == ACCEL_AVX512)
        return scene_node_leaves_avx512(s, r, active, first, count, rays);
    if (isa == ACCEL_AVX2)
        return scene_node_leaves_avx2(s, r, active, first, count, rays);
#endif
    return isa == ACCEL_SCALAR ? scene_node_leaves_scalar(s, r, active, first, count, rays)
                               : scene_node_leaves_sse(s, r, active, first, count, rays);
}

bool scene_packets_pay(const scene *s)
{
    if (!s->flat && !one_node(s))
        return false;
    for (int l = 0; l < s->bvh.width; l++) {
        uint32_t first, n = s->flat ? (l == 0 ? scene_flat_leaf(s, &first) : 0)
                                    : node_leaf(s, l, &first);
        for (uint32_t i = 0; i < n; i++) {
            const object *o = &s->objects[s->bvh.prims[first + i]];
            shape_kind k = o->shape.kind;
            if (k == SHAPE_MESH && !o->moving &&
                (o->shape.mesh->bvh.isa == ACCEL_AVX2 || o->shape.mesh->bvh.isa == ACCEL_AVX512))
                return true;
            if ((k == SHAPE_SPHERE || k == SHAPE_QUAD) && o->xform < 0 &&
                (s->bvh.isa == ACCEL_AVX2 || s->bvh.isa == ACCEL_AVX512))
                return true;
        }
    }
    return false;
}

int scene_intersect8(const scene *s, const ray8 *r, int active, scene_hit *hit)
{
    int found = 0;
    if (!active)
        return 0;
    if (!s->flat && !one_node(s)) {
        for (int m = active; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ray one = {v3(r->ox[k], r->oy[k], r->oz[k]), v3(r->dx[k], r->dy[k], r->dz[k]),
                       r->tmin[k], r->tmax[k], r->time[k]};
            if (scene_intersect(s, &one, &hit[k]))
                found |= 1 << k;
        }
        return found;
    }
    float best[8];
    memcpy(best, r->tmax, sizeof best);
    for (int k = 0; k < 8; k++)
        hit[k].object = -1;
    for (int i = 0; i < s->nunbounded; i++)
        found |= packet_object(s, s->unbounded[i], r, active, best, hit);
    uint32_t first, n;
    if (s->flat) {
        n = scene_flat_leaf(s, &first);
        for (uint32_t i = 0; i < n; i++)
            found |= packet_object(s, s->bvh.prims[first + i], r, active, best, hit);
        return found;
    }
    /* Every leaf a ray enters, in whatever order: the order does not
     * change the hits (scene_hit_object). */
    uint32_t lfirst[8], lcount[8];
    int rays[8];
    int nl = node_leaves(s, r, active, lfirst, lcount, rays);
    for (int l = 0; l < nl; l++)
        for (uint32_t i = 0; i < lcount[l]; i++)
            found |= packet_object(s, s->bvh.prims[lfirst[l] + i], r, rays[l], best, hit);
    return found;
}

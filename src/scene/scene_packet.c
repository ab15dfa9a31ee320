/* scene_intersect8: eight rays' nearest hits at once. In a flat scene (one
 * leaf of objects, plus the unbounded ones) each object is tested in the
 * order scene_intersect tests it, a mesh against all eight rays in one
 * walk of its BVH (mesh_intersect8), any other object against each ray on
 * its own; in a deeper scene each ray goes through scene_intersect. Either
 * way every ray gets the hit scene_intersect gives it, to the bit. */
#include <string.h>
#include "geom/mesh.h"
#include "scene_trace.h"

/* Object i against the rays of active, each searched up to best[k]. */
static int packet_object(const scene *s, int i, const ray8 *r, int active, float best[8],
                         scene_hit hit[8])
{
    const object *o = &s->objects[i];
    int found = 0;
    if (o->shape.kind == SHAPE_MESH && !o->moving) {
        ray8 lr;
        int first = __builtin_ctz((unsigned)active);
        for (int k = 0; k < 8; k++) {
            int q = active >> k & 1 ? k : first; /* idle lanes repeat an active ray */
            ray one = {v3(r->ox[q], r->oy[q], r->oz[q]), v3(r->dx[q], r->dy[q], r->dz[q]),
                       r->tmin[q], best[q], 0.0f};
            ray l = scene_object_ray(s, o, &one);
            lr.ox[k] = l.o.x, lr.oy[k] = l.o.y, lr.oz[k] = l.o.z;
            lr.dx[k] = l.d.x, lr.dy[k] = l.d.y, lr.dz[k] = l.d.z;
            lr.tmin[k] = l.tmin, lr.tmax[k] = l.tmax;
        }
        shape_hit h[8];
        found = mesh_intersect8(o->shape.mesh, &lr, active, h);
        for (int m = found; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            best[k] = h[k].t;
            hit[k] = (scene_hit){h[k], i};
        }
        return found;
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

bool scene_packets_pay(const scene *s)
{
    if (!s->flat)
        return false;
    uint32_t first, n = scene_flat_leaf(s, &first);
    for (uint32_t i = 0; i < n; i++) {
        const object *o = &s->objects[s->bvh.prims[first + i]];
        if (o->shape.kind == SHAPE_MESH && !o->moving &&
            (o->shape.mesh->bvh.isa == ACCEL_AVX2 || o->shape.mesh->bvh.isa == ACCEL_AVX512))
            return true;
    }
    return false;
}

int scene_intersect8(const scene *s, const ray8 *r, int active, scene_hit *hit)
{
    int found = 0;
    if (!active)
        return 0;
    if (!s->flat) {
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
    for (int i = 0; i < s->nunbounded; i++)
        found |= packet_object(s, s->unbounded[i], r, active, best, hit);
    uint32_t first, n = scene_flat_leaf(s, &first);
    for (uint32_t i = 0; i < n; i++)
        found |= packet_object(s, s->bvh.prims[first + i], r, active, best, hit);
    return found;
}

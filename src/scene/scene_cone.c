/* scene_cone: the objects a bundle of rays from one point may meet, found
 * once for the bundle (a tile's camera rays), and the bundle's packets then
 * tested against those objects alone instead of walking the tree. */
#include <math.h>
#include <string.h>

#include "scene_trace.h"

/* Whether a ray o + t d, t >= 0, with d anywhere in [dlo, dhi] (each
 * component on its own: a superset of the bundle), may meet box b grown
 * by a margin far beyond rounding (1e-4 of the coordinates' size: a
 * shape's hit found in floats lies within a few units in the last place
 * of its box). Each axis bounds the t at which some direction of the
 * interval is inside the box's slab; the bundle misses the box where the
 * three ranges of t do not meet. In doubles, whose rounding the margin
 * dwarfs. */
static bool cone_meets(aabb b, vec3 o, vec3 dlo, vec3 dhi)
{
    const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    const float oo[3] = {o.x, o.y, o.z}, p[3] = {dlo.x, dlo.y, dlo.z}, q[3] = {dhi.x, dhi.y, dhi.z};
    double tlo = 0.0, thi = INFINITY;
    for (int a = 0; a < 3; a++) {
        double pad = 1e-4 * (fabs((double)lo[a]) + fabs((double)hi[a]) + fabs((double)oo[a])) +
                     1e-30;
        double l = (double)lo[a] - pad - oo[a], h = (double)hi[a] + pad - oo[a];
        /* some t * d <= h, d >= p */
        if (p[a] > 0.0f) {
            if (h < 0.0)
                return false;
            thi = fmin(thi, h / p[a]);
        } else if (h < 0.0) {
            if (p[a] == 0.0f)
                return false;
            tlo = fmax(tlo, h / p[a]);
        }
        /* some t * d >= l, d <= q */
        if (q[a] < 0.0f) {
            if (l > 0.0)
                return false;
            thi = fmin(thi, l / q[a]);
        } else if (l > 0.0) {
            if (q[a] == 0.0f)
                return false;
            tlo = fmax(tlo, l / q[a]);
        }
    }
    return tlo <= thi * (1.0 + 1e-6);
}

int scene_cone_objects(const scene *s, vec3 o, vec3 dlo, vec3 dhi, int32_t *list, int cap)
{
    if (!s->flat && !(s->bvh.width == 8 && s->bvh.nnodes > 0))
        return -1;
    if (s->bvh.nprims > cap)
        return -1;
    const float c[9] = {o.x, o.y, o.z, dlo.x, dlo.y, dlo.z, dhi.x, dhi.y, dhi.z};
    if (!floats_finite(c, 9))
        return -1;
    int n = 0;
    for (int i = 0; i < s->bvh.nprims; i++) {
        int32_t k = s->bvh.prims[i];
        if (aabb_is_unbounded(s->bounds[k]) || cone_meets(s->bounds[k], o, dlo, dhi))
            list[n++] = k;
    }
    return n;
}

int scene_intersect8_among(const scene *s, const ray8 *r, int active, const int32_t *list,
                           int n, scene_hit *hit)
{
    if (!active)
        return 0;
    float best[8];
    memcpy(best, r->tmax, sizeof best);
    for (int k = 0; k < 8; k++)
        hit[k].object = -1;
    int found = 0;
    for (int i = 0; i < s->nunbounded; i++)
        found |= scene_packet_object(s, s->unbounded[i], r, active, best, hit);
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return found | scene_among8_avx512(s, r, active, list, n, best, hit);
    if (s->bvh.isa == ACCEL_AVX2)
        return found | scene_among8_avx2(s, r, active, list, n, best, hit);
#endif
    for (int i = 0; i < n; i++)
        found |= scene_packet_object(s, list[i], r, active, best, hit);
    return found;
}

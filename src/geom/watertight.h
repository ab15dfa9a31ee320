/* watertight: the ray/triangle test of Woop, Benthin and Wald,
 * "Watertight Ray/Triangle Intersection" (JCGT 2013). The ray is sheared so
 * that it runs along +z; edge functions are then evaluated in 2D, with a
 * double-precision fallback when one is exactly zero, so that a ray never
 * slips between two triangles sharing an edge. */
#ifndef GLINT_GEOM_WATERTIGHT_H
#define GLINT_GEOM_WATERTIGHT_H

#include <math.h>
#include <stdbool.h>
#include "core/ray.h"

/* Per-ray data, computed once and reused for every triangle. */
typedef struct tri_ray {
    vec3 o;
    int kx, ky, kz;
    float sx, sy, sz;
} tri_ray;

static inline float tri_comp(vec3 v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

static inline tri_ray tri_ray_make(const ray *r)
{
    tri_ray t;
    vec3 ad = v3(fabsf(r->d.x), fabsf(r->d.y), fabsf(r->d.z));
    t.kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    t.kx = (t.kz + 1) % 3;
    t.ky = (t.kx + 1) % 3;
    float dz = tri_comp(r->d, t.kz);
    if (dz < 0.0f) {
        int k = t.kx;
        t.kx = t.ky;
        t.ky = k;
    }
    t.sx = tri_comp(r->d, t.kx) / dz;
    t.sy = tri_comp(r->d, t.ky) / dz;
    t.sz = 1.0f / dz;
    t.o = r->o;
    return t;
}

/* Hit with t in (tmin, tmax): sets *t and the barycentric weights b1, b2 of
 * p1 and p2. */
static inline bool tri_intersect(const tri_ray *tr, vec3 p0, vec3 p1, vec3 p2, float tmin,
                                 float tmax, float *t, float *b1, float *b2)
{
    vec3 a = v3_sub(p0, tr->o), b = v3_sub(p1, tr->o), c = v3_sub(p2, tr->o);
    float az = tri_comp(a, tr->kz), bz = tri_comp(b, tr->kz), cz = tri_comp(c, tr->kz);
    float ax = tri_comp(a, tr->kx) - tr->sx * az, ay = tri_comp(a, tr->ky) - tr->sy * az;
    float bx = tri_comp(b, tr->kx) - tr->sx * bz, by = tri_comp(b, tr->ky) - tr->sy * bz;
    float cx = tri_comp(c, tr->kx) - tr->sx * cz, cy = tri_comp(c, tr->ky) - tr->sy * cz;
    float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = (float)((double)cx * by - (double)cy * bx);
        v = (float)((double)ax * cy - (double)ay * cx);
        w = (float)((double)bx * ay - (double)by * ax);
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f))
        return false;
    float det = u + v + w;
    if (det == 0.0f)
        return false;
    float tt = (u * az + v * bz + w * cz) * tr->sz;
    float inv = 1.0f / det;
    tt *= inv;
    if (!(tt > tmin && tt < tmax))
        return false;
    *t = tt;
    *b1 = v * inv;
    *b2 = w * inv;
    return true;
}

#endif

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

/* Per-ray data, computed once and reused for every triangle: the ray's
 * origin and the shear that maps p - o to the space where the ray runs
 * along +z with unit speed (rows: x, y, z of the sheared space). */
typedef struct tri_ray {
    vec3 o;
    vec3 mx, my, mz;
} tri_ray;

static inline vec3 tri_axis(int k, float s)
{
    return v3(k == 0 ? s : 0.0f, k == 1 ? s : 0.0f, k == 2 ? s : 0.0f);
}

static inline tri_ray tri_ray_make(const ray *r)
{
    vec3 ad = v3(fabsf(r->d.x), fabsf(r->d.y), fabsf(r->d.z));
    int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    float dz = v3_at(r->d, kz);
    if (dz < 0.0f) {
        int k = kx;
        kx = ky;
        ky = k;
    }
    float sx = v3_at(r->d, kx) / dz, sy = v3_at(r->d, ky) / dz, sz = 1.0f / dz;
    tri_ray t;
    t.o = r->o;
    t.mx = v3_add(tri_axis(kx, 1.0f), tri_axis(kz, -sx));
    t.my = v3_add(tri_axis(ky, 1.0f), tri_axis(kz, -sy));
    t.mz = tri_axis(kz, sz);
    return t;
}

/* Hit with t in (tmin, tmax): sets *t and the barycentric weights b1, b2 of
 * p1 and p2. */
__attribute__((always_inline)) static inline bool tri_intersect(const tri_ray *tr, vec3 p0, vec3 p1, vec3 p2, float tmin,
                                 float tmax, float *t, float *b1, float *b2)
{
    vec3 a = v3_sub(p0, tr->o), b = v3_sub(p1, tr->o), c = v3_sub(p2, tr->o);
    float ax = v3_dot(tr->mx, a), ay = v3_dot(tr->my, a);
    float bx = v3_dot(tr->mx, b), by = v3_dot(tr->my, b);
    float cx = v3_dot(tr->mx, c), cy = v3_dot(tr->my, c);
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
    float tt = u * v3_dot(tr->mz, a) + v * v3_dot(tr->mz, b) + w * v3_dot(tr->mz, c);
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

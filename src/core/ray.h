/* ray: origin, direction and the open parametric interval (tmin, tmax) in
 * which hits count. Directions need not be unit length; t is measured in
 * units of the direction, so transforming a ray keeps t meaningful.
 *
 * The offset rule (one for the whole renderer): a ray leaving a surface
 * starts at the hit point pushed along the geometric normal, to the side the
 * ray departs into, by ray_epsilon(p) — a distance relative to the point's
 * magnitude so that float rounding in the hit point cannot put the origin
 * back behind the surface. tmin is then 0. A shadow ray that walks on
 * through a transmitting surface it crossed keeps its origin and moves tmin
 * past the crossing by the same ray_epsilon distance along the ray. */
#ifndef GLINT_CORE_RAY_H
#define GLINT_CORE_RAY_H

#include <stdbool.h>
#include "vec3.h"

/* o with tmin and d with tmax in 16 bytes each: a ray made in registers
 * and passed in memory is stored in those two pieces, and a read of o or
 * d (as one 8-byte and one 4-byte load) then lies within one of them,
 * where the processor forwards it from the store; across two (o, d
 * side by side) it waited for the stores to reach the cache (row 8's
 * shading points, each given a ray taken from its packet). Initialise by
 * field names. */
typedef struct ray {
    vec3 o;
    float tmin;
    vec3 d;
    float tmax;
    float time; /* seconds: where moving objects are for this ray (motion blur) */
} ray;

/* Eight rays traced together (scene_intersect8, mesh_intersect8), one
 * lane per ray. Every lane holds numbers, those of idle rays included. */
typedef struct ray8 {
    float ox[8], oy[8], oz[8];
    float dx[8], dy[8], dz[8];
    float tmin[8], tmax[8];
    float time[8];
} ray8;

/* Ray k of a packet, and a ray put into lane k. */
static inline ray ray8_get(const ray8 *p, int k)
{
    return (ray){.o = {p->ox[k], p->oy[k], p->oz[k]},
                 .d = {p->dx[k], p->dy[k], p->dz[k]},
                 .tmin = p->tmin[k],
                 .tmax = p->tmax[k],
                 .time = p->time[k]};
}

static inline void ray8_put(ray8 *p, int k, const ray *r)
{
    p->ox[k] = r->o.x, p->oy[k] = r->o.y, p->oz[k] = r->o.z;
    p->dx[k] = r->d.x, p->dy[k] = r->d.y, p->dz[k] = r->d.z;
    p->tmin[k] = r->tmin, p->tmax[k] = r->tmax, p->time[k] = r->time;
}

/* The idle lanes of a packet whose lanes of active (not 0) are set: each
 * repeats an active ray, so that every lane holds numbers. */
static inline void ray8_fill(ray8 *p, int active)
{
    int first = __builtin_ctz((unsigned)active);
    for (int m = ~active & 0xff; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray r = ray8_get(p, first);
        ray8_put(p, k, &r);
    }
}

/* The rays r[k] of the lanes of active (not 0) as a packet, the idle
 * lanes filled (ray8_fill). */
static inline void ray8_pack(ray8 *p, const ray r[8], int active)
{
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray8_put(p, k, &r[k]);
    }
    ray8_fill(p, active);
}

/* How many lanes mask has (without a popcount instruction, which
 * baseline builds lack). */
static inline int ray8_count(int mask)
{
    int n = 0;
    for (; mask; mask &= mask - 1)
        n++;
    return n;
}

/* Whether mask has three lanes or more: enough for a packet to pay
 * (without a popcount instruction, which baseline builds lack). */
static inline bool ray8_three_or_more(int mask)
{
    mask &= mask - 1;
    mask &= mask - 1;
    return mask != 0;
}

#define RAY_EPS_REL 1e-4f

static inline vec3 ray_at(const ray *r, float t) { return v3_madd(r->o, r->d, t); }

/* Whether t lies in the ray's open interval (tmin, tmax); false for NaN. */
static inline bool ray_in_range(const ray *r, float t) { return t > r->tmin && t < r->tmax; }

static inline float ray_epsilon(vec3 p) { return RAY_EPS_REL * (1.0f + v3_max_abs(p)); }

/* Origin for a ray leaving point p (on a surface with geometric normal ng)
 * in direction d. */
static inline vec3 ray_offset(vec3 p, vec3 ng, vec3 d)
{
    float e = ray_epsilon(p);
    return v3_madd(p, ng, v3_dot(ng, d) >= 0.0f ? e : -e);
}

static inline ray ray_make(vec3 o, vec3 d, float tmax)
{
    return (ray){.o = o, .d = d, .tmin = 0.0f, .tmax = tmax, .time = 0.0f};
}

/* Where r meets the plane through point with normal n: true with *t when
 * that is within (tmin, tmax); a ray parallel to the plane misses it. */
static inline bool ray_plane(const ray *r, vec3 point, vec3 n, float *t)
{
    float dn = v3_dot(r->d, n);
    if (dn == 0.0f)
        return false;
    *t = v3_dot(v3_sub(point, r->o), n) / dn;
    return ray_in_range(r, *t);
}

#endif

/* shape8: the sphere, quad, plane, box and cylinder tests against eight rays
 * at once, one ray per AVX lane, for packets of camera rays
 * (scene_intersect8). Each lane does the one-ray test's operations in the
 * same order, so it finds the same hit to the bit; branches become masks.
 * For translation units compiled with AVX2. */
#ifndef GLINT_GEOM_SHAPE8_H
#define GLINT_GEOM_SHAPE8_H

#include <immintrin.h>
#include "core/ray.h"
#include "geom/mesh_packet.h"
#include "geom/shape.h"
#include "geom/torus8.h"

/* The rays of a packet, one register per coordinate. */
typedef struct rays8 {
    __m256 ox, oy, oz, dx, dy, dz, tmin;
} rays8;

static inline rays8 rays8_load(const ray8 *r)
{
    return (rays8){_mm256_loadu_ps(r->ox), _mm256_loadu_ps(r->oy), _mm256_loadu_ps(r->oz),
                   _mm256_loadu_ps(r->dx), _mm256_loadu_ps(r->dy), _mm256_loadu_ps(r->dz),
                   _mm256_loadu_ps(r->tmin)};
}

/* v3_dot's (a.x * b.x + a.y * b.y) + a.z * b.z, lane by lane. */
static inline __m256 dot8(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz)
{
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)),
                         _mm256_mul_ps(az, bz));
}

/* copysignf(mag, sgn), lane by lane. */
static inline __m256 copysign8(__m256 mag, __m256 sgn)
{
    const __m256 sign = _mm256_set1_ps(-0.0f);
    return _mm256_or_ps(_mm256_andnot_ps(sign, mag), _mm256_and_ps(sign, sgn));
}

/* ray_in_range: tmin < t < tmax. */
static inline __m256 in_range8(__m256 t, __m256 tmin, __m256 tmax)
{
    return _mm256_and_ps(_mm256_cmp_ps(t, tmin, _CMP_GT_OQ), _mm256_cmp_ps(t, tmax, _CMP_LT_OQ));
}

/* sphere_roots for the rays of active: returns the rays with roots, near
 * <= far per ray. */
static inline int sphere8_roots(const struct sphere *s, const rays8 *r, int active, __m256 *near,
                                __m256 *far)
{
    const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
    __m256 fx = _mm256_sub_ps(r->ox, _mm256_set1_ps(s->center.x));
    __m256 fy = _mm256_sub_ps(r->oy, _mm256_set1_ps(s->center.y));
    __m256 fz = _mm256_sub_ps(r->oz, _mm256_set1_ps(s->center.z));
    __m256 b = _mm256_xor_ps(dot8(fx, fy, fz, r->dx, r->dy, r->dz), sign);
    float rr1 = s->radius * s->radius;
    __m256 rr = _mm256_set1_ps(rr1);
    __m256 c = _mm256_sub_ps(dot8(fx, fy, fz, fx, fy, fz), rr);
    __m256 away = _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps(c, zero, _CMP_GT_OQ), _mm256_cmp_ps(b, zero, _CMP_LT_OQ)),
        _mm256_cmp_ps(r->tmin, zero, _CMP_GE_OQ));
    active &= ~_mm256_movemask_ps(away);
    if (!active)
        return 0;
    __m256 a = dot8(r->dx, r->dy, r->dz, r->dx, r->dy, r->dz);
    __m256 ba = _mm256_div_ps(b, a);
    __m256 lx = _mm256_add_ps(fx, _mm256_mul_ps(r->dx, ba));
    __m256 ly = _mm256_add_ps(fy, _mm256_mul_ps(r->dy, ba));
    __m256 lz = _mm256_add_ps(fz, _mm256_mul_ps(r->dz, ba));
    __m256 disc = _mm256_mul_ps(a, _mm256_sub_ps(rr, dot8(lx, ly, lz, lx, ly, lz)));
    active &= ~_mm256_movemask_ps(_mm256_cmp_ps(disc, zero, _CMP_LT_OQ));
    if (!active)
        return 0;
    __m256 q = _mm256_add_ps(b, copysign8(_mm256_sqrt_ps(disc), b));
    __m256 q0 = _mm256_cmp_ps(q, zero, _CMP_EQ_OQ);
    __m256 t0 = _mm256_andnot_ps(q0, _mm256_div_ps(c, q));
    __m256 t1 = _mm256_andnot_ps(q0, _mm256_div_ps(q, a));
    __m256 swap = _mm256_cmp_ps(t0, t1, _CMP_GT_OQ);
    *near = _mm256_blendv_ps(t0, t1, swap);
    *far = _mm256_blendv_ps(t1, t0, swap);
    return active;
}

/* sphere_hit for the rays of active with (tmin, tmax[k]): returns the
 * rays hit, with t per ray. */
static inline int sphere8_hit(const struct sphere *s, const rays8 *r, __m256 tmax, int active,
                              __m256 *t)
{
    __m256 near = _mm256_setzero_ps(), far = near;
    active = sphere8_roots(s, r, active, &near, &far);
    if (!active)
        return 0;
    __m256 first = in_range8(near, r->tmin, tmax);
    *t = _mm256_blendv_ps(far, near, first);
    return active & _mm256_movemask_ps(_mm256_or_ps(first, in_range8(far, r->tmin, tmax)));
}

/* Where the search for a shadow ray's next crossing starts after one at
 * t (scene_cross_next, lane by lane): ray_epsilon at the point over the
 * direction's length dlen beyond t, or the next float up. */
static inline __m256 cross_next8(const rays8 *r, __m256 t, __m256 dlen)
{
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    __m256 px = _mm256_add_ps(r->ox, _mm256_mul_ps(r->dx, t));
    __m256 py = _mm256_add_ps(r->oy, _mm256_mul_ps(r->dy, t));
    __m256 pz = _mm256_add_ps(r->oz, _mm256_mul_ps(r->dz, t));
    __m256 m = _mm256_max_ps(_mm256_and_ps(px, abs),
                             _mm256_max_ps(_mm256_and_ps(py, abs), _mm256_and_ps(pz, abs)));
    __m256 e = _mm256_mul_ps(_mm256_set1_ps(RAY_EPS_REL), _mm256_add_ps(_mm256_set1_ps(1.0f), m));
    __m256 next = _mm256_add_ps(t, _mm256_div_ps(e, dlen));
    return _mm256_blendv_ps(packet_next_up(t), next, _mm256_cmp_ps(next, t, _CMP_GT_OQ));
}

/* A shadow ray's crossings of a sphere (scene_shadow_object's loop, lane
 * by lane), for the rays of active: t[j][k] is ray k's crossing j, and
 * took[j] the rays that cross it a (j + 1)-th time. */
static inline void sphere8_crossings(const struct sphere *s, const ray8 *r8, int active,
                                     float t[2][8], int took[2])
{
    rays8 r = rays8_load(r8);
    __m256 near = _mm256_setzero_ps(), far = near, tmax = _mm256_loadu_ps(r8->tmax);
    took[0] = took[1] = 0;
    active = sphere8_roots(s, &r, active, &near, &far);
    if (!active)
        return;
    __m256 dlen = _mm256_sqrt_ps(dot8(r.dx, r.dy, r.dz, r.dx, r.dy, r.dz));
    __m256 in0 = in_range8(near, r.tmin, tmax);
    __m256 tmin = _mm256_blendv_ps(r.tmin, cross_next8(&r, near, dlen), in0);
    __m256 in1 = in_range8(far, tmin, tmax);
    /* the first crossing is the near root where it is in range, else the far */
    int m0 = active & _mm256_movemask_ps(in0), m1 = active & _mm256_movemask_ps(in1);
    _mm256_storeu_ps(t[0], _mm256_blendv_ps(far, near, in0));
    _mm256_storeu_ps(t[1], far);
    took[0] = m0 | m1;
    took[1] = m0 & m1;
}

/* ray_plane (core/ray.h) likewise: the rays of active that meet the plane
 * through point with normal n within (tmin, tmax[k]), with t per ray. */
static inline int plane8_hit(vec3 point, vec3 n, const rays8 *r, __m256 tmax, int active,
                             __m256 *t)
{
    const __m256 zero = _mm256_setzero_ps();
    __m256 nx = _mm256_set1_ps(n.x), ny = _mm256_set1_ps(n.y), nz = _mm256_set1_ps(n.z);
    __m256 dn = dot8(r->dx, r->dy, r->dz, nx, ny, nz);
    active &= ~_mm256_movemask_ps(_mm256_cmp_ps(dn, zero, _CMP_EQ_OQ));
    if (!active)
        return 0;
    __m256 px = _mm256_sub_ps(_mm256_set1_ps(point.x), r->ox);
    __m256 py = _mm256_sub_ps(_mm256_set1_ps(point.y), r->oy);
    __m256 pz = _mm256_sub_ps(_mm256_set1_ps(point.z), r->oz);
    *t = _mm256_div_ps(dot8(px, py, pz, nx, ny, nz), dn);
    return active & _mm256_movemask_ps(in_range8(*t, r->tmin, tmax));
}

/* quad_hit likewise, with (u, v) in b1, b2. */
static inline int quad8_hit(const struct quad *s, const rays8 *r, __m256 tmax, int active,
                            __m256 *t, __m256 *b1, __m256 *b2)
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    __m256 tt = zero;
    active = plane8_hit(s->origin, s->normal, r, tmax, active, &tt);
    if (!active)
        return 0;
    /* q = ray_at(t) - origin */
    __m256 qx = _mm256_sub_ps(_mm256_add_ps(r->ox, _mm256_mul_ps(r->dx, tt)), _mm256_set1_ps(s->origin.x));
    __m256 qy = _mm256_sub_ps(_mm256_add_ps(r->oy, _mm256_mul_ps(r->dy, tt)), _mm256_set1_ps(s->origin.y));
    __m256 qz = _mm256_sub_ps(_mm256_add_ps(r->oz, _mm256_mul_ps(r->dz, tt)), _mm256_set1_ps(s->origin.z));
    __m256 ux = _mm256_set1_ps(s->edge_u.x), uy = _mm256_set1_ps(s->edge_u.y);
    __m256 uz = _mm256_set1_ps(s->edge_u.z), vx = _mm256_set1_ps(s->edge_v.x);
    __m256 vy = _mm256_set1_ps(s->edge_v.y), vz = _mm256_set1_ps(s->edge_v.z);
    __m256 wx = _mm256_set1_ps(s->w.x), wy = _mm256_set1_ps(s->w.y), wz = _mm256_set1_ps(s->w.z);
    /* v3_cross(q, edge_v) and v3_cross(edge_u, q) */
    __m256 cx = _mm256_sub_ps(_mm256_mul_ps(qy, vz), _mm256_mul_ps(qz, vy));
    __m256 cy = _mm256_sub_ps(_mm256_mul_ps(qz, vx), _mm256_mul_ps(qx, vz));
    __m256 cz = _mm256_sub_ps(_mm256_mul_ps(qx, vy), _mm256_mul_ps(qy, vx));
    __m256 ex = _mm256_sub_ps(_mm256_mul_ps(uy, qz), _mm256_mul_ps(uz, qy));
    __m256 ey = _mm256_sub_ps(_mm256_mul_ps(uz, qx), _mm256_mul_ps(ux, qz));
    __m256 ez = _mm256_sub_ps(_mm256_mul_ps(ux, qy), _mm256_mul_ps(uy, qx));
    __m256 u = dot8(wx, wy, wz, cx, cy, cz), v = dot8(wx, wy, wz, ex, ey, ez);
    __m256 in = _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps(u, zero, _CMP_GE_OQ), _mm256_cmp_ps(u, one, _CMP_LE_OQ)),
        _mm256_and_ps(_mm256_cmp_ps(v, zero, _CMP_GE_OQ), _mm256_cmp_ps(v, one, _CMP_LE_OQ)));
    *t = tt;
    *b1 = u;
    *b2 = v;
    return active & _mm256_movemask_ps(in);
}

/* box_intersect likewise: the slabs in the same order, each lane keeping
 * the face that bounds its interval (ties to the earlier axis), with the
 * face per ray in part. */
static inline int box8_hit(const struct box *s, const rays8 *r, __m256 tmax, int active,
                           __m256 *t, __m256 *part)
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 o[3] = {r->ox, r->oy, r->oz}, d[3] = {r->dx, r->dy, r->dz};
    const float lo[3] = {s->lo.x, s->lo.y, s->lo.z}, hi[3] = {s->hi.x, s->hi.y, s->hi.z};
    __m256 tnear = _mm256_set1_ps(-INFINITY), tfar = _mm256_set1_ps(INFINITY);
    __m256 nf = _mm256_set1_ps(-1.0f), ff = nf, miss = zero;
    for (int a = 0; a < 3; a++) {
        __m256 l = _mm256_set1_ps(lo[a]), h = _mm256_set1_ps(hi[a]);
        __m256 flat = _mm256_cmp_ps(d[a], zero, _CMP_EQ_OQ); /* parallel to the slab */
        __m256 out = _mm256_or_ps(_mm256_cmp_ps(o[a], l, _CMP_LT_OQ),
                                  _mm256_cmp_ps(o[a], h, _CMP_GT_OQ));
        miss = _mm256_or_ps(miss, _mm256_and_ps(flat, out));
        __m256 inv = _mm256_div_ps(one, d[a]);
        __m256 t0 = _mm256_mul_ps(_mm256_sub_ps(l, o[a]), inv);
        __m256 t1 = _mm256_mul_ps(_mm256_sub_ps(h, o[a]), inv);
        __m256 f0 = _mm256_set1_ps((float)(2 * a)), f1 = _mm256_set1_ps((float)(2 * a + 1));
        __m256 swap = _mm256_cmp_ps(t0, t1, _CMP_GT_OQ);
        __m256 tn = _mm256_blendv_ps(t0, t1, swap), tf = _mm256_blendv_ps(t1, t0, swap);
        __m256 fn = _mm256_blendv_ps(f0, f1, swap), fb = _mm256_blendv_ps(f1, f0, swap);
        __m256 up = _mm256_andnot_ps(flat, _mm256_cmp_ps(tn, tnear, _CMP_GT_OQ));
        tnear = _mm256_blendv_ps(tnear, tn, up);
        nf = _mm256_blendv_ps(nf, fn, up);
        __m256 down = _mm256_andnot_ps(flat, _mm256_cmp_ps(tf, tfar, _CMP_LT_OQ));
        tfar = _mm256_blendv_ps(tfar, tf, down);
        ff = _mm256_blendv_ps(ff, fb, down);
        miss = _mm256_or_ps(miss, _mm256_cmp_ps(tnear, tfar, _CMP_GT_OQ));
    }
    active &= ~_mm256_movemask_ps(miss);
    if (!active)
        return 0;
    __m256 first = in_range8(tnear, r->tmin, tmax);
    *t = _mm256_blendv_ps(tfar, tnear, first);
    *part = _mm256_blendv_ps(ff, nf, first);
    return active & _mm256_movemask_ps(_mm256_or_ps(first, in_range8(tfar, r->tmin, tmax)));
}

/* a.x * b.x + a.y * b.y of two-component vectors, lane by lane. */
static inline __m256 dot2_8(__m256 ax, __m256 ay, __m256 bx, __m256 by)
{
    return _mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by));
}

/* cylinder_intersect's consider(), lane by lane: candidate t with part p
 * where valid, in range and nearer than *best. */
static inline void cylinder8_consider(__m256 valid, __m256 t, float p, __m256 tmin,
                                      __m256 *best, __m256 *part)
{
    __m256 take = _mm256_and_ps(_mm256_and_ps(valid, _mm256_cmp_ps(t, tmin, _CMP_GT_OQ)),
                                _mm256_cmp_ps(t, *best, _CMP_LT_OQ));
    *best = _mm256_blendv_ps(*best, t, take);
    *part = _mm256_blendv_ps(*part, _mm256_set1_ps(p), take);
}

/* cylinder_intersect likewise: the candidates in the same order (the
 * side's two roots, then the caps), with the part of the one kept. */
static inline int cylinder8_hit(const struct cylinder *s, const rays8 *r, __m256 tmax,
                                int active, __m256 *t, __m256 *part)
{
    const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
    __m256 ox = _mm256_sub_ps(r->ox, _mm256_set1_ps(s->base.x));
    __m256 oy = _mm256_sub_ps(r->oy, _mm256_set1_ps(s->base.y));
    __m256 oz = _mm256_sub_ps(r->oz, _mm256_set1_ps(s->base.z));
    __m256 rr = _mm256_set1_ps(s->radius * s->radius), height = _mm256_set1_ps(s->height);
    *t = tmax;
    *part = _mm256_set1_ps(-1.0f);
    __m256 a = dot2_8(r->dx, r->dz, r->dx, r->dz);
    __m256 side = _mm256_cmp_ps(a, zero, _CMP_GT_OQ);
    if (_mm256_movemask_ps(side) & active) {
        __m256 b = _mm256_xor_ps(dot2_8(ox, oz, r->dx, r->dz), sign);
        __m256 ba = _mm256_div_ps(b, a);
        __m256 lx = _mm256_add_ps(ox, _mm256_mul_ps(r->dx, ba));
        __m256 lz = _mm256_add_ps(oz, _mm256_mul_ps(r->dz, ba));
        __m256 disc = _mm256_mul_ps(a, _mm256_sub_ps(rr, dot2_8(lx, lz, lx, lz)));
        side = _mm256_and_ps(side, _mm256_cmp_ps(disc, zero, _CMP_GE_OQ));
        __m256 c = _mm256_sub_ps(dot2_8(ox, oz, ox, oz), rr);
        __m256 q = _mm256_add_ps(b, copysign8(_mm256_sqrt_ps(disc), b));
        __m256 ts[2] = {_mm256_andnot_ps(_mm256_cmp_ps(q, zero, _CMP_EQ_OQ), _mm256_div_ps(c, q)),
                        _mm256_div_ps(q, a)};
        for (int i = 0; i < 2; i++) {
            __m256 y = _mm256_add_ps(oy, _mm256_mul_ps(r->dy, ts[i]));
            __m256 on = _mm256_and_ps(_mm256_cmp_ps(y, zero, _CMP_GE_OQ),
                                      _mm256_cmp_ps(y, height, _CMP_LE_OQ));
            cylinder8_consider(_mm256_and_ps(side, on), ts[i], 0.0f, r->tmin, t, part);
        }
    }
    __m256 ends = _mm256_cmp_ps(r->dy, zero, _CMP_NEQ_UQ);
    if (s->capped && (_mm256_movemask_ps(ends) & active)) {
        const float caps[2] = {0.0f, s->height};
        for (int i = 0; i < 2; i++) {
            __m256 tc = _mm256_div_ps(_mm256_sub_ps(_mm256_set1_ps(caps[i]), oy), r->dy);
            __m256 x = _mm256_add_ps(ox, _mm256_mul_ps(r->dx, tc));
            __m256 z = _mm256_add_ps(oz, _mm256_mul_ps(r->dz, tc));
            __m256 in = _mm256_cmp_ps(dot2_8(x, z, x, z), rr, _CMP_LE_OQ);
            cylinder8_consider(_mm256_and_ps(ends, in), tc, (float)(1 + i), r->tmin, t, part);
        }
    }
    return active & ~_mm256_movemask_ps(_mm256_cmp_ps(*part, zero, _CMP_LT_OQ));
}

/* shape8_hit (shape.h): the test of shape_tests_eight's kinds, each lane's
 * results stored at once when there is a best to beat. */
static inline int shape8_hit(const shape *sh, const ray8 *r, const float *best, int active,
                             shape_hits8 *out, int *nearer)
{
    if (!shape_tests_eight(sh->kind))
        return -1;
    rays8 rs = rays8_load(r);
    __m256 lim = best ? packet_next_up(_mm256_loadu_ps(best)) : _mm256_loadu_ps(r->tmax);
    __m256 t = _mm256_setzero_ps(), b1 = t, b2 = t, part = t;
    int m = sh->kind == SHAPE_SPHERE ? sphere8_hit(&sh->sphere, &rs, lim, active, &t)
            : sh->kind == SHAPE_QUAD
                ? quad8_hit(&sh->quad, &rs, lim, active, &t, &b1, &b2)
            : sh->kind == SHAPE_BOX
                ? box8_hit(&sh->box, &rs, lim, active, &t, &part)
            : sh->kind == SHAPE_CYLINDER
                ? cylinder8_hit(&sh->cylinder, &rs, lim, active, &t, &part)
                : plane8_hit(sh->plane.point, sh->plane.normal, &rs, lim, active, &t);
    if (best && m) {
        *nearer = m & _mm256_movemask_ps(_mm256_cmp_ps(t, _mm256_loadu_ps(best), _CMP_LT_OQ));
        _mm256_storeu_ps(out->t, t);
        _mm256_storeu_ps(out->b1, b1);
        _mm256_storeu_ps(out->b2, b2);
        _mm256_storeu_si256((__m256i *)out->part, _mm256_cvttps_epi32(part));
    }
    return m;
}

/* Defines shape8_hit_<isa>, sphere8_crossings_<isa> and torus8_hit_<isa>. */
#define SHAPE8_KERNELS(isa)                                                                    \
    int shape8_hit_##isa(const shape *sh, const ray8 *r, const float *best, int active,       \
                         shape_hits8 *out, int *nearer)                                        \
    {                                                                                          \
        return shape8_hit(sh, r, best, active, out, nearer);                                   \
    }                                                                                          \
    void sphere8_crossings_##isa(const struct sphere *s, const ray8 *r, int active,           \
                                 float t[2][8], int took[2])                                   \
    {                                                                                          \
        sphere8_crossings(s, r, active, t, took);                                              \
    }                                                                                          \
    int torus8_hit_##isa(const struct torus *s, const ray8 *r, int active, shape_hit *hit)     \
    {                                                                                          \
        return torus8_hit(s, r, active, hit);                                                  \
    }                                                                                          \
    int torus8_occluded_##isa(const struct torus *s, const ray8 *r, int active)                \
    {                                                                                          \
        return torus8_occluded(s, r, active);                                                  \
    }

#endif

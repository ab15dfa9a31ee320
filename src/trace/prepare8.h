/* prepare8: a packet's shading points eight lanes at once (bounce8_api.h:
 * prepare) where its rays hit one of shade_prepare's plain surfaces
 * (shading.h): an untextured, unturned sphere (shade_prepare's inline
 * case), an untextured, unturned plane, or an untextured torus turned by a
 * fixed transform (shading.c: plain_surface). Lane by lane the same
 * floats as those, in the same order (no fused multiply-adds): the
 * torus's nearest point in doubles, as torus_nearest (geom/shape_inline.h)
 * works it out. For translation units compiled with AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_PREPARE8_H
#define GLINT_TRACE_PREPARE8_H

#include "geom/mesh_packet.h" /* packet_lanes */
#include "geom/torus8.h"      /* eight lanes of doubles */
#include "scene/scene.h"
#include "trace/bounce8_api.h"
#include "trace/simd8.h"

/* v3_norm lane by lane: a * (1 / |a|) where |a| > 0, else a. */
__attribute__((always_inline)) static inline void prepare8_norm(const __m256 a[3], __m256 out[3])
{
    __m256 l = _mm256_sqrt_ps(simd8_dot(a, a));
    __m256 pos = _mm256_cmp_ps(l, _mm256_setzero_ps(), _CMP_GT_OQ);
    __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), l);
    for (int c = 0; c < 3; c++)
        out[c] = _mm256_blendv_ps(a[c], _mm256_mul_ps(a[c], inv), pos);
}

/* The lanes of `lanes` grouped by the record each reads (at[k], a
 * pointer): each record once, with its lanes (bits, and as a register's
 * lanes). */
typedef struct prepare8_groups {
    int n, bits[8];
    const char *at[8];
    __m256 sel[8];
} prepare8_groups;

/* One group: every lane of `lanes` reads at. */
static inline void prepare8_one(const char *at, int lanes, prepare8_groups *g)
{
    g->n = 1, g->at[0] = at, g->bits[0] = lanes;
}

__attribute__((always_inline)) static inline void
prepare8_group(const char *const at[8], int lanes, prepare8_groups *g)
{
    g->n = 0;
    for (int m = lanes; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m), i = 0;
        while (i < g->n && g->at[i] != at[k])
            i++;
        if (i == g->n)
            g->at[i] = at[k], g->bits[i] = 0, g->n++;
        g->bits[i] |= 1 << k;
    }
    for (int i = 1; i < g->n; i++)
        g->sel[i] = packet_lanes(g->bits[i]);
}

/* The float at byte off of each lane's record (of base[i] + off for group
 * i): one broadcast for each, blended in by its lanes (the lanes of no
 * group take the first one's). */
__attribute__((always_inline)) static inline __m256
prepare8_read(const prepare8_groups *g, const char *const base[8], size_t off)
{
    __m256 v = _mm256_broadcast_ss((const float *)(const void *)(base[0] + off));
    for (int i = 1; i < g->n; i++)
        v = _mm256_blendv_ps(v, _mm256_broadcast_ss((const float *)(const void *)(base[i] + off)),
                             g->sel[i]);
    return v;
}

/* The objects a kind of surface reads for the lanes of `lanes`, each
 * once: its shape (at byte off of the object) and transform. */
typedef struct prepare8_objs {
    prepare8_groups g;
    const char *shape[8], *xf[8];
} prepare8_objs;

__attribute__((always_inline)) static inline void
prepare8_objects(const scene *s, const scene_hit *hit, int lanes, size_t off, prepare8_objs *o)
{
    int one = hit[__builtin_ctz((unsigned)lanes)].object, other = 0;
    for (int m = lanes & (lanes - 1); m; m &= m - 1) /* the commonest case: one object */
        other |= hit[__builtin_ctz((unsigned)m)].object ^ one;
    if (!other) {
        prepare8_one((const char *)&s->objects[one], lanes, &o->g);
    } else {
        const char *ob[8];
        for (int m = lanes; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ob[k] = (const char *)&s->objects[hit[k].object];
        }
        prepare8_group(ob, lanes, &o->g);
    }
    for (int i = 0; i < o->g.n; i++) {
        const object *x = (const object *)(const void *)o->g.at[i];
        o->shape[i] = o->g.at[i] + off;
        o->xf[i] = x->xform >= 0 ? (const char *)&s->xforms[x->xform] : NULL;
    }
}

__attribute__((always_inline)) static inline __m256 prepare8_field(const prepare8_objs *o, bool xf,
                                                                   size_t off)
{
    return prepare8_read(&o->g, xf ? o->xf : o->shape, off);
}

/* b into c for the lanes of `lanes`; all of c where they are every lane
 * being prepared (all). */
__attribute__((always_inline)) static inline void prepare8_put(int lanes, int all,
                                                               const __m256 b[3], __m256 c[3])
{
    __m256 m = packet_lanes(lanes);
    for (int i = 0; i < 3; i++)
        c[i] = lanes == all ? b[i] : _mm256_blendv_ps(c[i], b[i], m);
}

/* shade_prepare's sphere: sphere_surface_plain at ray_at(t). */
__attribute__((always_inline)) static inline void
prepare8_sphere(const scene *s, const scene_hit *hit, int lanes, int all, __m256 tt,
                const __m256 org[3], const __m256 d[3], __m256 P[3], __m256 N[3])
{
    prepare8_objs o;
    prepare8_objects(s, hit, lanes, offsetof(object, shape.sphere), &o);
    __m256 rad = prepare8_field(&o, false, offsetof(struct sphere, radius)), c[3], q[3];
    __m256 n[3], p[3];
    for (int i = 0; i < 3; i++) {
        size_t at = offsetof(struct sphere, center) + (size_t)i * sizeof(float);
        c[i] = prepare8_field(&o, false, at);
        q[i] = _mm256_sub_ps(_mm256_add_ps(org[i], _mm256_mul_ps(d[i], tt)), c[i]);
    }
    prepare8_norm(q, n);
    for (int i = 0; i < 3; i++)
        p[i] = _mm256_add_ps(c[i], _mm256_mul_ps(n[i], rad));
    prepare8_put(lanes, all, p, P);
    prepare8_put(lanes, all, n, N);
}

/* plain_surface's plane: ray_at(t) moved onto the plane (plane_onto); its
 * normal. */
__attribute__((always_inline)) static inline void
prepare8_plane(const scene *s, const scene_hit *hit, int lanes, int all, __m256 tt,
               const __m256 org[3], const __m256 d[3], __m256 P[3], __m256 N[3])
{
    prepare8_objs o;
    prepare8_objects(s, hit, lanes, offsetof(object, shape.plane), &o);
    __m256 pt[3], n[3], p[3], v[3];
    for (int i = 0; i < 3; i++) {
        size_t at = (size_t)i * sizeof(float);
        pt[i] = prepare8_field(&o, false, offsetof(struct plane, point) + at);
        n[i] = prepare8_field(&o, false, offsetof(struct plane, normal) + at);
        p[i] = _mm256_add_ps(org[i], _mm256_mul_ps(d[i], tt));
        v[i] = _mm256_sub_ps(p[i], pt[i]);
    }
    __m256 k = _mm256_xor_ps(simd8_dot(v, n), _mm256_set1_ps(-0.0f)); /* -(v . n) */
    for (int i = 0; i < 3; i++)
        p[i] = _mm256_add_ps(p[i], _mm256_mul_ps(n[i], k));
    prepare8_put(lanes, all, p, P);
    prepare8_put(lanes, all, n, N);
}

/* The top three rows of the matrix at byte off of each lane's transform. */
__attribute__((always_inline)) static inline void
prepare8_matrix(const prepare8_objs *o, size_t off, __m256 a[3][4])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++)
            a[r][c] = prepare8_field(o, true, off + (size_t)(r * 4 + c) * sizeof(float));
}

/* Row r of a times (x, y, z, w), as mat4_point (w) or mat4_vector (no w)
 * sum it. */
__attribute__((always_inline)) static inline __m256 prepare8_row(__m256 a[3][4], int r,
                                                                 const __m256 v[3], bool w)
{
    __m256 s = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(a[r][0], v[0]), _mm256_mul_ps(a[r][1], v[1])),
        _mm256_mul_ps(a[r][2], v[2]));
    return w ? _mm256_add_ps(s, a[r][3]) : s;
}

/* torus_nearest of the torus's local points lp: the nearest point p and
 * the unit normal n there, both in the torus's space. */
__attribute__((always_inline)) static inline void prepare8_nearest(const prepare8_objs *o,
                                                                   const __m256 lp[3],
                                                                   __m256 p[3], __m256 n[3])
{
    const td zero = t8_zero(), one = t8_k(1.0);
    td R = t8_widen(prepare8_field(o, false, offsetof(struct torus, major)));
    td rm = t8_widen(prepare8_field(o, false, offsetof(struct torus, minor)));
    td c[3], q[3];
    for (int i = 0; i < 3; i++) {
        size_t at = offsetof(struct torus, center) + (size_t)i * sizeof(float);
        c[i] = t8_widen(prepare8_field(o, false, at));
        q[i] = t8_sub(t8_widen(lp[i]), c[i]);
    }
    td rho = t8_sqrt(t8_add(t8_mul(q[0], q[0]), t8_mul(q[2], q[2])));
    tk off_axis = t8_cmp(rho, zero, _CMP_GT_OQ);
    td f = t8_div(R, rho);
    td ax = t8_pick(off_axis, t8_mul(q[0], f), R), az = t8_pick(off_axis, t8_mul(q[2], f), zero);
    td w0 = t8_sub(q[0], ax), w2 = t8_sub(q[2], az);
    td wa = t8_add(t8_add(t8_mul(w0, w0), t8_mul(q[1], q[1])), t8_mul(w2, w2));
    td bx = t8_add(q[0], ax), bz = t8_add(q[2], az);
    td wb = t8_add(t8_add(t8_mul(bx, bx), t8_mul(q[1], q[1])), t8_mul(bz, bz));
    td rm2 = t8_mul(rm, rm);
    tk lens = t8_cmp(t8_abs(t8_sub(wb, rm2)), t8_abs(t8_sub(wa, rm2)), _CMP_LT_OQ);
    ax = t8_pick(lens, t8_neg(ax), ax), az = t8_pick(lens, t8_neg(az), az);
    td sgn = t8_pick(lens, t8_k(-1.0), one);
    w0 = t8_pick(lens, t8_sub(q[0], ax), w0), w2 = t8_pick(lens, t8_sub(q[2], az), w2);
    wa = t8_pick(lens, wb, wa);
    td wl = t8_sqrt(wa);
    tk some = t8_cmp(wl, zero, _CMP_GT_OQ);
    td inv = t8_pick(some, t8_div(one, wl), zero), k = t8_mul(rm, inv);
    td e[3] = {t8_pick(some, t8_add(ax, t8_mul(w0, k)), q[0]),
               t8_pick(some, t8_mul(q[1], k), q[1]),
               t8_pick(some, t8_add(az, t8_mul(w2, k)), q[2])};
    inv = t8_mul(inv, sgn);
    td w[3] = {w0, q[1], w2}, up[3] = {zero, one, zero};
    for (int i = 0; i < 3; i++) {
        p[i] = t8_narrow(t8_add(e[i], c[i]));
        n[i] = t8_narrow(t8_pick(some, t8_mul(w[i], inv), up[i]));
    }
}

/* plain_surface's torus: the ray in the torus's space, the nearest point
 * there at t (torus_nearest), its normal through the transform
 * (xform_normal) made unit, and the point back in the world. */
__attribute__((always_inline)) static inline void
prepare8_torus(const scene *s, const scene_hit *hit, int lanes, int all, __m256 tt,
               const __m256 org[3], const __m256 d[3], __m256 P[3], __m256 N[3])
{
    prepare8_objs o;
    prepare8_objects(s, hit, lanes, offsetof(object, shape.torus), &o);
    __m256 lp[3], p[3], n[3], xn[3], wp[3], wn[3], inv[3][4], fwd[3][4];
    prepare8_matrix(&o, offsetof(xform, inv), inv);
    for (int r = 0; r < 3; r++)
        lp[r] = _mm256_add_ps(prepare8_row(inv, r, org, true),
                              _mm256_mul_ps(prepare8_row(inv, r, d, false), tt));
    prepare8_nearest(&o, lp, p, n);
    prepare8_matrix(&o, offsetof(xform, fwd), fwd);
    for (int c = 0; c < 3; c++) { /* the inverse's transpose */
        xn[c] = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(inv[0][c], n[0]), _mm256_mul_ps(inv[1][c], n[1])),
            _mm256_mul_ps(inv[2][c], n[2]));
        wp[c] = prepare8_row(fwd, c, p, true);
    }
    prepare8_norm(xn, wn);
    prepare8_put(lanes, all, wp, P);
    prepare8_put(lanes, all, wn, N);
}

/* prepare (bounce8_api.h): each kind's point and normal (the two normals
 * are here the same), then facing. */
__attribute__((always_inline)) static inline void prepare8(const scene *s, const ray8 *p,
                                                           shade8_plain kinds, const scene_hit *hit,
                                                           shade8 *sp)
{
    int all = kinds.sphere | kinds.plane | kinds.torus;
    const void *t[8];
    for (int k = 0, first = __builtin_ctz((unsigned)all); k < 8; k++)
        t[k] = &hit[all >> k & 1 ? k : first].h.t;
    const __m256 sign = _mm256_set1_ps(-0.0f), one = _mm256_set1_ps(1.0f);
    __m256 tt = simd8_at(t, 0), col[3];
    prepare8_groups mg; /* the lanes' materials: most often the packet's one */
    if (sp->same) {
        prepare8_one((const char *)sp->same, all, &mg);
    } else {
        const char *mat[8];
        for (int m = all; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            mat[k] = (const char *)sp->m[k];
        }
        prepare8_group(mat, all, &mg);
    }
    for (int i = 0; i < 3; i++)
        col[i] = prepare8_read(&mg, mg.at, offsetof(material, color) + (size_t)i * sizeof(float));
    __m256 d[3] = {_mm256_loadu_ps(p->dx), _mm256_loadu_ps(p->dy), _mm256_loadu_ps(p->dz)};
    __m256 org[3] = {_mm256_loadu_ps(p->ox), _mm256_loadu_ps(p->oy), _mm256_loadu_ps(p->oz)};
    __m256 P[3], N[3], dn[3];
    for (int i = 0; i < 3; i++)
        P[i] = N[i] = _mm256_setzero_ps();
    if (kinds.sphere)
        prepare8_sphere(s, hit, kinds.sphere, all, tt, org, d, P, N);
    if (kinds.plane)
        prepare8_plane(s, hit, kinds.plane, all, tt, org, d, P, N);
    if (kinds.torus)
        prepare8_torus(s, hit, kinds.torus, all, tt, org, d, P, N);
    prepare8_norm(d, dn);
    __m256 inside = _mm256_cmp_ps(simd8_dot(dn, N), _mm256_setzero_ps(), _CMP_GT_OQ);
    for (int i = 0; i < 3; i++) {
        __m256 f = _mm256_blendv_ps(N[i], _mm256_xor_ps(N[i], sign), inside);
        _mm256_storeu_ps(sp->p[i], P[i]);
        _mm256_storeu_ps(sp->n[i], f);
        _mm256_storeu_ps(sp->ng[i], f);
        _mm256_storeu_ps(sp->d[i], dn[i]);
        _mm256_storeu_ps(sp->base[i], _mm256_mul_ps(col[i], one));
    }
    sp->inside = (sp->inside & ~all) | (_mm256_movemask_ps(inside) & all);
}

#endif

/* prepare8: a packet's shading points eight lanes at once (bounce8_api.h:
 * prepare) where its rays hit one of the plain surfaces of shading.h: an
 * untextured, unturned sphere (shade_prepare's inline case), an
 * untextured, unturned plane, or an untextured torus turned by a fixed
 * transform (shading.c: plain_surface); an unturned quad, untextured or
 * with a flat texture (prepare8_texture.h), an untextured box or
 * cylinder, and a csg object's sphere, box or cylinder leaf, turned by a
 * fixed transform or not (shade_prepare_surface's general way). Lane by
 * lane the same floats as those, in the same order (no fused
 * multiply-adds): the torus's nearest point in doubles, as torus_nearest
 * (geom/shape_inline.h) works it out. For translation units compiled with
 * AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_PREPARE8_H
#define GLINT_TRACE_PREPARE8_H

#include "geom/csg.h"
#include "geom/torus8.h" /* eight lanes of doubles */
#include "trace/bounce8_api.h"
#include "trace/prepare8_read.h"
#include "trace/prepare8_texture.h"

/* plain_surface's plane: ray_at(t) moved onto the plane (plane_onto); its
 * normal. */
__attribute__((always_inline)) static inline void
prepare8_plane(const scene *s, const scene_hit *hit, int lanes, __m256 tt,
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
    prepare8_put(lanes, p, P);
    prepare8_put(lanes, n, N);
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

/* The lanes' points at tt in their objects' space: their rays through
 * the transforms' inverses (mat4_ray), then ray_at; the inverses' rows
 * into inv. */
__attribute__((always_inline)) static inline void
prepare8_local(const prepare8_objs *o, __m256 tt, const __m256 org[3], const __m256 d[3],
               __m256 inv[3][4], __m256 lp[3])
{
    prepare8_matrix(o, offsetof(xform, inv), inv);
    for (int r = 0; r < 3; r++)
        lp[r] = _mm256_add_ps(prepare8_row(inv, r, org, true),
                              _mm256_mul_ps(prepare8_row(inv, r, d, false), tt));
}

/* Points p and normals n of the objects' space back in the world, into
 * P and N for the lanes of `lanes`: each point through its transform
 * (mat4_point), each normal through the inverse's transpose
 * (xform_normal) and made unit. */
__attribute__((always_inline)) static inline void
prepare8_world(const prepare8_objs *o, __m256 inv[3][4], const __m256 p[3], const __m256 n[3],
               int lanes, __m256 P[3], __m256 N[3])
{
    __m256 fwd[3][4], xn[3], wp[3], wn[3];
    prepare8_matrix(o, offsetof(xform, fwd), fwd);
    for (int c = 0; c < 3; c++) {
        xn[c] = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(inv[0][c], n[0]), _mm256_mul_ps(inv[1][c], n[1])),
            _mm256_mul_ps(inv[2][c], n[2]));
        wp[c] = prepare8_row(fwd, c, p, true);
    }
    prepare8_norm(xn, wn);
    prepare8_put(lanes, wp, P);
    prepare8_put(lanes, wn, N);
}

/* plain_surface's torus: the nearest point in the torus's space at t
 * (torus_nearest) and its normal, back in the world. */
__attribute__((always_inline)) static inline void
prepare8_torus(const scene *s, const scene_hit *hit, int lanes, __m256 tt,
               const __m256 org[3], const __m256 d[3], __m256 P[3], __m256 N[3])
{
    prepare8_objs o;
    prepare8_objects(s, hit, lanes, offsetof(object, shape.torus), &o);
    __m256 lp[3], p[3], n[3], inv[3][4];
    prepare8_local(&o, tt, org, d, inv, lp);
    prepare8_nearest(&o, lp, p, n);
    prepare8_world(&o, inv, p, n, lanes, P, N);
}

/* quad_surface: the point from the hit's (u, v) = (b1, b2), (origin +
 * edge_u u) + edge_v v, and the quad's normal. */
__attribute__((always_inline)) static inline void
prepare8_quad(const scene *s, const scene_hit *hit, int lanes, __m256 b1, __m256 b2, __m256 P[3],
              __m256 N[3])
{
    prepare8_objs o;
    prepare8_objects(s, hit, lanes, offsetof(object, shape.quad), &o);
    __m256 p[3], n[3];
    for (int i = 0; i < 3; i++) {
        size_t at = (size_t)i * sizeof(float);
        __m256 org = prepare8_field(&o, false, offsetof(struct quad, origin) + at);
        __m256 eu = prepare8_field(&o, false, offsetof(struct quad, edge_u) + at);
        __m256 ev = prepare8_field(&o, false, offsetof(struct quad, edge_v) + at);
        p[i] = _mm256_add_ps(_mm256_add_ps(org, _mm256_mul_ps(eu, b1)), _mm256_mul_ps(ev, b2));
        n[i] = prepare8_field(&o, false, offsetof(struct quad, normal) + at);
    }
    prepare8_put(lanes, p, P);
    prepare8_put(lanes, n, N);
}

/* box_surface at the points lp of the boxes' space, on the faces part
 * (axis * 2 + side, side 1 the max face): each point moved onto its face
 * exactly, the face's normal. */
__attribute__((always_inline)) static inline void prepare8_box_at(const prepare8_objs *o,
                                                                  __m256i part,
                                                                  const __m256 lp[3],
                                                                  __m256 p[3], __m256 n[3])
{
    __m256i axis = _mm256_srli_epi32(part, 1);
    __m256 side = _mm256_castsi256_ps(_mm256_slli_epi32(part, 31)); /* the sign bit: side 1 */
    __m256 out = _mm256_blendv_ps(_mm256_set1_ps(-1.0f), _mm256_set1_ps(1.0f), side);
    for (int a = 0; a < 3; a++) {
        __m256 on = _mm256_castsi256_ps(_mm256_cmpeq_epi32(axis, _mm256_set1_epi32(a)));
        size_t at = (size_t)a * sizeof(float);
        __m256 face = _mm256_blendv_ps(prepare8_field(o, false, offsetof(struct box, lo) + at),
                                       prepare8_field(o, false, offsetof(struct box, hi) + at),
                                       side);
        p[a] = _mm256_blendv_ps(lp[a], face, on);
        n[a] = _mm256_and_ps(on, out);
    }
}

/* cylinder_surface_no_uv at the points lp of the cylinders' space: on the
 * side (part 0) the normal out from the axis, made unit, and the point put
 * back on the side; on a cap (1 bottom, 2 top) the point at the cap's
 * height and the normal down or up. */
__attribute__((always_inline)) static inline void
prepare8_cylinder_at(const prepare8_objs *o, __m256i part, const __m256 lp[3], __m256 p[3],
                     __m256 n[3])
{
    const __m256 zero = _mm256_setzero_ps();
    __m256 b[3], sn[3];
    for (int i = 0; i < 3; i++) {
        size_t at = offsetof(struct cylinder, base) + (size_t)i * sizeof(float);
        b[i] = prepare8_field(o, false, at);
    }
    __m256 rad = prepare8_field(o, false, offsetof(struct cylinder, radius));
    __m256 height = prepare8_field(o, false, offsetof(struct cylinder, height));
    __m256 side = _mm256_castsi256_ps(_mm256_cmpeq_epi32(part, _mm256_setzero_si256()));
    __m256 top = _mm256_castsi256_ps(_mm256_cmpeq_epi32(part, _mm256_set1_epi32(2)));
    __m256 radial[3] = {_mm256_sub_ps(lp[0], b[0]), zero, _mm256_sub_ps(lp[2], b[2])};
    prepare8_norm(radial, sn);
    __m256 cap_y = _mm256_add_ps(b[1], _mm256_and_ps(top, height));
    __m256 up = _mm256_blendv_ps(_mm256_set1_ps(-1.0f), _mm256_set1_ps(1.0f), top);
    p[0] = _mm256_blendv_ps(lp[0], _mm256_add_ps(b[0], _mm256_mul_ps(sn[0], rad)), side);
    p[1] = _mm256_blendv_ps(cap_y, lp[1], side);
    p[2] = _mm256_blendv_ps(lp[2], _mm256_add_ps(b[2], _mm256_mul_ps(sn[2], rad)), side);
    n[0] = _mm256_and_ps(side, sn[0]);
    n[1] = _mm256_blendv_ps(up, sn[1], side);
    n[2] = _mm256_and_ps(side, sn[2]);
}

/* sphere_surface_plain at the points lp of the spheres' space: the unit
 * normal from the centre, and the point put back on the sphere. */
__attribute__((always_inline)) static inline void prepare8_sphere_at(const prepare8_objs *o,
                                                                     const __m256 lp[3],
                                                                     __m256 p[3], __m256 n[3])
{
    __m256 rad = prepare8_field(o, false, offsetof(struct sphere, radius)), c[3], q[3];
    for (int i = 0; i < 3; i++) {
        size_t at = offsetof(struct sphere, center) + (size_t)i * sizeof(float);
        c[i] = prepare8_field(o, false, at);
        q[i] = _mm256_sub_ps(lp[i], c[i]);
    }
    prepare8_norm(q, n);
    for (int i = 0; i < 3; i++)
        p[i] = _mm256_add_ps(c[i], _mm256_mul_ps(n[i], rad));
}

/* The solids a packet's lanes hit, by kind. */
enum { PREPARE8_SPHERE, PREPARE8_BOX, PREPARE8_CYLINDER, PREPARE8_SOLIDS };

/* The solids of `kind` hit by the lanes of `lanes`, their shapes read
 * through sh and, where they are turned (turned), their transforms
 * through xo: each point and normal worked out in its shape's space, the
 * normals of the lanes of flip turned round (a csg leaf's), and brought
 * back to the world. */
__attribute__((always_inline)) static inline void
prepare8_solid_in(const prepare8_objs *sh, const prepare8_objs *xo, int lanes, int kind,
                  bool turned, int flip, __m256 tt, __m256i part, const __m256 org[3],
                  const __m256 d[3], __m256 P[3], __m256 N[3])
{
    __m256 lp[3], p[3], n[3], inv[3][4];
    if (turned)
        prepare8_local(xo, tt, org, d, inv, lp);
    else
        for (int i = 0; i < 3; i++)
            lp[i] = _mm256_add_ps(org[i], _mm256_mul_ps(d[i], tt));
    if (kind == PREPARE8_SPHERE)
        prepare8_sphere_at(sh, lp, p, n);
    else if (kind == PREPARE8_BOX)
        prepare8_box_at(sh, part, lp, p, n);
    else
        prepare8_cylinder_at(sh, part, lp, p, n);
    if (flip) {
        __m256 f = packet_lanes(flip);
        for (int i = 0; i < 3; i++)
            n[i] = _mm256_blendv_ps(n[i], _mm256_xor_ps(n[i], _mm256_set1_ps(-0.0f)), f);
    }
    if (turned) {
        prepare8_world(xo, inv, p, n, lanes, P, N);
    } else {
        prepare8_put(lanes, p, P);
        prepare8_put(lanes, n, N);
    }
}

/* The spheres, boxes or cylinders (kind) hit by the lanes of `lanes`,
 * turned ones (turned) worked out in their objects' space: shade_prepare's
 * sphere (sphere_surface_plain at ray_at(t)), box_surface's and
 * cylinder_surface_no_uv's points. */
__attribute__((always_inline)) static inline void
prepare8_solid(const scene *s, const scene_hit *hit, int lanes, int kind, bool turned,
               __m256 tt, __m256i part, const __m256 org[3], const __m256 d[3], __m256 P[3],
               __m256 N[3])
{
    prepare8_objs o;
    size_t off = kind == PREPARE8_SPHERE ? offsetof(object, shape.sphere)
                 : kind == PREPARE8_BOX  ? offsetof(object, shape.box)
                                         : offsetof(object, shape.cylinder);
    prepare8_objects(s, hit, lanes, off, &o);
    prepare8_solid_in(&o, &o, lanes, kind, turned, 0, tt, part, org, d, P, N);
}

/* csg_surface for the csg objects hit by the lanes of `lanes` (turned ones
 * if turned), whose hits are on leaves that are spheres, boxes or
 * cylinders in the csg's space (shading.h: shade_plain_leaf): each kind of
 * leaf's lanes together, every leaf read once. */
__attribute__((always_inline)) static inline void
prepare8_csg(const scene *s, const scene_hit *hit, int lanes, bool turned, __m256 tt,
             __m256i part, const __m256 org[3], const __m256 d[3], __m256 P[3], __m256 N[3])
{
    prepare8_objs xo, sh;
    prepare8_objects(s, hit, lanes, 0, &xo);
    const char *leaf[8];
    int flip = 0, of[PREPARE8_SOLIDS] = {0, 0, 0};
    for (int m = lanes; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        const csg_leaf *l = &s->objects[hit[k].object].shape.csg->leaves[hit[k].h.leaf];
        leaf[k] = (const char *)l;
        flip |= l->flip << k;
        of[l->shape.kind == SHAPE_SPHERE ? PREPARE8_SPHERE
           : l->shape.kind == SHAPE_BOX  ? PREPARE8_BOX
                                         : PREPARE8_CYLINDER] |= 1 << k;
    }
    for (int kind = 0; kind < PREPARE8_SOLIDS; kind++) {
        if (!of[kind])
            continue;
        prepare8_group(leaf, of[kind], &sh.g);
        for (int i = 0; i < sh.g.n; i++) /* the union's members all start there */
            sh.shape[i] = sh.g.at[i] + offsetof(csg_leaf, shape.sphere);
        prepare8_solid_in(&sh, &xo, of[kind], kind, turned, flip & of[kind], tt, part, org, d,
                          P, N);
    }
}

/* The float at byte off of each lane's hit (of its field t, hit[k].h.t
 * at t[k]), as eight loads; an int's bits with an int's offset. */
#define PREPARE8_HIT(t, field) \
    simd8_at(t, offsetof(scene_hit, h.field) - offsetof(scene_hit, h.t))

/* prepare (bounce8_api.h): each kind's point and normal (the two normals
 * are here the same), the chequers of the quads, then facing. */
__attribute__((always_inline)) static inline void prepare8(const scene *s, const float decode[256],
                                                           const ray8 *p,
                                                           const shade8_plain *kinds,
                                                           const scene_hit *hit, shade8 *sp)
{
    int solid = kinds->box | kinds->cylinder | kinds->csg;
    int all = kinds->sphere | kinds->plane | kinds->torus | kinds->quad | solid;
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
        col[i] = _mm256_mul_ps(
            prepare8_read(&mg, mg.at, offsetof(material, color) + (size_t)i * sizeof(float)), one);
    __m256 d[3] = {_mm256_loadu_ps(p->dx), _mm256_loadu_ps(p->dy), _mm256_loadu_ps(p->dz)};
    __m256 org[3] = {_mm256_loadu_ps(p->ox), _mm256_loadu_ps(p->oy), _mm256_loadu_ps(p->oz)};
    __m256 P[3], N[3], dn[3];
    for (int i = 0; i < 3; i++)
        P[i] = N[i] = _mm256_setzero_ps();
    if (kinds->sphere)
        prepare8_solid(s, hit, kinds->sphere, PREPARE8_SPHERE, false, tt, _mm256_setzero_si256(),
                       org, d, P, N);
    if (kinds->plane)
        prepare8_plane(s, hit, kinds->plane, tt, org, d, P, N);
    if (kinds->torus)
        prepare8_torus(s, hit, kinds->torus, tt, org, d, P, N);
    if (kinds->quad) {
        __m256 b1 = PREPARE8_HIT(t, b1), b2 = PREPARE8_HIT(t, b2), tex[3];
        prepare8_quad(s, hit, kinds->quad, b1, b2, P, N);
        if (prepare8_texture(s, decode, &mg, b1, b2, tex))
            for (int i = 0; i < 3; i++)
                col[i] = _mm256_mul_ps(col[i], tex[i]);
    }
    if (solid) {
        __m256i part = _mm256_castps_si256(PREPARE8_HIT(t, part));
        int box = kinds->box & ~kinds->turned, turned_box = kinds->box & kinds->turned;
        int cyl = kinds->cylinder & ~kinds->turned, turned_cyl = kinds->cylinder & kinds->turned;
        int csgs = kinds->csg & ~kinds->turned, turned_csg = kinds->csg & kinds->turned;
        if (box)
            prepare8_solid(s, hit, box, PREPARE8_BOX, false, tt, part, org, d, P, N);
        if (turned_box)
            prepare8_solid(s, hit, turned_box, PREPARE8_BOX, true, tt, part, org, d, P, N);
        if (cyl)
            prepare8_solid(s, hit, cyl, PREPARE8_CYLINDER, false, tt, part, org, d, P, N);
        if (turned_cyl)
            prepare8_solid(s, hit, turned_cyl, PREPARE8_CYLINDER, true, tt, part, org, d, P, N);
        if (csgs)
            prepare8_csg(s, hit, csgs, false, tt, part, org, d, P, N);
        if (turned_csg)
            prepare8_csg(s, hit, turned_csg, true, tt, part, org, d, P, N);
    }
    prepare8_norm(d, dn);
    __m256 inside = _mm256_cmp_ps(simd8_dot(dn, N), _mm256_setzero_ps(), _CMP_GT_OQ);
    for (int i = 0; i < 3; i++) {
        __m256 f = _mm256_blendv_ps(N[i], _mm256_xor_ps(N[i], sign), inside), pi = P[i];
        /* through a register: else the stores of P's lanes, kept on the
         * stack, are merged into wider copies that wait for them */
        __asm__("" : "+x"(pi));
        _mm256_storeu_ps(sp->p[i], pi);
        _mm256_storeu_ps(sp->n[i], f);
        _mm256_storeu_ps(sp->ng[i], f);
        _mm256_storeu_ps(sp->d[i], dn[i]);
        _mm256_storeu_ps(sp->base[i], col[i]);
    }
    sp->inside = (sp->inside & ~all) | (_mm256_movemask_ps(inside) & all);
}

#endif

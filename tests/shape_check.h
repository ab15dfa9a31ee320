/* shape_check: assertions about shapes shared by the shape tests: a hit
 * with its point, normal and (u, v), a miss, the occlusion twin agreeing
 * with intersect, a one-object scene, and that rays leaving a convex
 * surface never meet it again.
 *
 * Tolerances: TOL (1e-5) on t, points, normals and (u, v) of hand-computed
 * hits (a few float ulps at the magnitudes used, which are below 20); XTOL
 * (1e-4) on hits through a transform, whose matrices hold rounded sines and
 * cosines. */
#ifndef GLINT_TESTS_SHAPE_CHECK_H
#define GLINT_TESTS_SHAPE_CHECK_H

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>

#include "core/mat4.h"
#include "core/rng.h"
#include "geom/shape.h"
#include "scene/scene.h"
#include "shade/material.h"
#include "near.h"

#define TOL 1e-5
#define XTOL 1e-4

/* ---- helpers ------------------------------------------------------------- */

/* Intersects and, on a hit, fills the surface; asserts the normal is unit. */
static inline bool hit_surface(const shape *s, ray r, shape_hit *h, surface *sf)
{
    bool hit = shape_intersect(s, &r, h);
    cr_assert_eq(shape_occluded(s, &r), hit, "occluded disagrees with intersect");
    if (!hit)
        return false;
    shape_surface(s, &r, h, sf);
    ASSERT_NEAR(v3_len(sf->n), 1.0, TOL);
    ASSERT_NEAR(v3_len(sf->ng), 1.0, TOL);
    return true;
}

static inline void expect_miss(const shape *s, ray r)
{
    shape_hit h;
    cr_assert_not(shape_intersect(s, &r, &h), "unexpected hit at t = %.9g", (double)h.t);
    cr_assert_not(shape_occluded(s, &r), "occluded reports a hit that intersect does not");
}

/* Expects a hit at t with point p, normal n and (u, v); u < 0 skips (u, v). */
static inline void expect_hit(const shape *s, ray r, double t, vec3 p, vec3 n, double u, double v)
{
    shape_hit h;
    surface sf;
    cr_assert(hit_surface(s, r, &h, &sf), "expected a hit at t = %g", t);
    ASSERT_NEAR(h.t, t, TOL);
    ASSERT_V3_NEAR(sf.p, p.x, p.y, p.z, TOL);
    ASSERT_V3_NEAR(sf.n, n.x, n.y, n.z, TOL);
    if (u >= 0.0) {
        ASSERT_NEAR(sf.u, u, TOL);
        ASSERT_NEAR(sf.v, v, TOL);
    }
}

static inline vec3 rand_in_box(rng *g, aabb b)
{
    return v3(b.lo.x + (b.hi.x - b.lo.x) * rng_float(g), b.lo.y + (b.hi.y - b.lo.y) * rng_float(g),
              b.lo.z + (b.hi.z - b.lo.z) * rng_float(g));
}

/* A scene with one object (default material) and an optional transform. */
static inline scene *one_object(shape sh, const xform *x)
{
    scene *s = scene_new();
    cr_assert_not_null(s);
    material m = material_default();
    cr_assert_eq(scene_add_material(s, &m), 0);
    int xi = -1;
    if (x) {
        xi = scene_add_xform(s, x);
        cr_assert_geq(xi, 0);
    }
    cr_assert_geq(scene_add_object(s, &sh, 0, xi), 0);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* ---- no self-intersection from a convex surface --------------------------- */

/* Finds surface points with rays from a sphere around the shape aimed at
 * random points of its bounds, then sends a ray from each point into a
 * random direction of the normal's hemisphere, starting where ray_offset
 * puts it. Half the directions are near-tangent (the normal's share between
 * 1e-4 and 1e-2), the hardest case. None may meet the shape again. */
static inline void expect_no_rehit(const char *name, shape sh, const xform *x, uint64_t seed)
{
    enum { RAYS = 100000 };
    scene *s = one_object(sh, x);
    aabb b = s->bounds[0];
    vec3 c = aabb_center(b);
    float R = 2.0f * v3_len(aabb_extent(b)) + 1.0f;
    rng g = rng_seed(seed, 3);
    int tested = 0, rehits = 0;
    char first[256] = "";
    while (tested < RAYS) {
        vec3 o = v3_madd(c, rng_unit_dir(&g), R);
        ray r = ray_make(o, v3_sub(rand_in_box(&g, b), o), INFINITY);
        scene_hit h;
        if (!scene_intersect(s, &r, &h))
            continue;
        surface sf;
        scene_surface(s, &r, &h, &sf);
        vec3 d;
        if (tested % 2 == 0) {
            d = rng_unit_dir(&g);
        } else {
            vec3 t = v3_norm(v3_cross(sf.ng, rng_unit_dir(&g)));
            d = v3_norm(v3_madd(t, sf.ng, 1e-4f + 1e-2f * rng_float(&g)));
        }
        float dn = v3_dot(d, sf.ng);
        if (dn == 0.0f)
            continue;
        if (dn < 0.0f)
            d = v3_neg(d);
        ray out = ray_make(ray_offset(sf.p, sf.ng, d), d, INFINITY);
        scene_hit h2;
        bool again = scene_intersect(s, &out, &h2);
        bool occ = scene_occluded_opaque(s, &out);
        if ((again || occ) && rehits++ == 0)
            snprintf(first, sizeof first,
                     "p (%.9g %.9g %.9g) ng (%.9g %.9g %.9g) d (%.9g %.9g %.9g) t %.9g occ %d",
                     (double)sf.p.x, (double)sf.p.y, (double)sf.p.z, (double)sf.ng.x,
                     (double)sf.ng.y, (double)sf.ng.z, (double)d.x, (double)d.y, (double)d.z,
                     again ? (double)h2.h.t : -1.0, occ);
        tested++;
    }
    scene_free(s);
    cr_assert_eq(rehits, 0, "%s: %d of %d rays re-hit the surface they left; first: %s", name,
                 rehits, RAYS, first);
}

#endif

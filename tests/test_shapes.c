/* Shapes (src/geom): for each primitive a hit at a hand-computed t with its
 * unit outward normal and (u, v), a miss, a tangent or grazing ray, a ray
 * starting inside, culling by tmax (the interval is open), and agreement of
 * the occlusion twin with intersect on fixed-seed random rays. Then shapes
 * placed through the scene's object transforms (a rotated box and an
 * ellipsoid, normals through the inverse transpose), and the property that
 * a ray leaving a convex surface outward, from an origin placed by the
 * documented ray_offset rule, never meets the same shape again.
 *
 * Tolerances: 1e-5 on t, points, normals and (u, v) of hand-computed hits
 * (a few float ulps at the magnitudes used, which are below 20); 1e-4 on
 * hits through a transform, whose matrices hold rounded sines and cosines. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/mat4.h"
#include "core/rng.h"
#include "geom/shape.h"
#include "scene/scene.h"
#include "shade/material.h"
#include "near.h"
#include "shape_check.h"

/* ---- sphere -------------------------------------------------------------- */

/* Centre (1, 2, 3), radius 2. The hit's direction from the centre is
 * n = (0.48, 0.6, 0.64), so u = 0.5 + atan2(0.48, 0.64) / 2pi and
 * v = 0.5 + asin(0.6) / pi. */
Test(shapes, sphere_hit_known_t)
{
    shape s = shape_sphere(v3(1, 2, 3), 2);
    expect_hit(&s, ray_make(v3(1, 2, 10), v3(0, 0, -1), INFINITY), 5.0, v3(1, 2, 5), v3(0, 0, 1),
               0.5, 0.5);
    double u = 0.5 + atan2(0.48, 0.64) / (2 * M_PI), v = 0.5 + asin(0.6) / M_PI;
    expect_hit(&s, ray_make(v3(1.96f, 3.2f, 10), v3(0, 0, -1), INFINITY), 5.72,
               v3(1.96f, 3.2f, 4.28f), v3(0.48f, 0.6f, 0.64f), u, v);
    /* A direction of length 2 halves t. */
    expect_hit(&s, ray_make(v3(1, 2, 10), v3(0, 0, -2), INFINITY), 2.5, v3(1, 2, 5), v3(0, 0, 1),
               0.5, 0.5);
    cr_assert(shape_is_convex(&s));
}

Test(shapes, sphere_miss)
{
    shape s = shape_sphere(v3(1, 2, 3), 2);
    expect_miss(&s, ray_make(v3(3.5f, 2, 10), v3(0, 0, -1), INFINITY)); /* passes beside */
    expect_miss(&s, ray_make(v3(1, 2, 10), v3(0, 0, 1), INFINITY));     /* points away */
}

/* A ray touching the sphere at (3, 2, 3): reported there (the two roots
 * coincide) with the normal perpendicular to the ray; a hair outside misses
 * and a hair inside hits close to the tangent point. */
Test(shapes, sphere_tangent)
{
    shape s = shape_sphere(v3(1, 2, 3), 2);
    shape_hit h;
    surface sf;
    if (hit_surface(&s, ray_make(v3(3, 2, 10), v3(0, 0, -1), INFINITY), &h, &sf)) {
        ASSERT_NEAR(h.t, 7.0, TOL);
        ASSERT_V3_NEAR(sf.n, 1, 0, 0, TOL);
    }
    expect_miss(&s, ray_make(v3(3.001f, 2, 10), v3(0, 0, -1), INFINITY));
    cr_assert(hit_surface(&s, ray_make(v3(2.999f, 2, 10), v3(0, 0, -1), INFINITY), &h, &sf));
    /* depth of the chord: sqrt(4 - 1.999^2) = 0.0632 */
    ASSERT_NEAR(h.t, 7.0 - sqrt(4.0 - 1.999 * 1.999), 1e-4);
}

Test(shapes, sphere_inside_hits_far_side_with_outward_normal)
{
    shape s = shape_sphere(v3(1, 2, 3), 2);
    expect_hit(&s, ray_make(v3(1, 2, 3), v3(0, 1, 0), INFINITY), 2.0, v3(1, 4, 3), v3(0, 1, 0),
               0.5, 1.0);
    expect_hit(&s, ray_make(v3(1, 2, 4), v3(0, 0, -1), INFINITY), 3.0, v3(1, 2, 1), v3(0, 0, -1),
               -1, 0);
}

/* Centre 0, radius 1, ray from z = 6 down z: roots exactly 5 and 7. */
Test(shapes, sphere_tmax_culls)
{
    shape s = shape_sphere(v3(0, 0, 0), 1);
    ray r = ray_make(v3(0, 0, 6), v3(0, 0, -1), 4.9f);
    expect_miss(&s, r);
    r.tmax = 5.0f; /* open interval: t == tmax is not a hit, and 7 is beyond */
    expect_miss(&s, r);
    r.tmax = nextafterf(5.0f, 6.0f);
    expect_hit(&s, r, 5.0, v3(0, 0, 1), v3(0, 0, 1), -1, 0);
    /* tmin past the near root gives the far one; tmin past both, nothing. */
    r = ray_make(v3(0, 0, 6), v3(0, 0, -1), INFINITY);
    r.tmin = 5.0f;
    expect_hit(&s, r, 7.0, v3(0, 0, -1), v3(0, 0, -1), -1, 0);
    r.tmin = 7.0f;
    expect_miss(&s, r);
}

/* ---- plane --------------------------------------------------------------- */

Test(shapes, plane_hit_known_t)
{
    shape s = shape_plane(v3(0, -1, 0), v3(0, 2, 0)); /* normal normalised by the constructor */
    const struct plane *pl = &s.plane;
    ASSERT_V3_NEAR(pl->normal, 0, 1, 0, TOL);
    /* The tangents are unit, orthogonal, and tu x tv = normal. */
    ASSERT_NEAR(v3_len(pl->tu), 1.0, TOL);
    ASSERT_NEAR(v3_len(pl->tv), 1.0, TOL);
    ASSERT_NEAR(v3_dot(pl->tu, pl->tv), 0.0, TOL);
    vec3 c = v3_cross(pl->tu, pl->tv);
    ASSERT_V3_NEAR(c, 0, 1, 0, TOL);

    shape_hit h;
    surface sf;
    cr_assert(hit_surface(&s, ray_make(v3(2, 3, 5), v3(0, -1, 0), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 4.0, TOL);
    ASSERT_V3_NEAR(sf.p, 2, -1, 5, TOL);
    ASSERT_V3_NEAR(sf.n, 0, 1, 0, TOL);
    /* (u, v) are world units along the tangents from the plane's point. */
    ASSERT_NEAR(sf.u, v3_dot(v3(2, 0, 5), pl->tu), TOL);
    ASSERT_NEAR(sf.v, v3_dot(v3(2, 0, 5), pl->tv), TOL);
    ASSERT_NEAR(sf.u * sf.u + sf.v * sf.v, 29.0, 1e-4);
    /* From below: the same point, and the normal stays the plane's. */
    expect_hit(&s, ray_make(v3(2, -4, 5), v3(0, 1, 0), INFINITY), 3.0, v3(2, -1, 5), v3(0, 1, 0),
               -1, 0);
    /* Oblique: from (0, 1, 0) along (1, -1, 0) reaches y = -1 at t = 2. */
    expect_hit(&s, ray_make(v3(0, 1, 0), v3(1, -1, 0), INFINITY), 2.0, v3(2, -1, 0), v3(0, 1, 0),
               -1, 0);
}

Test(shapes, plane_miss_parallel_and_grazing)
{
    shape s = shape_plane(v3(0, -1, 0), v3(0, 1, 0));
    expect_miss(&s, ray_make(v3(0, 3, 0), v3(0, 1, 0), INFINITY));  /* away */
    expect_miss(&s, ray_make(v3(0, 3, 0), v3(1, 0, 0), INFINITY));  /* parallel above */
    expect_miss(&s, ray_make(v3(0, -1, 0), v3(1, 0, 1), INFINITY)); /* in the plane */
    /* Grazing: slope 1e-3 reaches the plane 1000 units on. */
    shape_hit h;
    surface sf;
    cr_assert(hit_surface(&s, ray_make(v3(0, 0, 0), v3(1, -1e-3f, 0), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 1000.0, 1e-2);
}

Test(shapes, plane_tmax_culls)
{
    shape s = shape_plane(v3(0, -1, 0), v3(0, 1, 0));
    expect_miss(&s, ray_make(v3(0, 3, 0), v3(0, -1, 0), 4.0f));
    expect_hit(&s, ray_make(v3(0, 3, 0), v3(0, -1, 0), 4.01f), 4.0, v3(0, -1, 0), v3(0, 1, 0), -1,
               0);
}

/* ---- quad ---------------------------------------------------------------- */

/* Origin (1, 1, 0), edges (2, 0, 0) and (0, 4, 0): normal +z. */
Test(shapes, quad_hit_known_t_and_uv_corners)
{
    shape s = shape_quad(v3(1, 1, 0), v3(2, 0, 0), v3(0, 4, 0));
    expect_hit(&s, ray_make(v3(1.5f, 4, 5), v3(0, 0, -1), INFINITY), 5.0, v3(1.5f, 4, 0),
               v3(0, 0, 1), 0.25, 0.75);
    /* From behind: the same normal (edge_u x edge_v). */
    expect_hit(&s, ray_make(v3(2, 3, -2), v3(0, 0, 1), INFINITY), 2.0, v3(2, 3, 0), v3(0, 0, 1),
               0.5, 0.5);
    /* The corners, inclusive. */
    const float cu[4] = {0, 1, 0, 1}, cv[4] = {0, 0, 1, 1};
    for (int i = 0; i < 4; i++) {
        vec3 p = v3(1 + 2 * cu[i], 1 + 4 * cv[i], 0);
        expect_hit(&s, ray_make(v3_add(p, v3(0, 0, 1)), v3(0, 0, -1), INFINITY), 1.0, p,
                   v3(0, 0, 1), cu[i], cv[i]);
    }
}

Test(shapes, quad_miss_parallel_and_tmax)
{
    shape s = shape_quad(v3(1, 1, 0), v3(2, 0, 0), v3(0, 4, 0));
    expect_miss(&s, ray_make(v3(3.01f, 2, 5), v3(0, 0, -1), INFINITY)); /* beside edge u = 1 */
    expect_miss(&s, ray_make(v3(2, 0.99f, 5), v3(0, 0, -1), INFINITY)); /* below v = 0 */
    expect_miss(&s, ray_make(v3(0, 2, 0), v3(1, 0, 0), INFINITY));      /* in its plane */
    expect_miss(&s, ray_make(v3(2, 2, 5), v3(0, 0, -1), 5.0f));
    expect_hit(&s, ray_make(v3(2, 2, 5), v3(0, 0, -1), 5.01f), 5.0, v3(2, 2, 0), v3(0, 0, 1), 0.5,
               0.25);
}

/* A skewed parallelogram: (u, v) are coordinates along the edges. */
Test(shapes, quad_skewed_uv)
{
    shape s = shape_quad(v3(0, 0, 0), v3(2, 0, 0), v3(1, 2, 0));
    /* origin + 0.5 edge_u + 0.25 edge_v = (1.25, 0.5, 0) */
    expect_hit(&s, ray_make(v3(1.25f, 0.5f, 3), v3(0, 0, -1), INFINITY), 3.0,
               v3(1.25f, 0.5f, 0), v3(0, 0, 1), 0.5, 0.25);
    expect_miss(&s, ray_make(v3(0.1f, 1.5f, 3), v3(0, 0, -1), INFINITY)); /* left of the slant */
}

/* ---- box ----------------------------------------------------------------- */

/* Box [-1, 1] x [-2, 2] x [-3, 3]. Face f = axis*2 + (max side); (u, v) run
 * along the next two axes in cyclic order. */
Test(shapes, box_hit_known_t)
{
    shape s = shape_box(v3(1, 2, 3), v3(-1, -2, -3)); /* corners in any order */
    ASSERT_V3_NEAR(s.box.lo, -1, -2, -3, 0);
    shape_hit h;
    surface sf;
    /* +z face: u along x, v along y. */
    cr_assert(hit_surface(&s, ray_make(v3(0.5f, -1, 10), v3(0, 0, -1), INFINITY), &h, &sf));
    cr_assert_eq(h.part, 5);
    ASSERT_NEAR(h.t, 7.0, TOL);
    ASSERT_V3_NEAR(sf.n, 0, 0, 1, TOL);
    ASSERT_NEAR(sf.u, 0.75, TOL);
    ASSERT_NEAR(sf.v, 0.25, TOL);
    /* -x face: u along y, v along z. */
    cr_assert(hit_surface(&s, ray_make(v3(-5, 1, -1.5f), v3(1, 0, 0), INFINITY), &h, &sf));
    cr_assert_eq(h.part, 0);
    ASSERT_NEAR(h.t, 4.0, TOL);
    ASSERT_V3_NEAR(sf.p, -1, 1, -1.5, TOL);
    ASSERT_V3_NEAR(sf.n, -1, 0, 0, TOL);
    ASSERT_NEAR(sf.u, 0.75, TOL);
    ASSERT_NEAR(sf.v, 0.25, TOL);
    /* +y face from above, obliquely: from (0, 6, 0) along (0.125, -1, 0.5). */
    cr_assert(hit_surface(&s, ray_make(v3(0, 6, 0), v3(0.125f, -1, 0.5f), INFINITY), &h, &sf));
    cr_assert_eq(h.part, 3);
    ASSERT_NEAR(h.t, 4.0, TOL);
    ASSERT_V3_NEAR(sf.p, 0.5, 2, 2, TOL);
    ASSERT_V3_NEAR(sf.n, 0, 1, 0, TOL);
    ASSERT_NEAR(sf.u, 5.0 / 6.0, TOL); /* z: (2 + 3) / 6 */
    ASSERT_NEAR(sf.v, 0.75, TOL);      /* x: (0.5 + 1) / 2 */
}

Test(shapes, box_miss)
{
    shape s = shape_box(v3(-1, -2, -3), v3(1, 2, 3));
    expect_miss(&s, ray_make(v3(0, 0, 10), v3(0, 0, 1), INFINITY));   /* away */
    expect_miss(&s, ray_make(v3(5, 0, 10), v3(0, 0, -1), INFINITY));  /* beside */
    expect_miss(&s, ray_make(v3(0, 0, 10), v3(1, 1, -1), INFINITY));  /* passes the corner */
}

/* Rays with zero direction components: outside a slab they miss, inside it
 * they are unconstrained by it, and on its boundary plane they graze the
 * face and still hit the face they run into. */
Test(shapes, box_rays_parallel_to_faces)
{
    shape s = shape_box(v3(-1, -2, -3), v3(1, 2, 3));
    expect_miss(&s, ray_make(v3(0, 2.5f, 10), v3(0, 0, -1), INFINITY));
    expect_miss(&s, ray_make(v3(-1.5f, 0, 10), v3(0, 0, -1), INFINITY));
    expect_miss(&s, ray_make(v3(0, 2.5f, 10), v3(-0.0f, 0.0f, -1), INFINITY));
    expect_hit(&s, ray_make(v3(0.5f, 1, 10), v3(0, 0, -1), INFINITY), 7.0, v3(0.5f, 1, 3),
               v3(0, 0, 1), 0.75, 0.75);
    /* negative zero is still zero */
    expect_hit(&s, ray_make(v3(0.5f, 1, 10), v3(-0.0f, -0.0f, -1), INFINITY), 7.0,
               v3(0.5f, 1, 3), v3(0, 0, 1), 0.75, 0.75);
    /* In the plane y = 2 of the +y face: grazes it, enters through +z. */
    expect_hit(&s, ray_make(v3(0, 2, 10), v3(0, 0, -1), INFINITY), 7.0, v3(0, 2, 3), v3(0, 0, 1),
               0.5, 1.0);
    /* Along the edge x = 1, y = 2. */
    shape_hit h;
    surface sf;
    cr_assert(hit_surface(&s, ray_make(v3(1, 2, 10), v3(0, 0, -1), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 7.0, TOL);
    /* Diagonal in the xz plane with dy = 0, inside the y slab. */
    expect_hit(&s, ray_make(v3(4, 0, 0), v3(-1, 0, 0.5f), INFINITY), 3.0, v3(1, 0, 1.5f),
               v3(1, 0, 0), 0.5, 0.75);
}

Test(shapes, box_inside_hits_far_side_with_outward_normal)
{
    shape s = shape_box(v3(-1, -2, -3), v3(1, 2, 3));
    expect_hit(&s, ray_make(v3(0, 0, 0), v3(1, 0, 0), INFINITY), 1.0, v3(1, 0, 0), v3(1, 0, 0),
               0.5, 0.5);
    expect_hit(&s, ray_make(v3(0, 0, 0), v3(0, -1, 0), INFINITY), 2.0, v3(0, -2, 0),
               v3(0, -1, 0), 0.5, 0.5);
    expect_hit(&s, ray_make(v3(0.5f, 0, 1), v3(0, 0, -2), INFINITY), 2.0, v3(0.5f, 0, -3),
               v3(0, 0, -1), 0.75, 0.5);
}

Test(shapes, box_tmax_culls)
{
    shape s = shape_box(v3(-1, -2, -3), v3(1, 2, 3));
    ray r = ray_make(v3(0, 0, 10), v3(0, 0, -1), 7.0f);
    expect_miss(&s, r); /* near face at 7 == tmax; far face at 13 is beyond */
    r.tmax = 7.01f;
    expect_hit(&s, r, 7.0, v3(0, 0, 3), v3(0, 0, 1), -1, 0);
    r.tmax = INFINITY;
    r.tmin = 7.0f;
    expect_hit(&s, r, 13.0, v3(0, 0, -3), v3(0, 0, -1), -1, 0);
}

/* ---- cylinder ------------------------------------------------------------ */

/* Base (1, 0, 0), radius 2, height 4, capped. Side: u = 0.5 facing +z,
 * v = height fraction; caps: the disc mapped onto [0, 1]^2. */
Test(shapes, cylinder_hit_known_t)
{
    shape s = shape_cylinder(v3(1, 0, 0), 2, 4, true);
    expect_hit(&s, ray_make(v3(1, 1, 10), v3(0, 0, -1), INFINITY), 8.0, v3(1, 1, 2), v3(0, 0, 1),
               0.5, 0.25);
    /* The side at n = (0.6, 0, 0.8): x = 1 + 1.2, z = 1.6. */
    expect_hit(&s, ray_make(v3(2.2f, 3, 10), v3(0, 0, -1), INFINITY), 8.4, v3(2.2f, 3, 1.6f),
               v3(0.6f, 0, 0.8f), 0.5 + atan2(0.6, 0.8) / (2 * M_PI), 0.75);
    /* +x side: u = 0.75. */
    expect_hit(&s, ray_make(v3(10, 2, 0), v3(-1, 0, 0), INFINITY), 7.0, v3(3, 2, 0), v3(1, 0, 0),
               0.75, 0.5);
    /* Top cap at (2, 4, 1): u = 0.5 + 0.5 * 1/2, v = 0.5 - 0.5 * 1/2. */
    expect_hit(&s, ray_make(v3(2, 9, 1), v3(0, -1, 0), INFINITY), 5.0, v3(2, 4, 1), v3(0, 1, 0),
               0.75, 0.25);
    /* Bottom cap at (2, 0, 1): v mirrored, as seen from below. */
    expect_hit(&s, ray_make(v3(2, -3, 1), v3(0, 1, 0), INFINITY), 3.0, v3(2, 0, 1), v3(0, -1, 0),
               0.75, 0.75);
    cr_assert(shape_is_convex(&s));
    shape open = shape_cylinder(v3(1, 0, 0), 2, 4, false);
    cr_assert_not(shape_is_convex(&open));
}

Test(shapes, cylinder_miss)
{
    shape s = shape_cylinder(v3(1, 0, 0), 2, 4, true);
    expect_miss(&s, ray_make(v3(1, 4.5f, 10), v3(0, 0, -1), INFINITY)); /* above */
    expect_miss(&s, ray_make(v3(1, -0.5f, 10), v3(0, 0, -1), INFINITY)); /* below */
    expect_miss(&s, ray_make(v3(3.5f, 2, 10), v3(0, 0, -1), INFINITY)); /* beside */
    expect_miss(&s, ray_make(v3(4, 9, 0), v3(0, -1, 0), INFINITY));    /* parallel to the axis */
    /* Uncapped: straight down the axis passes through. */
    shape open = shape_cylinder(v3(1, 0, 0), 2, 4, false);
    expect_miss(&open, ray_make(v3(1, 9, 0), v3(0, -1, 0), INFINITY));
}

Test(shapes, cylinder_tangent)
{
    shape s = shape_cylinder(v3(1, 0, 0), 2, 4, true);
    shape_hit h;
    surface sf;
    /* touches the side line x = 3, z = 0 */
    if (hit_surface(&s, ray_make(v3(3, 2, 10), v3(0, 0, -1), INFINITY), &h, &sf)) {
        ASSERT_NEAR(h.t, 10.0, TOL);
        ASSERT_V3_NEAR(sf.n, 1, 0, 0, TOL);
    }
    expect_miss(&s, ray_make(v3(3.001f, 2, 10), v3(0, 0, -1), INFINITY));
    /* grazes the top rim: in the plane y = 4, enters the cap's edge */
    cr_assert(hit_surface(&s, ray_make(v3(1, 4, 10), v3(0, 0, -1), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 8.0, TOL);
    ASSERT_V3_NEAR(sf.p, 1, 4, 2, TOL);
}

Test(shapes, cylinder_inside_hits_far_side_with_outward_normal)
{
    shape s = shape_cylinder(v3(1, 0, 0), 2, 4, true);
    expect_hit(&s, ray_make(v3(1, 1, 0), v3(1, 0, 0), INFINITY), 2.0, v3(3, 1, 0), v3(1, 0, 0),
               0.75, 0.25);
    expect_hit(&s, ray_make(v3(1, 1, 0), v3(0, 1, 0), INFINITY), 3.0, v3(1, 4, 0), v3(0, 1, 0),
               0.5, 0.5);
    expect_hit(&s, ray_make(v3(1, 1, 0), v3(0, -1, 0), INFINITY), 1.0, v3(1, 0, 0), v3(0, -1, 0),
               0.5, 0.5);
    /* Open cylinder seen from inside: the far wall, normal still away from
     * the axis ((u, v) not checked: -z is the seam, u = 0 or 1). */
    shape open = shape_cylinder(v3(1, 0, 0), 2, 4, false);
    expect_hit(&open, ray_make(v3(1, 1, 0), v3(0, 0, -1), INFINITY), 2.0, v3(1, 1, -2),
               v3(0, 0, -1), -1, 0);
    expect_hit(&open, ray_make(v3(1, 1, 0), v3(0, 0.5f, 1), INFINITY), 2.0, v3(1, 2, 2),
               v3(0, 0, 1), 0.5, 0.5);
}

Test(shapes, cylinder_tmax_culls)
{
    shape s = shape_cylinder(v3(1, 0, 0), 2, 4, true);
    ray r = ray_make(v3(1, 1, 10), v3(0, 0, -1), 8.0f);
    expect_miss(&s, r);
    r.tmax = 8.01f;
    expect_hit(&s, r, 8.0, v3(1, 1, 2), v3(0, 0, 1), -1, 0);
    r = ray_make(v3(2, 9, 1), v3(0, -1, 0), 5.0f); /* the cap */
    expect_miss(&s, r);
    r.tmin = 5.0f;
    r.tmax = INFINITY;
    expect_hit(&s, r, 9.0, v3(2, 0, 1), v3(0, -1, 0), -1, 0);
}

/* ---- triangle ------------------------------------------------------------ */

/* (0,0,0) (2,0,0) (0,2,0): front (counter-clockwise) faces +z. */
Test(shapes, triangle_hit_known_t)
{
    shape s = shape_triangle(v3(0, 0, 0), v3(2, 0, 0), v3(0, 2, 0));
    shape_hit h;
    surface sf;
    cr_assert(hit_surface(&s, ray_make(v3(0.5f, 1, 3), v3(0, 0, -1), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 3.0, TOL);
    ASSERT_NEAR(h.b1, 0.25, TOL);
    ASSERT_NEAR(h.b2, 0.5, TOL);
    ASSERT_V3_NEAR(sf.p, 0.5, 1, 0, TOL);
    ASSERT_V3_NEAR(sf.n, 0, 0, 1, TOL);
    ASSERT_NEAR(sf.u, 0.25, TOL); /* default uv: the barycentrics */
    ASSERT_NEAR(sf.v, 0.5, TOL);
    /* From behind: same geometric normal. */
    expect_hit(&s, ray_make(v3(0.5f, 1, -1), v3(0, 0, 1), INFINITY), 1.0, v3(0.5f, 1, 0),
               v3(0, 0, 1), 0.25, 0.5);
    /* Custom per-corner (u, v) interpolate: b0 = 0.25, b1 = 0.25, b2 = 0.5. */
    s.triangle.uv[0][0] = 0.2f, s.triangle.uv[0][1] = 0.4f;
    s.triangle.uv[1][0] = 1.0f, s.triangle.uv[1][1] = 0.0f;
    s.triangle.uv[2][0] = 0.6f, s.triangle.uv[2][1] = 1.0f;
    expect_hit(&s, ray_make(v3(0.5f, 1, 3), v3(0, 0, -1), INFINITY), 3.0, v3(0.5f, 1, 0),
               v3(0, 0, 1), 0.25 * 0.2 + 0.25 * 1.0 + 0.5 * 0.6, 0.25 * 0.4 + 0.5 * 1.0);
    /* Clockwise order flips the normal. */
    shape cw = shape_triangle(v3(0, 0, 0), v3(0, 2, 0), v3(2, 0, 0));
    expect_hit(&cw, ray_make(v3(0.5f, 1, 3), v3(0, 0, -1), INFINITY), 3.0, v3(0.5f, 1, 0),
               v3(0, 0, -1), -1, 0);
}

Test(shapes, triangle_miss_edge_and_parallel)
{
    shape s = shape_triangle(v3(0, 0, 0), v3(2, 0, 0), v3(0, 2, 0));
    expect_miss(&s, ray_make(v3(1.1f, 1.1f, 3), v3(0, 0, -1), INFINITY)); /* past the hypotenuse */
    expect_miss(&s, ray_make(v3(-0.1f, 1, 3), v3(0, 0, -1), INFINITY));
    expect_miss(&s, ray_make(v3(-1, 0.5f, 0), v3(1, 0, 0), INFINITY)); /* in its plane */
    expect_miss(&s, ray_make(v3(0.5f, 0.5f, 3), v3(0, 0, -1), 3.0f));  /* tmax */
    expect_hit(&s, ray_make(v3(0.5f, 0.5f, 3), v3(0, 0, -1), 3.01f), 3.0, v3(0.5f, 0.5f, 0),
               v3(0, 0, 1), -1, 0);
    /* A ray through a vertex or along an edge's point counts (edges are inclusive). */
    shape_hit h;
    surface sf;
    cr_assert(hit_surface(&s, ray_make(v3(1, 1, 3), v3(0, 0, -1), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 3.0, TOL);
}

/* Two triangles sharing the edge (0,0,0)-(1,1,0): rays through points on
 * that edge, from random origins, never slip between them (watertight). */
Test(shapes, triangle_shared_edge_is_watertight)
{
    shape a = shape_triangle(v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0));
    shape b = shape_triangle(v3(0, 0, 0), v3(1, 1, 0), v3(0, 1, 0));
    rng g = rng_seed(0x5eed, 11);
    int leaks = 0;
    for (int i = 0; i < 20000; i++) {
        float s = 0.01f + 0.98f * rng_float(&g);
        vec3 target = v3(s, s, 0);
        vec3 o = v3_madd(target, rng_unit_dir(&g), 1.0f + 10.0f * rng_float(&g));
        if (fabsf(o.z) < 1e-3f)
            continue;
        ray r = ray_make(o, v3_sub(target, o), INFINITY);
        shape_hit h;
        if (!shape_intersect(&a, &r, &h) && !shape_intersect(&b, &r, &h))
            leaks++;
    }
    cr_assert_eq(leaks, 0, "%d rays passed between two triangles sharing an edge", leaks);
}

/* ---- occlusion twin ------------------------------------------------------ */

/* Random rays from [-3, 3]^3 (many start inside the solids), non-unit
 * directions (half of them aimed near the shape), and tmax either infinite
 * or random: occluded must answer
 * exactly as intersect, every hit must lie in (tmin, tmax) and on the
 * shape's bounds (within 1e-4 relative). */
Test(shapes, occluded_agrees_with_intersect_on_random_rays)
{
    shape shapes[] = {
        shape_sphere(v3(0.2f, -0.1f, 0.3f), 1.5f),
        shape_plane(v3(0, 0.3f, 0), v3(0.2f, 1, -0.1f)),
        shape_quad(v3(-1, -1, 0.5f), v3(2, 0.3f, 0), v3(0.2f, 2, 0.4f)),
        shape_box(v3(-1, -1.5f, -0.5f), v3(1.2f, 1, 2)),
        shape_cylinder(v3(0.1f, -1, 0), 1.2f, 2.5f, true),
        shape_cylinder(v3(0.1f, -1, 0), 1.2f, 2.5f, false),
        shape_triangle(v3(-2, -1, 0), v3(2, -1, 0.5f), v3(0, 2, -0.5f)),
    };
    for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++) {
        const shape *s = &shapes[k];
        aabb b = shape_bounds(s);
        rng g = rng_seed(1234, k);
        int hits = 0;
        for (int i = 0; i < 10000; i++) {
            vec3 o = v3(6 * rng_float(&g) - 3, 6 * rng_float(&g) - 3, 6 * rng_float(&g) - 3);
            vec3 d = v3_scale(rng_unit_dir(&g), 0.5f + 1.5f * rng_float(&g));
            if (i % 2 && !aabb_is_empty(b)) /* aimed at the shape's bounds, grown by 0.5 */
                d = v3_sub(rand_in_box(&g, (aabb){v3_sub(b.lo, v3s(0.5f)), v3_add(b.hi, v3s(0.5f))}), o);
            float tmax = i % 3 == 0 ? INFINITY : 6.0f * rng_float(&g);
            ray r = ray_make(o, d, tmax);
            shape_hit h;
            bool hit = shape_intersect(s, &r, &h);
            cr_assert_eq(shape_occluded(s, &r), hit, "shape %zu ray %d: occluded %d, intersect %d",
                         k, i, !hit, hit);
            if (!hit)
                continue;
            hits++;
            cr_assert(h.t > r.tmin && h.t < r.tmax, "shape %zu ray %d: t %g outside (0, %g)", k, i,
                      (double)h.t, (double)tmax);
            if (!aabb_is_empty(b)) {
                vec3 p = ray_at(&r, h.t);
                float e = 1e-4f * (1.0f + v3_max_abs(p));
                cr_assert(p.x >= b.lo.x - e && p.y >= b.lo.y - e && p.z >= b.lo.z - e &&
                              p.x <= b.hi.x + e && p.y <= b.hi.y + e && p.z <= b.hi.z + e,
                          "shape %zu ray %d: hit (%g %g %g) outside the bounds", k, i,
                          (double)p.x, (double)p.y, (double)p.z);
            }
        }
        /* Not vacuous: a good share of the rays must hit. */
        cr_assert_gt(hits, 1000, "shape %zu: only %d hits", k, hits);
    }
}

/* ---- through object transforms -------------------------------------------- */

/* The cube [-1, 1]^3 turned 45 degrees about +y (right-handed: +z goes to
 * (s, 0, c)). Its +z face now lies in (x + z)/sqrt2 = 1 with normal
 * (1, 0, 1)/sqrt2, its -x face in (z - x)/sqrt2 = 1 with normal
 * (-1, 0, 1)/sqrt2. A ray down -z at x = +-0.3 meets them at
 * z = sqrt2 - 0.3. */
Test(shapes, rotated_box_through_scene_transform)
{
    xform x = xform_rotate(v3(0, 1, 0), 45.0f);
    scene *s = one_object(shape_box(v3(-1, -1, -1), v3(1, 1, 1)), &x);
    const double h = M_SQRT1_2, z = M_SQRT2 - 0.3;
    /* world bounds: the rotated corners reach sqrt2 in x and z */
    ASSERT_NEAR(s->bounds[0].hi.x, M_SQRT2, XTOL);
    ASSERT_NEAR(s->bounds[0].hi.y, 1.0, XTOL);
    ASSERT_NEAR(s->bounds[0].lo.z, -M_SQRT2, XTOL);
    const float xs[2] = {0.3f, -0.3f};
    const double nx[2] = {h, -h};
    for (int i = 0; i < 2; i++) {
        ray r = ray_make(v3(xs[i], 0.25f, 10), v3(0, 0, -1), INFINITY);
        scene_hit hit;
        cr_assert(scene_intersect(s, &r, &hit));
        cr_assert(scene_occluded_opaque(s, &r));
        ASSERT_NEAR(hit.h.t, 10.0 - z, XTOL);
        surface sf;
        scene_surface(s, &r, &hit, &sf);
        ASSERT_V3_NEAR(sf.p, xs[i], 0.25, z, XTOL);
        ASSERT_V3_NEAR(sf.n, nx[i], 0.0, h, XTOL);
        ASSERT_V3_NEAR(sf.ng, nx[i], 0.0, h, XTOL);
    }
    /* From the side along -x at z = 0: meets the vertical edge where the +x
     * and +z faces join, at x = sqrt2, so either face's normal, (1, 0, -+1)/sqrt2;
     * misses above the top at y = 1. */
    ray r = ray_make(v3(10, 0, 0), v3(-2, 0, 0), INFINITY); /* non-unit: t halves */
    scene_hit hit;
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, (10.0 - M_SQRT2) / 2, XTOL);
    surface sf;
    scene_surface(s, &r, &hit, &sf);
    ASSERT_V3_NEAR(sf.p, M_SQRT2, 0, 0, XTOL);
    cr_assert(fabs(sf.n.x - h) <= XTOL && fabs(sf.n.y) <= XTOL && fabs(fabs(sf.n.z) - h) <= XTOL,
              "n = (%g %g %g)", (double)sf.n.x, (double)sf.n.y, (double)sf.n.z);
    r = ray_make(v3(10, 1.01f, 0), v3(-1, 0, 0), INFINITY);
    cr_assert_not(scene_intersect(s, &r, &hit));
    cr_assert_not(scene_occluded_opaque(s, &r));
    scene_free(s);
}

/* The unit sphere scaled by (2, 1, 0.5) and moved by (1, 2, 3): the
 * ellipsoid (x-1)^2/4 + (y-2)^2 + (z-3)^2/0.25 = 1. A ray down -z at
 * x - 1 = 1, y = 2 meets it at z - 3 = 0.5 sqrt(0.75); the normal there is
 * the gradient (x/4, y, 4z) ~ (0.25, 0, 1.7320508), of length 1.75. (The
 * forward matrix applied to the object normal would give (0.917, 0, 0.397)
 * instead.) */
Test(shapes, ellipsoid_normals_by_inverse_transpose)
{
    xform sc = xform_scale(v3(2, 1, 0.5f)), tr = xform_translate(v3(1, 2, 3));
    xform x = xform_then(&sc, &tr);
    scene *s = one_object(shape_sphere(v3(0, 0, 0), 1), &x);
    ASSERT_V3_NEAR(s->bounds[0].lo, -1, 1, 2.5, XTOL);
    ASSERT_V3_NEAR(s->bounds[0].hi, 3, 3, 3.5, XTOL);

    const double zc = 0.5 * sqrt(0.75);
    ray r = ray_make(v3(2, 2, 13), v3(0, 0, -1), INFINITY);
    scene_hit hit;
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, 10.0 - zc, XTOL);
    surface sf;
    scene_surface(s, &r, &hit, &sf);
    ASSERT_V3_NEAR(sf.p, 2, 2, 3 + zc, XTOL);
    ASSERT_V3_NEAR(sf.n, 0.25 / 1.75, 0, sqrt(3.0) / 1.75, XTOL);
    ASSERT_V3_NEAR(sf.ng, 0.25 / 1.75, 0, sqrt(3.0) / 1.75, XTOL);
    /* (u, v) are the object's where the material reads them (an untextured
     * one leaves them 0): the object point is (0.5, 0, 0.866). */
    texture chk = texture_checker(v3s(1.0f), v3s(0.0f), 1.0f, 1.0f);
    s->materials[0].texture = scene_add_texture(s, &chk);
    cr_assert(material_uses_uv(&s->materials[0]));
    scene_surface(s, &r, &hit, &sf);
    ASSERT_NEAR(sf.u, 0.5 + atan2(0.5, sqrt(0.75)) / (2 * M_PI), XTOL);
    ASSERT_NEAR(sf.v, 0.5, XTOL);

    /* Along the axes: the semi-axes 2, 1 and 0.5. */
    r = ray_make(v3(11, 2, 3), v3(-1, 0, 0), INFINITY);
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, 8.0, XTOL);
    scene_surface(s, &r, &hit, &sf);
    ASSERT_V3_NEAR(sf.n, 1, 0, 0, XTOL);
    r = ray_make(v3(1, 12, 3), v3(0, -1, 0), INFINITY);
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, 9.0, XTOL);
    r = ray_make(v3(1, 2, 3), v3(0, 0, -4), INFINITY); /* from the centre, |d| = 4 */
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, 0.125, XTOL);
    scene_surface(s, &r, &hit, &sf);
    ASSERT_V3_NEAR(sf.p, 1, 2, 2.5, XTOL);
    ASSERT_V3_NEAR(sf.n, 0, 0, -1, XTOL);
    /* Outside the ellipsoid but inside the unscaled sphere's reach. */
    r = ray_make(v3(1, 2.6f, 13), v3(0, 0, -1), INFINITY);
    cr_assert(scene_intersect(s, &r, &hit));
    r = ray_make(v3(1, 3.01f, 13), v3(0, 0, -1), INFINITY);
    cr_assert_not(scene_intersect(s, &r, &hit));
    cr_assert_not(scene_occluded_opaque(s, &r));
    scene_free(s);
}

/* A mirroring transform (negative determinant) keeps normals outward: the
 * sphere scaled by (-2, 1, 1) is met from +x at x = 2 with normal +x, and
 * the cube [0, 1]^3 mirrored in x occupies [-1, 0] with its old +x face
 * now facing -x. */
Test(shapes, mirrored_shapes_keep_outward_normals)
{
    xform m = xform_scale(v3(-2, 1, 1));
    scene *s = one_object(shape_sphere(v3(0, 0, 0), 1), &m);
    ray r = ray_make(v3(5, 0, 0), v3(-1, 0, 0), INFINITY);
    scene_hit hit;
    surface sf;
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, 3.0, XTOL);
    scene_surface(s, &r, &hit, &sf);
    ASSERT_V3_NEAR(sf.n, 1, 0, 0, XTOL);
    scene_free(s);

    xform mx = xform_scale(v3(-1, 1, 1));
    s = one_object(shape_box(v3(0, 0, 0), v3(1, 1, 1)), &mx);
    r = ray_make(v3(-5, 0.5f, 0.5f), v3(1, 0, 0), INFINITY);
    cr_assert(scene_intersect(s, &r, &hit));
    ASSERT_NEAR(hit.h.t, 4.0, XTOL);
    cr_assert_eq(hit.h.part, 1); /* the object's +x face */
    scene_surface(s, &r, &hit, &sf);
    ASSERT_V3_NEAR(sf.p, -1, 0.5, 0.5, XTOL);
    ASSERT_V3_NEAR(sf.n, -1, 0, 0, XTOL);
    scene_free(s);
}

/* ---- no self-intersection from a convex surface (expect_no_rehit) ------- */

Test(shapes, convex_sphere_never_rehits_itself)
{
    expect_no_rehit("sphere", shape_sphere(v3(3, -2, 5), 2.5f), NULL, 101);
    expect_no_rehit("far sphere", shape_sphere(v3(100, 40, -300), 20), NULL, 102);
}

Test(shapes, convex_box_never_rehits_itself)
{
    expect_no_rehit("box", shape_box(v3(-1, -2, -0.5f), v3(3, 1, 4)), NULL, 201);
}

Test(shapes, convex_cylinder_never_rehits_itself)
{
    expect_no_rehit("cylinder", shape_cylinder(v3(1, -1, 2), 1.5f, 3, true), NULL, 301);
}

Test(shapes, convex_transformed_shapes_never_rehit_themselves)
{
    xform rot = xform_rotate(v3(0, 1, 0), 45.0f), mv = xform_translate(v3(2, 1, -3));
    xform x = xform_then(&rot, &mv);
    expect_no_rehit("rotated box", shape_box(v3(-1, -1, -1), v3(1, 1, 1)), &x, 401);

    xform sc = xform_scale(v3(2, 1, 0.5f)), r2 = xform_rotate(v3(1, 1, 0), 30.0f);
    xform e = xform_then(&sc, &r2);
    e = xform_then(&e, &mv);
    expect_no_rehit("ellipsoid", shape_sphere(v3(0, 0, 0), 1), &e, 402);

    xform cs = xform_scale(v3(1, 3, 1)), r3 = xform_rotate(v3(0, 0, 1), 60.0f);
    xform cx = xform_then(&cs, &r3);
    expect_no_rehit("stretched cylinder", shape_cylinder(v3(0, 0, 0), 1, 1, true), &cx, 403);
}

/* The normal is worked out in double: a triangle whose float normal
 * overflows is too large, one with no area (or too small for floats) is
 * degenerate, and neither is confused with the other. */
Test(shapes, triangle_check_tells_too_large_from_degenerate)
{
    vec3 o = v3(0, 0, 0);
    cr_expect_eq(triangle_check(o, v3(1, 0, 0), v3(0, 1, 0)), TRIANGLE_OK);
    cr_expect_eq(triangle_check(o, v3(1e38f, 0, 0), v3(0, 1e38f, 0)), TRIANGLE_TOO_LARGE);
    cr_expect_eq(triangle_check(o, v3(1e10f, 0, 0), v3(0, 1e10f, 0)), TRIANGLE_TOO_LARGE);
    cr_expect_eq(triangle_check(o, v3(1e9f, 0, 0), v3(0, 1e9f, 0)), TRIANGLE_OK);
    cr_expect_eq(triangle_check(o, v3(1e38f, 0, 0), v3(-1e38f, 0, 0)), TRIANGLE_DEGENERATE);
    cr_expect_eq(triangle_check(o, v3(1, 1, 1), v3(2, 2, 2)), TRIANGLE_DEGENERATE);
    cr_expect_eq(triangle_check(o, v3(1e-30f, 0, 0), v3(0, 1e-30f, 0)), TRIANGLE_DEGENERATE);
    cr_expect_eq(triangle_check(o, v3(INFINITY, 0, 0), v3(0, 1, 0)), TRIANGLE_DEGENERATE);
}

/* A torus turned, stretched and moved: its box (shape_bounds_mapped) holds
 * every point of the mapped surface, and each face comes within 1e-3 of
 * the torus's size of the farthest of 360 x 360 points sampled on it. */
Test(shapes, turned_torus_bounds_hold_it_tightly)
{
    shape t = shape_torus(v3(0.1f, -0.2f, 0.3f), 0.32f, 0.1f);
    rng g = rng_seed(7, 1);
    for (int k = 0; k < 20; k++) {
        xform rx = xform_rotate(v3(1, 0, 0), 360.0f * rng_float(&g));
        xform ry = xform_rotate(v3(0, 1, 0), 360.0f * rng_float(&g));
        xform sc = xform_scale(v3(1.0f + rng_float(&g), 1.0f, 0.5f + rng_float(&g)));
        xform tr = xform_translate(v3(-49.5f + 99.0f * rng_float(&g), 0.42f, 20.0f));
        xform a = xform_then(&sc, &rx), b = xform_then(&a, &ry), x = xform_then(&b, &tr);
        aabb box = shape_bounds_mapped(&t, &x.fwd);
        aabb seen = aabb_empty();
        for (int i = 0; i < 360; i++)
            for (int j = 0; j < 360; j++) {
                double u = i * M_PI / 180.0, v = j * M_PI / 180.0;
                double rho = 0.32 + 0.1 * cos(v);
                vec3 p = v3((float)(0.1 + rho * sin(u)), (float)(-0.2 + 0.1 * sin(v)),
                            (float)(0.3 + rho * cos(u)));
                seen = aabb_grow(seen, mat4_point(&x.fwd, p));
            }
        float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
        float slo[3] = {seen.lo.x, seen.lo.y, seen.lo.z};
        float shi[3] = {seen.hi.x, seen.hi.y, seen.hi.z};
        const float tol = 1e-3f * 2.0f * 0.42f; /* of the torus's size */
        for (int a3 = 0; a3 < 3; a3++) {
            cr_assert(lo[a3] <= slo[a3] && hi[a3] >= shi[a3],
                      "turn %d axis %d: [%g, %g] misses [%g, %g]", k, a3, (double)lo[a3],
                      (double)hi[a3], (double)slo[a3], (double)shi[a3]);
            cr_assert(slo[a3] - lo[a3] < tol && hi[a3] - shi[a3] < tol,
                      "turn %d axis %d: [%g, %g] is loose round [%g, %g]", k, a3, (double)lo[a3],
                      (double)hi[a3], (double)slo[a3], (double)shi[a3]);
        }
    }
}

/* shape_surface_no_uv gives shape_surface's point and normals to the bit
 * and (u, v) of 0, on the sides and caps of cylinders and cones, spheres
 * and tori. */
Test(shapes, surface_without_uv_is_the_same_surface)
{
    shape shapes[] = {
        shape_sphere(v3(0.1f, 0.2f, -0.3f), 1.2f),
        shape_cylinder(v3(0, -1, 0), 0.8f, 2.0f, true),
        shape_cone(v3(0, -1, 0), 1.1f, 0.3f, 2.0f, true),
        shape_torus(v3(0, 0, 0), 1.0f, 0.35f),
    };
    rng g = rng_seed(8, 1);
    for (size_t k = 0; k < sizeof shapes / sizeof *shapes; k++) {
        int hits = 0, caps = 0;
        for (int i = 0; i < 3000; i++) {
            vec3 o = v3_scale(rng_unit_dir(&g), 5.0f);
            vec3 at = v3(rng_float(&g) - 0.5f, 2.2f * rng_float(&g) - 1.1f, rng_float(&g) - 0.5f);
            ray r = ray_make(o, v3_sub(at, o), INFINITY);
            shape_hit h;
            if (!shape_intersect(&shapes[k], &r, &h))
                continue;
            surface a, b;
            shape_surface(&shapes[k], &r, &h, &a);
            shape_surface_no_uv(&shapes[k], &r, &h, &b);
            cr_assert(memcmp(&a.p, &b.p, sizeof a.p) == 0 && memcmp(&a.n, &b.n, sizeof a.n) == 0 &&
                          memcmp(&a.ng, &b.ng, sizeof a.ng) == 0,
                      "shape %zu ray %d", k, i);
            cr_assert(b.u == 0.0f && b.v == 0.0f);
            hits++;
            caps += h.part != 0;
        }
        cr_assert_gt(hits, 500, "shape %zu: %d hits", k, hits);
        if (k == 1 || k == 2)
            cr_assert_gt(caps, 50, "shape %zu: %d cap hits", k, caps);
    }
}

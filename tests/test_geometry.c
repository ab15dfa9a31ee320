/* The shapes of the extension list (cone, disk, torus, polyhedron), in the
 * manner of test_shapes.c: known hits with their point, outward normal and
 * (u, v), misses, tangents, rays from inside, tmax culling, the occlusion
 * twin against intersect on random rays, placement through transforms
 * (shear included) and no re-hits from convex surfaces. Also the roots
 * finder the torus uses, and the polyhedron's checks of its input. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/roots.h"
#include "geom/polyhedron.h"
#include "shape_check.h"

/* ---- roots (core/roots.h) ------------------------------------------------- */

/* The next of a fixed sequence of numbers in [-2, 2). */
static double next_coefficient(uint32_t *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return (double)(*seed >> 8) / (double)(1u << 24) * 4.0 - 2.0;
}

/* (x - 1)(x - 2)(x - 3)(x - 4) = x^4 - 10x^3 + 35x^2 - 50x + 24. */
Test(roots, quartic_with_four_known_roots)
{
    const double c[5] = {24, -50, 35, -10, 1};
    double r[4];
    cr_assert_eq(roots_quartic(c, 0, 10, r, 4), 4);
    for (int i = 0; i < 4; i++)
        ASSERT_NEAR(r[i], i + 1, 1e-12);
    cr_assert_eq(roots_quartic(c, 0, 10, r, 1), 1, "max 1: only the first");
    ASSERT_NEAR(r[0], 1, 1e-12);
    cr_assert_eq(roots_quartic(c, 2.5, 10, r, 4), 2, "only those in the interval");
    ASSERT_NEAR(r[0], 3, 1e-12);
    cr_assert_eq(roots_quartic(c, 1, 2, r, 4), 0, "the interval is open");
}

/* Roots 1 and 1 + 1e-7 (and 5, 6): the critical point between the close
 * pair splits them, so both are found. A double root (touching zero) is not
 * a crossing and is not reported. */
Test(roots, close_and_double_roots)
{
    double e = 1e-7, a = 1, b = 1 + e;
    /* (x - a)(x - b) = x^2 - (a+b) x + ab; times (x - 5)(x - 6) = x^2 - 11x + 30 */
    double p[3] = {a * b, -(a + b), 1}, q[3] = {30, -11, 1};
    double c[5] = {0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            c[i + j] += p[i] * q[j];
    double r[4];
    cr_assert_eq(roots_quartic(c, 0, 10, r, 4), 4);
    /* The coefficients' rounding moves such a close pair by ~1e-9. */
    ASSERT_NEAR(r[0], a, 2e-8);
    ASSERT_NEAR(r[1], b, 2e-8);
    cr_assert_lt(r[0], r[1]);
    const double dbl[5] = {9, -6, 10, -6, 1}; /* (x - 3)^2 (x^2 + 1) */
    cr_assert_eq(roots_quartic(dbl, 0, 10, r, 4), 0);
    const double sq[3] = {-2, 0, 1};
    cr_assert_eq(roots_quadratic(sq, -5, 5, r), 2);
    ASSERT_NEAR(r[0], -M_SQRT2, 1e-15);
    ASSERT_NEAR(r[1], M_SQRT2, 1e-15);
    const double cub[4] = {-6, 11, -6, 1}; /* (x-1)(x-2)(x-3) */
    cr_assert_eq(roots_cubic(cub, 0, 4, r), 3);
    ASSERT_NEAR(r[2], 3, 1e-12);
}

/* The first root alone (max 1) against the first of all of them (max 4):
 * both none, or both a root within 1e-9; returns how many first roots. */
static int expect_first_root(const double c[5], double lo, double hi, const char *what)
{
    double one[4], all[4];
    int n1 = roots_quartic(c, lo, hi, one, 1), n4 = roots_quartic(c, lo, hi, all, 4);
    cr_assert_eq(n1, n4 > 0 ? 1 : 0, "%s: %d first roots, %d in all", what, n1, n4);
    if (n1)
        ASSERT_NEAR(one[0], all[0], 1e-9);
    return n1;
}

/* The first root alone (max 1), which for a quartic bending towards zero
 * is found by Newton's method from lo without the turning point ahead,
 * against the first of all the roots (max 4), which always goes by the
 * turning points: over many quartics, some with two real roots, some with
 * none, and intervals that start before, between and after the roots. */
Test(roots, first_root_alone_agrees_with_all)
{
    uint32_t seed = 12345;
    int found = 0;
    for (int k = 0; k < 20000; k++) {
        double v[6];
        for (int i = 0; i < 6; i++)
            v[i] = next_coefficient(&seed);
        /* (x - v0)(x - v1) times x^2 - 2 v2 x + v2^2 + v3 (v3 > 0: no real roots) or the
         * real pair v2 +- |v3| */
        double m = v[3] > 0 ? v[2] * v[2] + v[3] : v[2] * v[2] - v[3] * v[3];
        double p[3] = {v[0] * v[1], -(v[0] + v[1]), 1}, q[3] = {m, -2.0 * v[2], 1};
        double c[5] = {0};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                c[i + j] += p[i] * q[j];
        double lo = v[4], hi = lo + 1.0 + fabs(v[5]) * 2.0;
        char what[64];
        snprintf(what, sizeof what, "quartic %d", k);
        found += expect_first_root(c, lo, hi, what);
    }
    cr_assert_gt(found, 5000);
}

/* Where p'' has a double root (x^4 + x - 1: p'' = 12 x^2, concave on
 * neither side) or lo lies within rounding of an inflection, the sign of
 * p'' at lo and the inflections found need not tell which way p bends on
 * the piece searched from lo or from the first inflection: the first
 * root alone must still be the first of all. */
Test(roots, first_root_alone_where_the_inflections_mislead)
{
    const double dbl[5] = {-1, 1, 0, 0, 1};
    expect_first_root(dbl, -0.5, 0.9, "double inflection at 0");
    const double b1[5] = {-1.929226952366065, -1.9970649520931119, -3.7303703556296028,
                          -1.100000111139753, 1.2095539236881621};
    expect_first_root(b1, -0.52477747822553578, 4.7554408888322159, "inflection dropped");
    const double b2[5] = {-0.93073968491671621, 1.0861465041704577, 1.9931161348054898,
                          1.4022923506070162, 0.36997788981312851};
    expect_first_root(b2, -0.94733918571793385, 0.74563916402618491, "inflection before lo");
    /* random quartics with lo on a computed inflection and a float either side */
    uint32_t seed = 4242;
    for (int k = 0; k < 20000; k++) {
        double c[5];
        for (int i = 0; i < 5; i++)
            c[i] = next_coefficient(&seed);
        if (k % 4 == 0)
            c[2] = c[3] = 0.0; /* p'' = 12 c4 x^2: a double inflection at 0 */
        double ddc[3] = {2.0 * c[2], 6.0 * c[3], 12.0 * c[4]}, bend[2];
        int nb = roots_quadratic(ddc, -4.0, 4.0, bend);
        double at = nb > 0 ? bend[k % nb] : 0.0;
        double lo = k % 3 == 0 ? at : k % 3 == 1 ? nextafter(at, -INFINITY) : nextafter(at, INFINITY);
        char what[64];
        snprintf(what, sizeof what, "quartic %d", k);
        expect_first_root(c, lo, lo + 0.5 + (double)(k % 7), what);
    }
}

/* roots_quartic_above turns a quartic away only where the search finds no
 * root: over quartics with roots near, at and just past the ends of the
 * interval, pairs of roots a hair apart and tangent minima a hair above or
 * below zero. And it does turn the clear cases away. */
Test(roots, above_only_where_the_search_finds_nothing)
{
    uint32_t seed = 777;
    int above = 0;
    for (int k = 0; k < 200000; k++) {
        double v[5];
        for (int i = 0; i < 5; i++) {
            seed = seed * 1664525u + 1013904223u;
            v[i] = (double)(seed >> 8) / (double)(1u << 24);
        }
        /* ((x - p)^2 + e)((x - q)^2 + g): minima near p and q, at e and g from zero */
        double p = 2.0 * v[0] - 0.5, q = 2.0 * v[1] - 0.5;
        double e = ldexp(v[2] - 0.5, -(int)(v[4] * 60)), g = (v[3] - 0.3) * 0.5;
        double f[3] = {p * p + e, -2.0 * p, 1}, h[3] = {q * q + g, -2.0 * q, 1};
        double c[5] = {0};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                c[i + j] += f[i] * h[j];
        double hi = 0.5 + v[4], r[4];
        if (!roots_quartic_above(c, hi))
            continue;
        above++;
        cr_assert_eq(roots_quartic(c, 0.0, hi, r, 4), 0, "quartic %d", k);
        cr_assert_eq(roots_quartic(c, 0.0, hi, r, 1), 0, "quartic %d", k);
    }
    cr_assert_gt(above, 20000);
    const double clear[5] = {1, 0, 0, 0, 1}, through[5] = {-0.1, 0, 1, 0, 0};
    cr_assert(roots_quartic_above(clear, 1.0));
    cr_assert_not(roots_quartic_above(through, 1.0));
}

/* ---- cone ----------------------------------------------------------------- */

/* Pointed: base at the origin, radius 1, height 2, so R(y) = 1 - y/2 and
 * the side's normal is (cos, 0.5, sin) / sqrt(1.25). */
Test(geometry, cone_hit_known_t)
{
    shape s = shape_cone(v3(0, 0, 0), 1, 0, 2, true);
    double k = 1 / sqrt(1.25);
    expect_hit(&s, ray_make(v3(0, 0.5f, 5), v3(0, 0, -1), INFINITY), 4.25, v3(0, 0.5f, 0.75f),
               v3(0, 0.5 * k, k), 0.5, 0.25);
    expect_hit(&s, ray_make(v3(5, 1, 0), v3(-2, 0, 0), INFINITY), 2.25, v3(0.5f, 1, 0),
               v3(k, 0.5 * k, 0), 0.75, 0.5);
    /* The bottom cap from below: (u, v) as on the cylinder's. */
    expect_hit(&s, ray_make(v3(0.3f, -5, 0.2f), v3(0, 1, 0), INFINITY), 5, v3(0.3f, 0, 0.2f),
               v3(0, -1, 0), 0.65, 0.6);
    cr_assert(shape_is_convex(&s));
    cr_assert(shape_is_solid(&s));
    /* Truncated, moved: the top cap of radius 1 at y = 3. */
    shape t = shape_cone(v3(1, 1, 1), 2, 1, 2, true);
    expect_hit(&t, ray_make(v3(1.5f, 10, 1), v3(0, -1, 0), INFINITY), 7, v3(1.5f, 3, 1),
               v3(0, 1, 0), 0.75, 0.5);
    aabb b = shape_bounds(&t);
    ASSERT_V3_NEAR(b.lo, -1, 1, -1, TOL);
    ASSERT_V3_NEAR(b.hi, 3, 3, 3, TOL);
}

Test(geometry, cone_miss_inside_open_and_tmax)
{
    shape s = shape_cone(v3(0, 0, 0), 1, 0, 2, true);
    expect_miss(&s, ray_make(v3(0, 2.5f, 5), v3(0, 0, -1), INFINITY));  /* above the apex */
    expect_miss(&s, ray_make(v3(1.5f, 0.1f, 5), v3(0, 0, -1), INFINITY)); /* beside */
    expect_miss(&s, ray_make(v3(0, 0.5f, 5), v3(0, 0, 1), INFINITY));    /* away */
    expect_miss(&s, ray_make(v3(0, 0.5f, 5), v3(0, 0, -1), 4.25f));      /* tmax is open */
    /* The other nappe of the double cone (y > 2) is no part of it. */
    expect_miss(&s, ray_make(v3(0.5f, 3, 5), v3(0, 0, -1), INFINITY));
    double k = 1 / sqrt(1.25);
    /* From inside: the far side, normal outward. */
    expect_hit(&s, ray_make(v3(0, 0.5f, 0), v3(1, 0, 0), INFINITY), 0.75, v3(0.75f, 0.5f, 0),
               v3(k, 0.5 * k, 0), -1, 0);
    expect_hit(&s, ray_make(v3(0.1f, 0.5f, 0), v3(0, -1, 0), INFINITY), 0.5, v3(0.1f, 0, 0),
               v3(0, -1, 0), -1, 0);
    /* Open: up through the missing bottom to the inside of the side, where
     * R = 0.2 (y = 1.6); the normal stays outward. */
    shape o = shape_cone(v3(0, 0, 0), 1, 0, 2, false);
    cr_assert_not(shape_is_solid(&o));
    expect_hit(&o, ray_make(v3(0.2f, -5, 0), v3(0, 1, 0), INFINITY), 6.6, v3(0.2f, 1.6f, 0),
               v3(k, 0.5 * k, 0), -1, 0);
}

/* A ray nearly along a line of the side (the quadratic's leading
 * coefficient ~0): the side is still found where it is. */
Test(geometry, cone_ray_along_the_side)
{
    shape s = shape_cone(v3(0, 0, 0), 1, 0, 2, false);
    /* The side line from (1, 0, 0) to the apex (0, 2, 0), offset outward by
     * 0.01 along x and run from below. */
    ray r = ray_make(v3(1.01f + 0.5f, -1, 0), v3(-0.5f, 1, 0), INFINITY);
    shape_hit h;
    cr_assert_not(shape_intersect(&s, &r, &h), "parallel outside: no hit (t %g)", (double)h.t);
    r = ray_make(v3(0.99f + 0.5f, -1, 0), v3(-0.5f, 1.0001f, 0), INFINITY);
    /* Inside the line: enters through the open bottom... and meets the
     * side once, near the top. */
    surface sf;
    if (hit_surface(&s, r, &h, &sf)) {
        cr_assert(sf.p.y >= 0 && sf.p.y <= 2);
        ASSERT_NEAR(hypot(sf.p.x, sf.p.z), 1 - sf.p.y / 2, 1e-4);
    }
}

/* ---- disk ----------------------------------------------------------------- */

/* Centre (1, 2, 3), facing +z: tu = +x, tv = +y. */
Test(geometry, disk_and_annulus)
{
    shape s = shape_disk(v3(1, 2, 3), v3(0, 0, 2), 2, 0.5f);
    expect_hit(&s, ray_make(v3(1, 3, 10), v3(0, 0, -1), INFINITY), 7, v3(1, 3, 3), v3(0, 0, 1),
               0.5, 0.75);
    expect_hit(&s, ray_make(v3(2.5f, 2, -10), v3(0, 0, 2), INFINITY), 6.5, v3(2.5f, 2, 3),
               v3(0, 0, 1), 0.875, 0.5);
    expect_miss(&s, ray_make(v3(1.2f, 2, 10), v3(0, 0, -1), INFINITY)); /* the hole */
    expect_miss(&s, ray_make(v3(3.5f, 2, 10), v3(0, 0, -1), INFINITY)); /* outside */
    expect_miss(&s, ray_make(v3(1, 3, 3), v3(1, 0, 0), INFINITY));      /* in its plane */
    expect_miss(&s, ray_make(v3(1, 3, 10), v3(0, 0, -1), 7));           /* tmax */
    shape full = shape_disk(v3(0, 0, 0), v3(0, 1, 0), 1, 0);
    expect_hit(&full, ray_make(v3(0, 5, 0), v3(0, -1, 0), INFINITY), 5, v3(0, 0, 0), v3(0, 1, 0),
               0.5, 0.5);
    /* A tilted disk's box reaches radius * sqrt(1 - n_i^2) along each axis. */
    shape tilt = shape_disk(v3(0, 0, 0), v3(1, 1, 0), 2, 0);
    aabb b = shape_bounds(&tilt);
    ASSERT_V3_NEAR(b.hi, M_SQRT2, M_SQRT2, 2, TOL);
    cr_assert(shape_is_convex(&full));
    cr_assert_not(shape_is_solid(&full));
}

/* ---- torus ---------------------------------------------------------------- */

/* Centre at the origin, R = 2, r = 0.5. */
Test(geometry, torus_hit_known_t)
{
    shape s = shape_torus(v3(0, 0, 0), 2, 0.5f);
    expect_hit(&s, ray_make(v3(0, 0, 10), v3(0, 0, -1), INFINITY), 7.5, v3(0, 0, 2.5f),
               v3(0, 0, 1), 0.5, 0.5);
    /* The top of the tube: u a quarter turn on, v a quarter turn round. */
    expect_hit(&s, ray_make(v3(2, 10, 0), v3(0, -1, 0), INFINITY), 9.5, v3(2, 0.5f, 0),
               v3(0, 1, 0), 0.75, 0.75);
    /* The inner wall facing the hole, seen across the hole. */
    expect_hit(&s, ray_make(v3(0, 0, 0), v3(0, 0, -0.5f), INFINITY), 3, v3(0, 0, -1.5f),
               v3(0, 0, 1), -1, 0);
    /* Moved and turned through the tube at an angle: on the surface. */
    shape m = shape_torus(v3(1, 2, 3), 2, 0.5f);
    expect_hit(&m, ray_make(v3(3, 12, 3), v3(0, -1, 0), INFINITY), 9.5, v3(3, 2.5f, 3),
               v3(0, 1, 0), -1, 0);
    aabb b = shape_bounds(&m);
    ASSERT_V3_NEAR(b.lo, -1.5, 1.5, 0.5, TOL);
    ASSERT_V3_NEAR(b.hi, 3.5, 2.5, 5.5, TOL);
    cr_assert_not(shape_is_convex(&s));
    cr_assert(shape_is_solid(&s));
}

/* The surface point of a hit lies on the surface to float precision and
 * the normal is the field's gradient direction, out of the tube: on a
 * ring torus, and on a spindle torus (r > R), whose lens round the centre
 * faces inwards, seen from above and below along the axis. */
Test(geometry, torus_surface_on_the_tube_and_on_the_lens)
{
    struct { float R, r; } tori[] = {{2, 0.5f}, {0.32f, 0.1f}, {0.5f, 0.8f}};
    for (int k = 0; k < 3; k++) {
        shape s = shape_torus(v3(0.3f, -0.2f, 0.1f), tori[k].R, tori[k].r);
        double R = tori[k].R, r = tori[k].r;
        rng g = rng_seed(77, (uint64_t)k);
        int n = 0;
        for (int i = 0; i < 4000; i++) {
            vec3 o = v3_add(s.torus.center, v3_scale(rng_unit_dir(&g), 4.0f));
            vec3 d = v3_sub(v3_add(s.torus.center, v3(rng_float(&g) - 0.5f, rng_float(&g) - 0.5f,
                                                      rng_float(&g) - 0.5f)), o);
            if (i % 2) { /* from the centre: the lens, or the hole */
                o = v3_add(s.torus.center, v3_scale(rng_unit_dir(&g), 0.05f));
                d = rng_unit_dir(&g);
            }
            ray ry = ray_make(o, d, INFINITY);
            shape_hit h;
            if (!shape_intersect(&s, &ry, &h))
                continue;
            surface sf;
            shape_surface(&s, &ry, &h, &sf);
            double q[3] = {sf.p.x - s.torus.center.x, sf.p.y - s.torus.center.y,
                           sf.p.z - s.torus.center.z};
            double rho = hypot(q[0], q[2]), a = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + R * R;
            double near = sqrt(a - 2 * R * rho), far = sqrt(a + 2 * R * rho);
            cr_assert(fabs(near - r) < 2e-6 || fabs(far - r) < 2e-6, "torus %d ray %d", k, i);
            double gr[3] = {4 * (a - r * r) * q[0] - 8 * R * R * q[0], 4 * (a - r * r) * q[1],
                            4 * (a - r * r) * q[2] - 8 * R * R * q[2]};
            double gl = sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
            if (gl < 1e-3)
                continue; /* the lens's tips, where the gradient vanishes */
            ASSERT_V3_NEAR(sf.n, gr[0] / gl, gr[1] / gl, gr[2] / gl, 1e-4);
            n++;
        }
        cr_assert_gt(n, 500, "torus %d: only %d hits", k, n);
    }
}

Test(geometry, torus_miss_inside_and_tmax)
{
    shape s = shape_torus(v3(0, 0, 0), 2, 0.5f);
    expect_miss(&s, ray_make(v3(0, 10, 0), v3(0, -1, 0), INFINITY));   /* down the hole */
    expect_miss(&s, ray_make(v3(0, 0.6f, 10), v3(0, 0, -1), INFINITY)); /* above */
    expect_miss(&s, ray_make(v3(0, 0, 10), v3(0, 0, -1), 7.5f));       /* tmax is open */
    /* From inside the tube: out through the outer wall, or through the
     * inner wall into the hole, each normal pointing out of the tube. */
    expect_hit(&s, ray_make(v3(2, 0, 0), v3(1, 0, 0), INFINITY), 0.5, v3(2.5f, 0, 0),
               v3(1, 0, 0), -1, 0);
    expect_hit(&s, ray_make(v3(2, 0, 0), v3(-1, 0, 0), INFINITY), 0.5, v3(1.5f, 0, 0),
               v3(-1, 0, 0), -1, 0);
    /* Through the whole ring: four crossings in order, in and out. */
    ray r = ray_make(v3(-10, 0, 0), v3(1, 0, 0), INFINITY);
    crossing x[4];
    bool more;
    cr_assert_eq(shape_crossings(&s, &r, x, 4, &more), 4);
    const double ts[4] = {7.5, 8.5, 11.5, 12.5};
    for (int i = 0; i < 4; i++) {
        ASSERT_NEAR(x[i].h.t, ts[i], TOL);
        cr_assert_eq(x[i].enter, i % 2 == 0);
    }
    /* From inside the tube the first crossing leaves. */
    r = ray_make(v3(-2, 0, 0), v3(1, 0, 0), INFINITY);
    cr_assert_eq(shape_crossings(&s, &r, x, 4, &more), 3);
    cr_assert_not(x[0].enter);
}

/* Touching the top circle (y = r, rho = R) is a double root: either answer
 * may come, but a hit must be where the ray touches. Grazing just inside
 * finds both close roots; just outside, none. */
Test(geometry, torus_tangent_and_grazing)
{
    shape s = shape_torus(v3(0, 0, 0), 2, 0.5f);
    shape_hit h;
    ray r = ray_make(v3(-10, 0.5f, 2), v3(1, 0, 0), INFINITY);
    if (shape_intersect(&s, &r, &h))
        ASSERT_NEAR(h.t, 10, 1e-2);
    r = ray_make(v3(-10, 0.4999f, 2), v3(1, 0, 0), INFINITY);
    crossing x[4];
    bool more;
    cr_assert_eq(shape_crossings(&s, &r, x, 4, &more), 2);
    cr_assert(x[0].enter && !x[1].enter);
    ASSERT_NEAR(x[1].h.t - x[0].h.t, 0.4, 1e-2); /* x = +-0.2 */
    expect_miss(&s, ray_make(v3(-10, 0.5001f, 2), v3(1, 0, 0), INFINITY));
}

/* Far away (10^4 x its size) and very close: the hit is on the surface and
 * its normal is the true one. */
Test(geometry, torus_far_and_near)
{
    shape s = shape_torus(v3(3, -1, 2), 1, 0.25f);
    rng g = rng_seed(77, 1);
    for (int i = 0; i < 2000; i++) {
        float dist = i % 2 ? 1.25e4f : 1.3f;
        vec3 o = v3_madd(v3(3, -1, 2), rng_unit_dir(&g), dist);
        vec3 aim = v3(3 + 2.5f * rng_float(&g) - 1.25f, -1.2f + 0.4f * rng_float(&g),
                      2 + 2.5f * rng_float(&g) - 1.25f);
        ray r = ray_make(o, v3_norm(v3_sub(aim, o)), INFINITY);
        shape_hit h;
        surface sf;
        if (!hit_surface(&s, r, &h, &sf))
            continue;
        vec3 q = v3_sub(sf.p, v3(3, -1, 2));
        float rho = hypotf(q.x, q.z);
        ASSERT_NEAR(hypotf(rho - 1, q.y), 0.25, 1e-5);
        vec3 n = v3_norm(v3(q.x - q.x / rho, q.y, q.z - q.z / rho));
        ASSERT_V3_NEAR(sf.n, n.x, n.y, n.z, 1e-4);
    }
}

/* ---- polyhedra ------------------------------------------------------------ */

static polyhedron *preset(poly_preset k, vec3 c, float r)
{
    polyhedron *p = malloc(sizeof *p);
    poly_error why;
    cr_assert(polyhedron_preset(p, k, c, r, &why), "preset %d: problem %d", k, why.what);
    return p;
}

static void free_poly(polyhedron *p)
{
    polyhedron_free(p);
    free(p);
}

/* Each preset: its vertex and face counts, every vertex on the
 * circumsphere, every face planar, outward, with all vertices behind it. */
Test(geometry, platonic_presets)
{
    static const int nv[5] = {4, 8, 6, 20, 12}, nf[5] = {4, 6, 8, 12, 20}, sides[5] = {3, 4, 3, 5, 3};
    vec3 c = v3(1, 2, 3);
    for (int k = 0; k < POLY_PRESET_COUNT; k++) {
        polyhedron *p = preset((poly_preset)k, c, 2);
        cr_expect_eq(p->nverts, nv[k], "%s", poly_preset_names[k]);
        cr_expect_eq(p->nfaces, nf[k], "%s", poly_preset_names[k]);
        cr_expect(p->convex);
        for (int i = 0; i < p->nverts; i++)
            ASSERT_NEAR(v3_len(v3_sub(p->verts[i], c)), 2, 1e-5);
        for (int f = 0; f < p->nfaces; f++) {
            const poly_face *F = &p->faces[f];
            cr_expect_eq(F->count, sides[k]);
            cr_expect_gt(v3_dot(F->n, v3_sub(p->verts[p->idx[F->first]], c)), 0.0f, "outward");
            for (int i = 0; i < p->nverts; i++)
                cr_expect_leq(v3_dot(F->n, p->verts[i]) - F->d, 1e-5f);
        }
        free_poly(p);
    }
}

/* The cube preset of circumradius sqrt 3 is [-1, 1]^3; its faces' (u, v)
 * run over [0, 1]^2. */
Test(geometry, polyhedron_cube_hits)
{
    polyhedron *p = preset(POLY_CUBE, v3(0, 0, 0), sqrtf(3));
    shape s = shape_polyhedron(p);
    shape_hit h;
    surface sf;
    cr_assert(hit_surface(&s, ray_make(v3(0.2f, 0.3f, 5), v3(0, 0, -1), INFINITY), &h, &sf));
    ASSERT_NEAR(h.t, 4, TOL);
    ASSERT_V3_NEAR(sf.p, 0.2, 0.3, 1, TOL);
    ASSERT_V3_NEAR(sf.n, 0, 0, 1, TOL);
    cr_assert(sf.u >= 0 && sf.u <= 1 && sf.v >= 0 && sf.v <= 1);
    ASSERT_NEAR(fabs(sf.u - 0.5) + fabs(sf.v - 0.5), 0.1 + 0.15, TOL);
    expect_hit(&s, ray_make(v3(0, 0, 0), v3(-2, 0, 0), INFINITY), 0.5, v3(-1, 0, 0), v3(-1, 0, 0),
               -1, 0);
    expect_miss(&s, ray_make(v3(1.01f, 0, 5), v3(0, 0, -1), INFINITY));
    expect_miss(&s, ray_make(v3(0, 0, 5), v3(0, 0, -1), 4));
    aabb b = shape_bounds(&s);
    ASSERT_V3_NEAR(b.lo, -1, -1, -1, TOL);
    free_poly(p);
}

/* An L-shaped prism: a non-convex solid with a non-convex face. */
static polyhedron *l_prism(void)
{
    static const float xy[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    vec3 *v = malloc(sizeof *v * 12);
    int32_t *idx = malloc(sizeof *idx * (6 + 6 + 6 * 4));
    int sizes[8], k = 0;
    for (int i = 0; i < 6; i++) {
        v[i] = v3(xy[i][0], xy[i][1], 0);
        v[i + 6] = v3(xy[i][0], xy[i][1], 1);
    }
    for (int i = 0; i < 6; i++)
        idx[k++] = 6 + i; /* top, counter-clockwise from +z */
    for (int i = 0; i < 6; i++)
        idx[k++] = 5 - i; /* bottom, reversed */
    sizes[0] = sizes[1] = 6;
    for (int i = 0; i < 6; i++) {
        int j = (i + 1) % 6;
        idx[k++] = i, idx[k++] = j, idx[k++] = j + 6, idx[k++] = i + 6;
        sizes[2 + i] = 4;
    }
    polyhedron *p = malloc(sizeof *p);
    poly_error why;
    cr_assert(polyhedron_init(p, v, 12, idx, sizes, 8, &why), "problem %d face %d", why.what,
              why.face);
    return p;
}

Test(geometry, polyhedron_non_convex)
{
    polyhedron *p = l_prism();
    cr_assert_not(p->convex);
    cr_assert_eq(p->ntris, 4 + 4 + 12);
    shape s = shape_polyhedron(p);
    /* Into the notch's inner corner wall x = 1, facing +x. */
    expect_hit(&s, ray_make(v3(1.5f, 1.5f, 0.5f), v3(-1, 0, 0), INFINITY), 0.5,
               v3(1, 1.5f, 0.5f), v3(1, 0, 0), -1, 0);
    expect_miss(&s, ray_make(v3(1.5f, 1.5f, 5), v3(0, 0, -1), INFINITY)); /* down the notch */
    expect_hit(&s, ray_make(v3(0.5f, 0.5f, 5), v3(0, 0, -1), INFINITY), 4, v3(0.5f, 0.5f, 1),
               v3(0, 0, 1), -1, 0);
    /* Along x at y = 1.5: in and out of the arm, then nothing. It leaves
     * across the diagonal of the face x = 1, which both its triangles
     * report: the face's crossing counts once. */
    ray r = ray_make(v3(-1, 1.5f, 0.5f), v3(1, 0, 0), INFINITY);
    crossing x[4];
    bool more;
    int nx = shape_crossings(&s, &r, x, 4, &more);
    cr_assert_eq(nx, 2);
    ASSERT_NEAR(x[0].h.t, 1, TOL);
    ASSERT_NEAR(x[1].h.t, 2, TOL);
    cr_assert(x[0].enter && !x[1].enter);
    free_poly(p);
}

/* What polyhedron_init refuses, and where it says the fault is. */
static poly_error bad(const float (*v)[3], int nv, const int32_t *ix, const int *sizes, int nf)
{
    vec3 *verts = malloc(sizeof *verts * (size_t)nv);
    int total = 0;
    for (int f = 0; f < nf; f++)
        total += sizes[f];
    int32_t *idx = malloc(sizeof *idx * (size_t)total);
    for (int i = 0; i < nv; i++)
        verts[i] = v3(v[i][0], v[i][1], v[i][2]);
    memcpy(idx, ix, sizeof *idx * (size_t)total);
    polyhedron p;
    poly_error why;
    cr_assert_not(polyhedron_init(&p, verts, nv, idx, sizes, nf, &why));
    return why;
}

Test(geometry, polyhedron_refuses_bad_solids)
{
    static const float tet[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3f, 0.3f, 0.3f}};
    const int s3[4] = {3, 3, 3, 3};
    /* counter-clockwise from outside */
    const int32_t good[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    poly_error e;
    const int32_t open[9] = {0, 2, 1, 0, 1, 3, 0, 3, 2};
    e = bad(tet, 4, open, s3, 3);
    cr_expect_eq(e.what, POLY_OPEN);
    const int32_t flipped[12] = {0, 1, 2, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    e = bad(tet, 4, flipped, s3, 4);
    cr_expect_eq(e.what, POLY_WINDING);
    const int32_t inside_out[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    e = bad(tet, 4, inside_out, s3, 4);
    cr_expect_eq(e.what, POLY_INSIDE_OUT);
    const int32_t repeat[12] = {0, 2, 2, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    e = bad(tet, 4, repeat, s3, 4);
    cr_expect_eq(e.what, POLY_REPEAT);
    cr_expect_eq(e.face, 0);
    cr_expect_eq(e.corner, 2);
    const int s2[4] = {2, 3, 3, 4};
    const int32_t two[12] = {0, 2, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0};
    e = bad(tet, 4, two, s2, 4);
    cr_expect_eq(e.what, POLY_FEW_VERTICES);
    /* A face with a fourth corner well off its plane. */
    const int s4[4] = {4, 3, 3, 3};
    const int32_t bent[13] = {0, 2, 4, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    static const float bentv[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, -0.2f}};
    e = bad(bentv, 5, bent, s4, 4);
    cr_expect_eq(e.what, POLY_NOT_PLANAR);
    cr_expect_eq(e.face, 0);
    /* The good one passes; a duplicated face makes its edges non-manifold. */
    polyhedron p;
    vec3 *v = malloc(sizeof *v * 4);
    int32_t *ix = malloc(sizeof good);
    for (int i = 0; i < 4; i++)
        v[i] = v3(tet[i][0], tet[i][1], tet[i][2]);
    memcpy(ix, good, sizeof good);
    cr_assert(polyhedron_init(&p, v, 4, ix, s3, 4, &e));
    polyhedron_free(&p);
    const int s5[5] = {3, 3, 3, 3, 3};
    const int32_t dup[15] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 2, 1};
    e = bad(tet, 4, dup, s5, 5);
    cr_expect_eq(e.what, POLY_NOT_MANIFOLD);
}

/* ---- all new shapes: occlusion twin, bounds, transforms, no re-hits ------- */

Test(geometry, occluded_agrees_with_intersect_on_random_rays)
{
    polyhedron *ico = preset(POLY_ICOSAHEDRON, v3(0.2f, 0, -0.1f), 1.6f), *l = l_prism();
    shape shapes[] = {
        shape_cone(v3(0.1f, -1, 0), 1.3f, 0, 2.4f, true),
        shape_cone(v3(0.1f, -1, 0), 1.3f, 0.6f, 2.4f, false),
        shape_disk(v3(0, 0.2f, 0), v3(0.3f, 1, -0.2f), 1.8f, 0.6f),
        shape_torus(v3(0, 0.1f, 0.2f), 1.4f, 0.5f),
        shape_polyhedron(ico),
        shape_polyhedron(l),
    };
    for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++) {
        const shape *s = &shapes[k];
        aabb b = shape_bounds(s);
        rng g = rng_seed(4321, k);
        int hits = 0;
        for (int i = 0; i < 20000; i++) {
            vec3 o = v3(6 * rng_float(&g) - 3, 6 * rng_float(&g) - 3, 6 * rng_float(&g) - 3);
            vec3 d = v3_scale(rng_unit_dir(&g), 0.5f + 1.5f * rng_float(&g));
            if (i % 2)
                d = v3_sub(rand_in_box(&g, (aabb){v3_sub(b.lo, v3s(0.5f)), v3_add(b.hi, v3s(0.5f))}), o);
            float tmax = i % 3 == 0 ? INFINITY : 6.0f * rng_float(&g);
            ray r = ray_make(o, d, tmax);
            shape_hit h;
            bool hit = shape_intersect(s, &r, &h);
            cr_assert_eq(shape_occluded(s, &r), hit, "shape %zu ray %d", k, i);
            if (!hit)
                continue;
            hits++;
            cr_assert(h.t > r.tmin && h.t < r.tmax);
            vec3 p = ray_at(&r, h.t);
            float e = 1e-4f * (1.0f + v3_max_abs(p));
            cr_assert(p.x >= b.lo.x - e && p.y >= b.lo.y - e && p.z >= b.lo.z - e &&
                          p.x <= b.hi.x + e && p.y <= b.hi.y + e && p.z <= b.hi.z + e,
                      "shape %zu ray %d: hit outside the bounds", k, i);
        }
        cr_assert_gt(hits, 2000, "shape %zu: only %d hits", k, hits);
    }
    free_poly(ico);
    free_poly(l);
}

/* torus_occluded answers some rays without the root (a ray inside the tube
 * where it crosses the torus's plane is blocked): against torus_intersect
 * on shadow-like rays, many of them leaving the surface itself and many
 * ending a hair before or after their first hit, where rounding t onto
 * tmin or tmax would decide. */
Test(geometry, torus_occluded_agrees_with_intersect_near_the_ends)
{
    struct torus tor = {v3(0.3f, -0.2f, 0.1f), 0.32f, 0.1f};
    shape s = shape_torus(tor.center, tor.major, tor.minor);
    aabb b = shape_bounds(&s);
    rng g = rng_seed(97, 3);
    int blocked = 0, near_end = 0;
    for (int i = 0; i < 400000; i++) {
        vec3 o = rand_in_box(&g, (aabb){v3_sub(b.lo, v3s(1)), v3_add(b.hi, v3s(1))});
        vec3 d = v3_sub(rand_in_box(&g, b), o);
        ray r = ray_make(o, d, INFINITY);
        shape_hit h;
        if (i % 4 == 1 && shape_intersect(&s, &r, &h)) { /* from the surface, out or in */
            surface sf;
            shape_surface(&s, &r, &h, &sf);
            vec3 nd = v3_scale(rng_unit_dir(&g), 0.5f + rng_float(&g));
            r = ray_make(ray_offset(sf.p, sf.ng, nd), nd, INFINITY);
        }
        if (i % 3 && shape_intersect(&s, &r, &h)) { /* tmax within a few floats of the hit */
            r.tmax = h.t;
            for (int k = (int)(rng_u32(&g) % 5) - 2; k > 0; k--)
                r.tmax = nextafterf(r.tmax, INFINITY);
            for (int k = (int)(rng_u32(&g) % 5) - 2; k < 0; k++)
                r.tmax = nextafterf(r.tmax, 0.0f);
            near_end++;
        }
        bool hit = torus_intersect(&tor, &r, &h);
        cr_assert_eq(torus_occluded(&tor, &r), hit, "ray %d", i);
        blocked += hit;
    }
    cr_assert_gt(blocked, 100000);
    cr_assert_gt(near_end, 50000);
}

/* Through a shear and a turn: the world hit maps back onto the torus and
 * the world normal is the object's gradient through the inverse transpose. */
Test(geometry, sheared_torus_through_scene_transform)
{
    xform sh = xform_shear(0.4f, 0, 0.2f, 0, 0, 0.3f), rot = xform_rotate(v3(1, 0, 1), 35);
    xform x = xform_then(&sh, &rot);
    scene *s = one_object(shape_torus(v3(0, 0, 0), 1.5f, 0.4f), &x);
    rng g = rng_seed(5, 5);
    int hits = 0;
    for (int i = 0; i < 5000; i++) {
        vec3 o = v3_scale(rng_unit_dir(&g), 8);
        ray r = ray_make(o, v3_sub(rand_in_box(&g, s->bounds[0]), o), INFINITY);
        scene_hit h;
        if (!scene_intersect(s, &r, &h))
            continue;
        hits++;
        surface sf;
        scene_surface(s, &r, &h, &sf);
        vec3 q = mat4_point(&x.inv, sf.p);
        float rho = hypotf(q.x, q.z);
        ASSERT_NEAR(hypotf(rho - 1.5f, q.y), 0.4, 1e-4);
        vec3 n = v3_norm(xform_normal(&x, v3(q.x - 1.5f * q.x / rho, q.y, q.z - 1.5f * q.z / rho)));
        ASSERT_V3_NEAR(sf.n, n.x, n.y, n.z, 1e-3);
    }
    cr_assert_gt(hits, 1000);
    scene_free(s);
}

Test(geometry, convex_new_shapes_never_rehit_themselves)
{
    expect_no_rehit("cone", shape_cone(v3(1, -1, 2), 1.5f, 0, 3, true), NULL, 501);
    expect_no_rehit("truncated cone", shape_cone(v3(1, -1, 2), 1.5f, 0.5f, 3, true), NULL, 502);
    polyhedron *d = preset(POLY_DODECAHEDRON, v3(2, 1, -1), 2);
    xform sc = xform_scale(v3(1, 2, 0.7f)), rot = xform_rotate(v3(1, 2, 3), 40);
    xform x = xform_then(&sc, &rot);
    expect_no_rehit("stretched dodecahedron", shape_polyhedron(d), &x, 503);
    free_poly(d);
}

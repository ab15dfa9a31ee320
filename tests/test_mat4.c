/* mat4 and xform (src/core/mat4.h): composition order, inverses, and how
 * points, directions and normals transform. Tolerance 1e-5 throughout
 * (float matrices built from double arithmetic, values of order 1-10;
 * 1e-4 where entries reach 100). */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/mat4.h"
#include "core/rng.h"
#include "near.h"

#define TOL 1e-5

static void assert_identity(const mat4 *m, double tol, const char *what)
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            cr_assert(fabs(m->m[i][j] - (i == j ? 1.0 : 0.0)) <= tol,
                      "%s: element [%d][%d] = %.9g, expected %d", what, i, j, (double)m->m[i][j],
                      i == j);
}

/* Both products of an xform's matrices are the identity. */
static void assert_inverse_pair(const xform *x, double tol, const char *what)
{
    mat4 a = mat4_mul(&x->fwd, &x->inv), b = mat4_mul(&x->inv, &x->fwd);
    assert_identity(&a, tol, what);
    assert_identity(&b, tol, what);
}

Test(mat4, identity_and_multiplication_order)
{
    mat4 id = mat4_identity();
    assert_identity(&id, 0, "identity");
    xform i = xform_identity();
    cr_assert(xform_is_identity(&i));
    xform t = xform_translate(v3(1, 0, 0));
    cr_assert_not(xform_is_identity(&t));

    /* mat4_mul(a, b) applies b first: translate then scale moves (0,0,0) to
     * (2, 0, 0); scale then translate moves it to (1, 0, 0). */
    xform s = xform_scale(v3(2, 2, 2));
    mat4 ts = mat4_mul(&s.fwd, &t.fwd), st = mat4_mul(&t.fwd, &s.fwd);
    ASSERT_V3_NEAR(mat4_point(&ts, v3(0, 0, 0)), 2, 0, 0, 0);
    ASSERT_V3_NEAR(mat4_point(&st, v3(0, 0, 0)), 1, 0, 0, 0);

    /* A general product against a hand value. */
    mat4 a = {{{1, 2, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 3}, {0, 0, 0, 1}}};
    mat4 b = {{{0, -1, 0, 0}, {1, 0, 0, 0}, {0, 0, 2, 0}, {0, 0, 0, 1}}};
    mat4 ab = mat4_mul(&a, &b);
    const float want[4][4] = {{2, -1, 0, 0}, {1, 0, 0, 0}, {0, 0, 2, 3}, {0, 0, 0, 1}};
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            cr_assert_eq(ab.m[r][c], want[r][c], "ab[%d][%d] = %g", r, c, (double)ab.m[r][c]);
    mat4 tr = mat4_transpose(&ab);
    cr_assert_eq(tr.m[0][1], 1.0f);
    cr_assert_eq(tr.m[1][0], -1.0f);
    cr_assert_eq(tr.m[3][2], 3.0f);
}

/* scale (2, 3, 4), then 90 degrees about +z, then translate (1, 2, 3):
 * (1, 1, 1) -> (2, 3, 4) -> (-3, 2, 4) -> (-2, 4, 7). */
Test(mat4, compose_scale_rotate_translate)
{
    xform s = xform_scale(v3(2, 3, 4)), r = xform_rotate(v3(0, 0, 1), 90.0f),
          t = xform_translate(v3(1, 2, 3));
    xform sr = xform_then(&s, &r);
    xform x = xform_then(&sr, &t);
    ASSERT_V3_NEAR(mat4_point(&x.fwd, v3(1, 1, 1)), -2, 4, 7, TOL);
    ASSERT_V3_NEAR(mat4_point(&x.inv, v3(-2, 4, 7)), 1, 1, 1, TOL);
    assert_inverse_pair(&x, TOL, "scale-rotate-translate");
    /* The other order: translate first, then rotate, then scale:
     * (1, 1, 1) -> (2, 3, 4) -> (-3, 2, 4) -> (-6, 6, 16). */
    xform tr = xform_then(&t, &r);
    xform y = xform_then(&tr, &s);
    ASSERT_V3_NEAR(mat4_point(&y.fwd, v3(1, 1, 1)), -6, 6, 16, TOL);
    assert_inverse_pair(&y, TOL, "translate-rotate-scale");
}

/* x' = x + xy*y + xz*z, y' = y + yx*x + yz*z, z' = z + zx*x + zy*y. */
Test(mat4, shear)
{
    xform sh = xform_shear(1, 0, 0, 0.5f, 0, 0);
    ASSERT_V3_NEAR(mat4_point(&sh.fwd, v3(1, 2, 3)), 3, 3.5, 3, TOL);
    ASSERT_V3_NEAR(mat4_point(&sh.inv, v3(3, 3.5f, 3)), 1, 2, 3, TOL);
    assert_inverse_pair(&sh, TOL, "shear");
    xform all = xform_shear(0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f);
    /* (1, 2, 3): x = 1 + 0.2 + 0.6, y = 2 + 0.3 + 1.2, z = 3 + 0.5 + 1.2 */
    ASSERT_V3_NEAR(mat4_point(&all.fwd, v3(1, 2, 3)), 1.8, 3.5, 4.7, TOL);
    assert_inverse_pair(&all, TOL, "full shear");
    /* shear composed with the rest */
    xform r = xform_rotate(v3(1, 2, 3), 33.0f), t = xform_translate(v3(-4, 5, 6));
    xform a = xform_then(&all, &r);
    a = xform_then(&a, &t);
    assert_inverse_pair(&a, TOL, "shear-rotate-translate");
}

/* Random products of the elementary transforms, and general matrices
 * inverted by mat4_invert: inverse times forward is the identity. */
Test(mat4, inverse_times_forward_is_identity)
{
    rng g = rng_seed(42, 1);
    for (int i = 0; i < 500; i++) {
        xform x = xform_identity();
        for (int k = 0; k < 4; k++) {
            xform step;
            float a = rng_float(&g) * 2 - 1, b = rng_float(&g) * 2 - 1, c = rng_float(&g) * 2 - 1;
            switch (rng_u32(&g) % 4) {
            case 0:
                step = xform_translate(v3(5 * a, 5 * b, 5 * c));
                break;
            case 1: /* scales in +-[0.5, 2] */
                step = xform_scale(v3(copysignf(0.5f + 1.5f * fabsf(a), a),
                                      copysignf(0.5f + 1.5f * fabsf(b), b), 0.5f + 1.5f * fabsf(c)));
                break;
            case 2:
                step = xform_rotate(v3(a, b, c + 1e-3f), 360.0f * rng_float(&g));
                break;
            default:
                step = xform_shear(0.5f * a, 0.5f * b, 0.5f * c, 0, 0, 0);
                break;
            }
            x = xform_then(&x, &step);
        }
        assert_inverse_pair(&x, 1e-4, "random product");
        /* and mat4_invert agrees with the inverse carried along */
        mat4 inv;
        cr_assert(mat4_invert(&x.fwd, &inv));
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                ASSERT_NEAR(inv.m[r][c], x.inv.m[r][c], 1e-4 * (1 + fabs(x.inv.m[r][c])));
    }
    /* A general (non-affine-looking) invertible matrix. */
    mat4 m = {{{2, 1, 0, 3}, {0, 1, 4, -1}, {1, 0, 1, 2}, {0, 0, 0, 1}}};
    xform x;
    cr_assert(xform_from_matrix(&m, &x));
    assert_inverse_pair(&x, TOL, "from matrix");
}

Test(mat4, singular_matrices_are_refused)
{
    mat4 inv, zero = {{{0}}};
    cr_assert_not(mat4_invert(&zero, &inv));
    mat4 flat = mat4_identity(); /* squashes z */
    flat.m[2][2] = 0.0f;
    cr_assert_not(mat4_invert(&flat, &inv));
    mat4 dup = {{{1, 2, 3, 0}, {2, 4, 6, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}; /* rows 0, 1 parallel */
    cr_assert_not(mat4_invert(&dup, &inv));
    mat4 nan = mat4_identity();
    nan.m[0][1] = NAN;
    cr_assert_not(mat4_invert(&nan, &inv));
    xform x;
    cr_assert_not(xform_from_matrix(&flat, &x));
}

/* Translation moves points but not directions or normals. Under the
 * non-uniform scale (2, 1, 1) the plane x + y = 1 (normal (1, 1, 0))
 * becomes x/2 + y = 1, whose normal is (0.5, 1, 0): the inverse transpose
 * gives that; the forward matrix would give (2, 1, 0), which is wrong. */
Test(mat4, points_directions_and_normals)
{
    xform t = xform_translate(v3(1, 2, 3));
    ASSERT_V3_NEAR(mat4_point(&t.fwd, v3(1, 1, 1)), 2, 3, 4, 0);
    ASSERT_V3_NEAR(mat4_vector(&t.fwd, v3(1, 1, 1)), 1, 1, 1, 0);
    ASSERT_V3_NEAR(xform_normal(&t, v3(0, 0, 1)), 0, 0, 1, 0);

    xform s = xform_scale(v3(2, 1, 1));
    ASSERT_V3_NEAR(mat4_point(&s.fwd, v3(1, 1, 1)), 2, 1, 1, 0);
    ASSERT_V3_NEAR(mat4_vector(&s.fwd, v3(1, 1, 1)), 2, 1, 1, 0);
    vec3 n = v3_norm(xform_normal(&s, v3(1, 1, 0)));
    ASSERT_V3_NEAR(n, 1 / sqrt(5.0), 2 / sqrt(5.0), 0, TOL);

    /* For any transform, a normal stays perpendicular to transformed tangents. */
    rng g = rng_seed(7, 2);
    xform sh = xform_shear(0.3f, -0.2f, 0.1f, 0.4f, 0, -0.5f), sc = xform_scale(v3(3, 0.5f, 2)),
          r = xform_rotate(v3(1, -2, 0.5f), 70.0f);
    xform x = xform_then(&sh, &sc);
    x = xform_then(&x, &r);
    for (int i = 0; i < 1000; i++) {
        vec3 nn = v3_norm(v3(rng_float(&g) - 0.5f, rng_float(&g) - 0.5f, rng_float(&g) - 0.5f));
        vec3 a, b;
        v3_basis(nn, &a, &b);
        vec3 wn = v3_norm(xform_normal(&x, nn));
        vec3 wa = v3_norm(mat4_vector(&x.fwd, a)), wb = v3_norm(mat4_vector(&x.fwd, b));
        ASSERT_NEAR(v3_dot(wn, wa), 0.0, TOL);
        ASSERT_NEAR(v3_dot(wn, wb), 0.0, TOL);
    }
}

/* Right-handed rotations: 90 degrees about +z takes +x to +y; 120 degrees
 * about (1, 1, 1) cycles x -> y -> z -> x; and a hand value by Rodrigues:
 * (1, 0, 0) turned 90 degrees about (0, 1, 1)/sqrt2 is
 * v cos + (k x v) sin + k (k.v)(1 - cos) = (0, 1/sqrt2, -1/sqrt2). */
Test(mat4, rotation_about_arbitrary_axis)
{
    xform z = xform_rotate(v3(0, 0, 5), 90.0f); /* the axis need not be unit */
    ASSERT_V3_NEAR(mat4_vector(&z.fwd, v3(1, 0, 0)), 0, 1, 0, TOL);
    ASSERT_V3_NEAR(mat4_vector(&z.fwd, v3(0, 1, 0)), -1, 0, 0, TOL);
    xform x = xform_rotate(v3(1, 0, 0), 90.0f);
    ASSERT_V3_NEAR(mat4_vector(&x.fwd, v3(0, 1, 0)), 0, 0, 1, TOL);
    xform y = xform_rotate(v3(0, 1, 0), 90.0f);
    ASSERT_V3_NEAR(mat4_vector(&y.fwd, v3(0, 0, 1)), 1, 0, 0, TOL);

    xform d = xform_rotate(v3(1, 1, 1), 120.0f);
    ASSERT_V3_NEAR(mat4_point(&d.fwd, v3(1, 0, 0)), 0, 1, 0, TOL);
    ASSERT_V3_NEAR(mat4_point(&d.fwd, v3(0, 1, 0)), 0, 0, 1, TOL);
    ASSERT_V3_NEAR(mat4_point(&d.fwd, v3(0, 0, 1)), 1, 0, 0, TOL);
    ASSERT_V3_NEAR(mat4_point(&d.fwd, v3(1, 1, 1)), 1, 1, 1, TOL); /* the axis is fixed */

    xform k = xform_rotate(v3(0, 1, 1), 90.0f);
    ASSERT_V3_NEAR(mat4_vector(&k.fwd, v3(1, 0, 0)), 0, M_SQRT1_2, -M_SQRT1_2, TOL);
    /* 30 degrees about (0, 1, 1)/sqrt2 of (1, 0, 0):
     * (cos30, sin30/sqrt2, -sin30/sqrt2) since k.v = 0. */
    xform k30 = xform_rotate(v3(0, 1, 1), 30.0f);
    ASSERT_V3_NEAR(mat4_vector(&k30.fwd, v3(1, 0, 0)), cos(M_PI / 6), 0.5 * M_SQRT1_2,
                   -0.5 * M_SQRT1_2, TOL);

    /* A rotation's inverse is its transpose, and it keeps lengths. */
    xform r = xform_rotate(v3(-2, 0.5f, 3), 77.0f);
    mat4 rt = mat4_transpose(&r.fwd);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            ASSERT_NEAR(rt.m[i][j], r.inv.m[i][j], TOL);
    assert_inverse_pair(&r, TOL, "rotation");
    ASSERT_NEAR(v3_len(mat4_vector(&r.fwd, v3(3, -4, 12))), 13.0, 1e-4);
    /* A zero axis gives the identity rather than NaNs. */
    xform z0 = xform_rotate(v3(0, 0, 0), 45.0f);
    cr_assert(xform_is_identity(&z0));
}

/* Normals under a rotation are rotated like directions. */
Test(mat4, normals_under_rotation_and_uniform_scale)
{
    xform r = xform_rotate(v3(0, 0, 1), 90.0f), s = xform_scale(v3(3, 3, 3));
    xform x = xform_then(&r, &s);
    ASSERT_V3_NEAR(v3_norm(xform_normal(&x, v3(1, 0, 0))), 0, 1, 0, TOL);
    /* unnormalised: the inverse transpose of 3R scales normals by 1/3 */
    ASSERT_V3_NEAR(xform_normal(&x, v3(1, 0, 0)), 0, 1.0 / 3.0, 0, TOL);
    /* translation in the chain changes nothing for normals */
    xform t = xform_translate(v3(10, -20, 30));
    xform xt = xform_then(&x, &t);
    ASSERT_V3_NEAR(xform_normal(&xt, v3(0, 1, 0)), -1.0 / 3.0, 0, 0, TOL);
}

/* xform_is_finite: false as soon as one entry of either matrix is infinite
 * or NaN, wherever it is. */
Test(mat4, is_finite_finds_any_bad_entry)
{
    xform x = xform_rotate(v3(1, 2, 3), 30);
    cr_assert(xform_is_finite(&x));
    const float bad[3] = {INFINITY, -INFINITY, NAN};
    for (int k = 0; k < 32; k++)
        for (int b = 0; b < 3; b++) {
            xform y = x;
            mat4 *m = k < 16 ? &y.fwd : &y.inv;
            m->m[k % 16 / 4][k % 4] = bad[b];
            cr_assert_not(xform_is_finite(&y), "entry %d", k);
        }
    xform big = xform_scale(v3(3e38f, 1, 1));
    cr_assert(xform_is_finite(&big), "large but finite");
}

/* A random affine step: a translation, a rotation, a scale (mirrored when
 * a factor is negative), a shear, or a general matrix, at scales from
 * 1e-3 to 1e3 so that sums round. */
static xform random_step(rng *g)
{
    float a = rng_float(g) * 2 - 1, b = rng_float(g) * 2 - 1, c = rng_float(g) * 2 - 1;
    float big = powf(10.0f, 6.0f * rng_float(g) - 3.0f);
    switch (rng_u32(g) % 5) {
    case 0:
        return xform_translate(v3(a * big, b * big, c * big));
    case 1:
        return xform_rotate(v3(a, b, c + 1e-3f), 720.0f * rng_float(g) - 360.0f);
    case 2:
        return xform_scale(v3((a < 0 ? -1 : 1) * (fabsf(a) + 0.1f) * big, b + 2.0f,
                              c < 0 ? -0.5f : 3.0f));
    case 3:
        return xform_shear(a, b * big, c, a * b, b * c, c * a);
    default: {
        mat4 m = mat4_identity();
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++)
                m.m[i][j] = (rng_float(g) * 2 - 1) * (j == 3 ? big : 1.0f) + (i == j ? 2.0f : 0.0f);
        xform x = xform_identity();
        xform_from_matrix(&m, &x);
        return x;
    }
    }
}

/* The loader composes with xform_then_affine: it must give xform_then's
 * very bits (the images depend on them), on chains of every kind of step. */
Test(mat4, affine_compose_equals_the_general_one_to_the_bit)
{
    rng g = rng_seed(2025, 3);
    for (int t = 0; t < 20000; t++) {
        xform general = random_step(&g), affine = general;
        int n = 1 + (int)(rng_u32(&g) % 6);
        for (int s = 0; s < n; s++) {
            xform step = random_step(&g);
            general = xform_then(&general, &step);
            affine = xform_then_affine(&affine, &step);
            cr_assert(memcmp(&general, &affine, sizeof general) == 0,
                      "chain %d, step %d: the affine compose differs", t, s);
        }
    }
}

/* Signed zeros too: -0 entries (a rotation by 180 degrees, a mirror) must
 * come out as mat4_mul gives them. */
Test(mat4, affine_compose_keeps_signed_zeros)
{
    xform a = xform_rotate(v3(0, 1, 0), 180.0f), b = xform_scale(v3(-1, 1, -1));
    a.fwd.m[0][1] = -0.0f;
    xform g = xform_then(&a, &b), f = xform_then_affine(&a, &b);
    cr_assert(memcmp(&g, &f, sizeof g) == 0);
}

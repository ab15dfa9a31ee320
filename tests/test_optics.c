/* Optics (src/shade/optics.h, and v3_reflect in src/core/vec3.h): mirror
 * reflection, Snell refraction entering (1 -> 1.5) and leaving (1.5 -> 1)
 * glass, total internal reflection at and beyond the critical angle
 * asin(1/1.5), and Schlick's Fresnel approximation.
 *
 * The surface is the plane y = 0 with normal (0, 1, 0); an incident ray at
 * angle a from the normal travels along (sin a, -cos a, 0). Tolerance 1e-6
 * on directions (unit vectors in float) and reflectances. */
#include <criterion/criterion.h>
#include <math.h>

#include "shade/optics.h"
#include "near.h"

#define TOL 1e-6

static const vec3 UP = {0.0f, 1.0f, 0.0f};

static vec3 incident(double degrees)
{
    double a = degrees * M_PI / 180.0;
    return v3((float)sin(a), (float)-cos(a), 0.0f);
}

Test(optics, reflection_against_hand_values)
{
    ASSERT_V3_NEAR(v3_reflect(v3(0.6f, -0.8f, 0), UP), 0.6, 0.8, 0, TOL);
    ASSERT_V3_NEAR(v3_reflect(v3(0, -1, 0), UP), 0, 1, 0, TOL); /* straight back */
    ASSERT_V3_NEAR(v3_reflect(incident(30), UP), 0.5, cos(M_PI / 6), 0, TOL);
    /* a tilted normal (1, 1, 0)/sqrt2: a ray down -y leaves along +x */
    vec3 n = v3_norm(v3(1, 1, 0));
    ASSERT_V3_NEAR(v3_reflect(v3(0, -1, 0), n), 1, 0, 0, TOL);
    /* reflection keeps length and the tangential part, negates the normal part */
    vec3 d = v3_norm(v3(0.3f, -0.5f, 0.8f)), r = v3_reflect(d, n);
    ASSERT_NEAR(v3_len(r), 1.0, TOL);
    ASSERT_NEAR(v3_dot(r, n), -v3_dot(d, n), TOL);
    ASSERT_V3_NEAR(v3_sub(r, v3_scale(n, v3_dot(r, n))), d.x - n.x * v3_dot(d, n),
                   d.y - n.y * v3_dot(d, n), d.z - n.z * v3_dot(d, n), TOL);
}

/* The transmitted direction for sin t = (n1/n2) sin i is
 * (sin t, -cos t, 0). Hand values:
 *   1 -> 1.5 at 30: sin t = 1/3,      cos t = 0.942809042
 *   1 -> 1.5 at 45: sin t = 0.4714045, cos t = 0.881917104
 *   1.5 -> 1 at 30: sin t = 0.75,      cos t = 0.661437828 */
Test(optics, snell_entering_and_leaving)
{
    vec3 t;
    cr_assert(optics_refract(incident(30), UP, 1.0f / 1.5f, &t));
    ASSERT_V3_NEAR(t, 1.0 / 3.0, -0.942809042, 0, TOL);
    cr_assert(optics_refract(incident(45), UP, 1.0f / 1.5f, &t));
    ASSERT_V3_NEAR(t, 0.471404521, -0.881917104, 0, TOL);
    cr_assert(optics_refract(incident(30), UP, 1.5f, &t));
    ASSERT_V3_NEAR(t, 0.75, -0.661437828, 0, TOL);
    /* normal incidence goes straight through either way */
    cr_assert(optics_refract(v3(0, -1, 0), UP, 1.0f / 1.5f, &t));
    ASSERT_V3_NEAR(t, 0, -1, 0, TOL);
    cr_assert(optics_refract(v3(0, -1, 0), UP, 1.5f, &t));
    ASSERT_V3_NEAR(t, 0, -1, 0, TOL);
    /* eta 1: undeviated */
    cr_assert(optics_refract(incident(60), UP, 1.0f, &t));
    ASSERT_V3_NEAR(t, sin(M_PI / 3), -0.5, 0, TOL);
}

/* Over a sweep of angles and a general plane: the transmitted ray is unit,
 * coplanar with d and n, on the far side, and obeys n1 sin i = n2 sin t;
 * sending it back out retraces the ray. */
Test(optics, snell_law_holds_over_a_sweep)
{
    vec3 n = v3_norm(v3(0.2f, 0.9f, -0.4f));
    vec3 tan = v3_norm(v3_cross(n, v3(1, 0, 0)));
    for (int deg = 0; deg < 90; deg++) {
        double a = deg * M_PI / 180.0;
        vec3 d = v3_norm(v3_madd(v3_scale(n, (float)-cos(a)), tan, (float)sin(a)));
        vec3 t, back;
        cr_assert(optics_refract(d, n, 1.0f / 1.5f, &t), "%d degrees", deg);
        ASSERT_NEAR(v3_len(t), 1.0, 1e-5);
        cr_assert_lt(v3_dot(t, n), 0.0f);
        ASSERT_NEAR(v3_dot(t, v3_cross(n, tan)), 0.0, 1e-5); /* in the plane of d and n */
        double sin_t = v3_len(v3_cross(t, n)), sin_i = v3_len(v3_cross(d, n));
        ASSERT_NEAR(1.5 * sin_t, 1.0 * sin_i, 1e-5);
        /* reversibility: -t leaving the glass (normal -n faces against it) gives -d */
        cr_assert(optics_refract(v3_neg(t), v3_neg(n), 1.5f, &back), "%d degrees back", deg);
        ASSERT_V3_NEAR(back, -d.x, -d.y, -d.z, 1e-4);
    }
}

/* Leaving glass (eta 1.5), sin t = 1.5 sin i reaches 1 at the critical
 * angle asin(1/1.5) = 41.8103149 degrees: at it and beyond, total internal
 * reflection (false); just below, refraction at a grazing angle. */
Test(optics, total_internal_reflection_at_the_critical_angle)
{
    double crit = asin(1.0 / 1.5);
    vec3 t = v3(7, 7, 7);
    vec3 at = v3((float)sin(crit), (float)-cos(crit), 0);
    cr_assert_not(optics_refract(at, UP, 1.5f, &t), "refracts at exactly the critical angle");
    cr_assert_not(optics_refract(incident(45), UP, 1.5f, &t));
    cr_assert_not(optics_refract(incident(60), UP, 1.5f, &t));
    cr_assert_not(optics_refract(incident(89.9), UP, 1.5f, &t));
    cr_assert_not(optics_refract(incident(crit * 180 / M_PI + 0.01), UP, 1.5f, &t));
    ASSERT_V3_NEAR(t, 7, 7, 7, 0); /* left alone under TIR */

    /* 0.01 degree below: sin t = 1.5 sin(41.8003149 deg) = 0.999804 */
    double below = crit - 0.01 * M_PI / 180.0;
    cr_assert(optics_refract(incident(below * 180 / M_PI), UP, 1.5f, &t));
    double st = 1.5 * sin(below);
    ASSERT_V3_NEAR(t, st, -sqrt(1 - st * st), 0, 1e-5);
    /* entering glass never reflects totally, even at grazing incidence */
    cr_assert(optics_refract(incident(89.9), UP, 1.0f / 1.5f, &t));
    ASSERT_NEAR(t.x, sin(89.9 * M_PI / 180.0) / 1.5, 1e-5);
}

/* Schlick: R(cos) = R0 + (1 - R0)(1 - cos)^5, R0 = ((n1 - n2)/(n1 + n2))^2. */
Test(optics, schlick_fresnel)
{
    ASSERT_NEAR(optics_schlick(1.0f, 1.0f, 1.5f), 0.04, TOL); /* (0.5/2.5)^2 */
    ASSERT_NEAR(optics_schlick(1.0f, 1.5f, 1.0f), 0.04, TOL);
    ASSERT_NEAR(optics_schlick(1.0f, 1.0f, 1.33f), pow(0.33 / 2.33, 2), TOL);
    ASSERT_NEAR(optics_schlick(1.0f, 1.0f, 2.4f), pow(1.4 / 3.4, 2), TOL);
    ASSERT_NEAR(optics_schlick(1.0f, 1.2f, 1.2f), 0.0, TOL); /* matched media */
    ASSERT_NEAR(optics_schlick(0.0f, 1.0f, 1.5f), 1.0, TOL); /* grazing */
    /* cos 60 = 0.5: 0.04 + 0.96 / 32 */
    ASSERT_NEAR(optics_schlick(0.5f, 1.0f, 1.5f), 0.04 + 0.96 / 32.0, TOL);
    /* rises monotonically from R0 to 1 as the angle grows */
    float prev = optics_schlick(1.0f, 1.0f, 1.5f);
    for (int i = 99; i >= 0; i--) {
        float r = optics_schlick((float)i / 100.0f, 1.0f, 1.5f);
        cr_assert_geq(r, prev, "R(%g) = %g < %g", i / 100.0, (double)r, (double)prev);
        prev = r;
    }
}

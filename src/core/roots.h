/* roots: the real roots of a polynomial of degree 2 to 4 on an interval,
 * in double precision, by the method of Yuksel, "High-Performance
 * Polynomial Root Finding for Graphics" (Proc. ACM Comput. Graph.
 * Interact. Tech. 5(3), HPG 2022). The roots of the derivative (found the
 * same way, one degree down, ending in the closed-form quadratic) cut the
 * interval into pieces on which the polynomial is monotonic; a piece whose
 * ends have opposite signs holds exactly one root, found by Newton's
 * method kept inside the bracket (a step that would leave it bisects
 * instead). So no root that crosses zero is lost, however close two roots
 * are, and each comes out to full double precision (the first root alone,
 * when the quartic bends towards it from lo on, or from its first
 * inflection after bending away from it up to there, or from its second
 * inflection when the first piece has none and the one between the
 * inflections can have none, by a Newton search that stops at a step
 * under 1e-7: good to about 1e-14 at a simple root, 1e-12 close to a
 * double one, and about 1e-7 at a double one). A root where the
 * polynomial only touches zero (a tangent ray) is not reported.
 *
 * Coefficients are c[0] + c[1] x + ... + c[n] x^n. Roots are those in the
 * open interval (lo, hi) at which the sign changes, in increasing order. */
#ifndef GLINT_CORE_ROOTS_H
#define GLINT_CORE_ROOTS_H

#include <stdbool.h>

/* Both roots of c[0] + c[1] x + c[2] x^2 in (lo, hi), touching ones
 * included (these are the turning points of the cubic above). */
int roots_quadratic(const double c[3], double lo, double hi, double out[2]);
int roots_cubic(const double c[4], double lo, double hi, double out[3]);
/* Stops after max roots (1: just the first). */
int roots_quartic(const double c[5], double lo, double hi, double out[4], int max);

/* True when the quartic c provably stays above zero on [0, hi], so that
 * roots_quartic(c, 0, hi, ...) finds no root: its Bernstein coefficients on
 * [0, hi], whose convex hull holds its values (Farin, "Curves and Surfaces
 * for CAGD", ch. 5), all exceed 1e-9 of the size of its coefficients
 * there. That margin is a million times the rounding of any value the
 * search computes, so none it meets changes sign and no Newton step it
 * takes converges; intervals under 1e-4 long are left to the search. */
static inline bool roots_quartic_above(const double c[5], double hi)
{
    double h2 = hi * hi;
    double a0 = c[0], a1 = c[1] * hi, a2 = c[2] * h2, a3 = c[3] * h2 * hi, a4 = c[4] * h2 * h2;
    double m = 1e-9 * (__builtin_fabs(a0) + __builtin_fabs(a1) + __builtin_fabs(a2) +
                       __builtin_fabs(a3) + __builtin_fabs(a4));
    return hi >= 1e-4 && a0 > m && a0 + 0.25 * a1 > m && a0 + 0.5 * a1 + a2 * (1.0 / 6.0) > m &&
           a0 + 0.75 * a1 + 0.5 * a2 + 0.25 * a3 > m && a0 + a1 + a2 + a3 + a4 > m;
}

static inline double roots_eval(const double *c, int degree, double x)
{
    double v = c[degree];
    for (int i = degree - 1; i >= 0; i--)
        v = v * x + c[i];
    return v;
}

/* The cubic c and the quartic c at x by Estrin's scheme, (c0 + c1 x) +
 * x^2 ((c2 + c3 x) + x^2 c4): the same polynomial as roots_eval's, rounded
 * in other places, in three dependent steps of a product and a sum (the
 * cubic: two) where Horner's rule takes four (the cubic: three) in a row. The Newton search for
 * the first root (roots.c's convex_first, torus8.h's t8_first_root) waits
 * on them at every step; they must be written the same way in both. */
static inline double roots_cubic_at(const double c[4], double x)
{
    double x2 = x * x;
    return (c[0] + c[1] * x) + x2 * (c[2] + c[3] * x);
}

static inline double roots_quartic_at(const double c[5], double x)
{
    double x2 = x * x;
    return (c[0] + c[1] * x) + x2 * ((c[2] + c[3] * x) + x2 * c[4]);
}

#endif

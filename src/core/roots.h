/* roots: the real roots of a polynomial of degree 2 to 4 on an interval,
 * in double precision, by the method of Yuksel, "High-Performance
 * Polynomial Root Finding for Graphics" (Proc. ACM Comput. Graph.
 * Interact. Tech. 5(3), HPG 2022). The roots of the derivative (found the
 * same way, one degree down, ending in the closed-form quadratic) cut the
 * interval into pieces on which the polynomial is monotonic; a piece whose
 * ends have opposite signs holds exactly one root, found by Newton's
 * method kept inside the bracket (a step that would leave it bisects
 * instead). So no root that crosses zero is lost, however close two roots
 * are, and each comes out to full double precision. A root where the
 * polynomial only touches zero (a tangent ray) is not reported.
 *
 * Coefficients are c[0] + c[1] x + ... + c[n] x^n. Roots are those in the
 * open interval (lo, hi) at which the sign changes, in increasing order. */
#ifndef GLINT_CORE_ROOTS_H
#define GLINT_CORE_ROOTS_H

/* Both roots of c[0] + c[1] x + c[2] x^2 in (lo, hi), touching ones
 * included (these are the turning points of the cubic above). */
int roots_quadratic(const double c[3], double lo, double hi, double out[2]);
int roots_cubic(const double c[4], double lo, double hi, double out[3]);
/* Stops after max roots (1: just the first). */
int roots_quartic(const double c[5], double lo, double hi, double out[4], int max);

static inline double roots_eval(const double *c, int degree, double x)
{
    double v = c[degree];
    for (int i = degree - 1; i >= 0; i--)
        v = v * x + c[i];
    return v;
}

#endif

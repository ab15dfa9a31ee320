#include "roots.h"

#include <math.h>
#include <stdbool.h>

int roots_quadratic(const double c[3], double lo, double hi, double out[2])
{
    double r[2];
    int n = 0;
    if (c[2] == 0.0) {
        if (c[1] != 0.0)
            r[n++] = -c[0] / c[1];
    } else {
        double disc = c[1] * c[1] - 4.0 * c[2] * c[0];
        if (disc < 0.0)
            return 0;
        double q = -0.5 * (c[1] + copysign(sqrt(disc), c[1]));
        r[n++] = q / c[2];
        if (q != 0.0)
            r[n++] = c[0] / q;
        if (n == 2 && r[0] > r[1]) {
            double t = r[0];
            r[0] = r[1];
            r[1] = t;
        }
    }
    int k = 0;
    for (int i = 0; i < n; i++)
        if (r[i] > lo && r[i] < hi)
            out[k++] = r[i];
    return k;
}

/* fmax(1, v) for v >= 0 or NaN, without the library call fmax compiles to
 * here (a test for convergence made at every Newton step). */
static inline double at_least_one(double v) { return v > 1.0 ? v : 1.0; }

/* The one root of p in [a, b], where p(a) = fa and p(b) have opposite
 * signs and p is monotonic: Newton from the secant point, bisecting
 * whenever a step would leave the bracket, which shrinks every step. A
 * step too small to count ends the search even when it leaves the
 * bracket: x has just become one of its ends, and a converged x lies so
 * close to the root that rounding moves the step onto or past it (to
 * bisect then would throw x away and take some fifty halvings to come
 * back to it). */
static double bracketed(const double *c, const double *dc, int deg, double a, double b,
                        double fa, double fb)
{
    double x = a - fa * (b - a) / (fb - fa);
    if (!(x > a && x < b))
        x = 0.5 * (a + b);
    bool neg_a = fa < 0.0;
    for (int it = 0; it < 100; it++) {
        double f = roots_eval(c, deg, x);
        if (f == 0.0)
            return x;
        if ((f < 0.0) == neg_a)
            a = x;
        else
            b = x;
        double df = roots_eval(dc, deg - 1, x);
        double nx = df != 0.0 ? x - f / df : 0.5 * (a + b);
        if (!(nx > a && nx < b)) {
            if (fabs(nx - x) <= 1e-15 * at_least_one(fabs(x)))
                return x;
            nx = 0.5 * (a + b);
        }
        if (fabs(nx - x) <= 1e-15 * at_least_one(fabs(nx)) || nx == a || nx == b)
            return nx;
        x = nx;
    }
    return x;
}

/* The roots of c (degree deg, leading coefficient non-zero) in (lo, hi),
 * given the turning points crit[0 .. ncrit) inside it, in order. */
static int between(const double *c, const double *dc, int deg, double lo, double hi,
                   const double *crit, int ncrit, double *out, int max)
{
    int n = 0;
    double x0 = lo, f0 = roots_eval(c, deg, lo);
    for (int i = 0; i <= ncrit && n < max; i++) {
        double x1 = i < ncrit ? crit[i] : hi;
        double f1 = roots_eval(c, deg, x1);
        if ((f0 < 0.0 && f1 > 0.0) || (f0 > 0.0 && f1 < 0.0))
            out[n++] = bracketed(c, dc, deg, x0, x1, f0, f1);
        x0 = x1;
        f0 = f1;
    }
    return n;
}

int roots_cubic(const double c[4], double lo, double hi, double out[3])
{
    if (c[3] == 0.0)
        return roots_quadratic(c, lo, hi, out);
    double dc[3] = {c[1], 2.0 * c[2], 3.0 * c[3]};
    double crit[2];
    int ncrit = roots_quadratic(dc, lo, hi, crit);
    return between(c, dc, 3, lo, hi, crit, ncrit, out, 3);
}

/* The first root of the quartic c in (lo, e) when, with s the sign of
 * p(lo), s p falls at lo and bends upward all the way to e (e is the
 * first turning point of the cubic p', or hi): Newton's method from lo
 * then climbs to the root from below and never passes it, each tangent
 * lying under the curve (Fourier's condition), so no bracket is needed
 * and the quartic's turning point ahead need not be found. Returns 1 with
 * *root; 0 when s p stays positive on [lo, e) (a tangent reaches e, or
 * p' turns first); -1 when rounding left the path, for the general
 * search to decide. It stops at the first step under 1e-7 (relative):
 * the error left after a Newton step towards a simple root is of the
 * order of the step's square, so the root is then good to about 1e-14
 * (1e-12 near a double root), and waiting for a smaller step, as the
 * bracketed search does, costs one more step to learn that (two
 * dependent polynomial evaluations and a division: 4% of the render of
 * bench/README.md's scene of tori; with steps under 1e-9, one step in
 * sixteen was that one). At a double root, where the steps only halve,
 * the root is within about 1e-7, a float's resolution. Each step
 * evaluates p and p' by Estrin's scheme (roots_quartic_at): the step
 * waits on them. */
static int convex_first(const double *c, const double *dc, double lo, double e, double f0,
                        double *root)
{
    double s = f0 < 0.0 ? -1.0 : 1.0, x = lo, f = f0;
    for (int it = 0; it < 60; it++) {
        double df = roots_cubic_at(dc, x);
        if (!(s * df < 0.0))
            return 0;
        double nx = x - f / df;
        if (!(nx < e))
            return 0;
        if (fabs(nx - x) <= 1e-7 * at_least_one(fabs(nx))) {
            *root = nx;
            return nx > lo ? 1 : -1;
        }
        double nf = roots_quartic_at(c, nx);
        if (nf == 0.0) {
            *root = nx;
            return 1;
        }
        if (s * nf < 0.0) { /* rounding put nx past the root: it is bracketed */
            *root = bracketed(c, dc, 4, x, nx, f, nf);
            return 1;
        }
        x = nx;
        f = nf;
    }
    return -1;
}

/* The first root past convex_first's first piece [lo, bend[0]), in which
 * it found none, when two inflections cut (lo, hi): between them p bends
 * away from zero, so that where it has f0's sign at bend[1] it has it all
 * the way there; from bend[1] on it bends towards zero again, and
 * convex_first searches on up to hi. Returns as convex_first does, -1
 * also where the inflections' signs are not as they should be. Most rays
 * that pass a torus's near side and meet its far one come this way. */
static int past_first_piece(const double *c, const double *dc, const double *ddc,
                            const double bend[2], double hi, double f0, double *root)
{
    double f = roots_eval(c, 4, bend[1]);
    double bent = roots_eval(ddc, 2, 0.5 * (bend[0] + bend[1]));
    double pm = roots_eval(ddc, 2, 0.5 * (bend[1] + hi));
    bool pos = f0 > 0.0;
    if (f == 0.0 || bent == 0.0 || pm == 0.0 || (f > 0.0) != pos || (bent > 0.0) == pos ||
        (pm > 0.0) != pos)
        return -1;
    return convex_first(c, dc, bend[1], hi, f, root);
}

/* The quartic's turning points (the cubic's roots) are found one at a
 * time, in order, and each piece between two of them is searched as soon
 * as its end is known, so asking for the first root alone skips the
 * turning points beyond it; and for the first root alone, when the
 * quartic bends towards zero from lo on, or from its first inflection
 * after bending away from zero up to it, convex_first needs none, nor
 * past_first_piece after it when the first piece has no root. */
int roots_quartic(const double c[5], double lo, double hi, double out[4], int max)
{
    if (c[4] == 0.0) {
        double r[3];
        int n = roots_cubic(c, lo, hi, r);
        for (int i = 0; i < n && i < max; i++)
            out[i] = r[i];
        return n < max ? n : max;
    }
    const double dc[4] = {c[1], 2.0 * c[2], 3.0 * c[3], 4.0 * c[4]};
    const double ddc[3] = {dc[1], 2.0 * dc[2], 3.0 * dc[3]};
    double bend[2]; /* the cubic's turning points cut it into monotonic pieces */
    int nbend = roots_quadratic(ddc, lo, hi, bend), n = 0;
    double x0 = lo, f0 = roots_eval(c, 4, lo);  /* start of the quartic's piece */
    double y0 = lo, g0 = roots_eval(dc, 3, lo); /* start of the cubic's */
    if (max == 1 && f0 != 0.0) {
        /* convex_first where sign f0 p bends towards zero: from lo up to
         * p's first inflection (or hi); or, where it bends away from zero
         * up to that inflection (concave there, so it keeps its sign if
         * it has it at the inflection), from there up to the next. p'' is
         * taken in the middle of the piece searched, not only at its
         * start: the computed inflections may miss one within rounding of
         * lo, or list a double one where p'' keeps its sign. With no root
         * from lo to the first of two inflections, on from the second
         * (past_first_piece). */
        double pp = roots_eval(ddc, 2, lo);
        bool toward = (f0 > 0.0) == (pp > 0.0);
        if (toward || (nbend > 0 && pp != 0.0)) {
            double from = toward ? lo : bend[0], f = toward ? f0 : roots_eval(c, 4, from);
            double e = toward ? (nbend > 0 ? bend[0] : hi) : (nbend > 1 ? bend[1] : hi);
            int rest = toward ? nbend : nbend - 1; /* inflections past the piece */
            double pm = roots_eval(ddc, 2, 0.5 * (from + e));
            if (f != 0.0 && (f > 0.0) == (f0 > 0.0) && pm != 0.0 && (pm > 0.0) == (f0 > 0.0)) {
                int k = convex_first(c, dc, from, e, f, out);
                if (k > 0 || (k == 0 && rest == 0))
                    return k;
                if (k == 0 && toward && nbend == 2 &&
                    (k = past_first_piece(c, dc, ddc, bend, hi, f0, out)) >= 0)
                    return k;
            }
        }
    }
    for (int i = 0; i <= nbend; i++) {
        double y1 = i < nbend ? bend[i] : hi, g1 = roots_eval(dc, 3, y1);
        if ((g0 < 0.0 && g1 > 0.0) || (g0 > 0.0 && g1 < 0.0)) {
            double x1 = bracketed(dc, ddc, 3, y0, y1, g0, g1); /* a quartic turning point */
            double f1 = roots_eval(c, 4, x1);
            if ((f0 < 0.0 && f1 > 0.0) || (f0 > 0.0 && f1 < 0.0)) {
                out[n++] = bracketed(c, dc, 4, x0, x1, f0, f1);
                if (n >= max)
                    return n;
            }
            x0 = x1;
            f0 = f1;
        }
        y0 = y1;
        g0 = g1;
    }
    double f1 = roots_eval(c, 4, hi);
    if (n < max && ((f0 < 0.0 && f1 > 0.0) || (f0 > 0.0 && f1 < 0.0)))
        out[n++] = bracketed(c, dc, 4, x0, hi, f0, f1);
    return n;
}

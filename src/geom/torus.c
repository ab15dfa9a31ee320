/* Torus round the +y axis: f(p) = (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + z^2)
 * = 0 (p relative to the centre, R the major and r the minor radius);
 * f < 0 inside the tube.
 *
 * The quartic along the ray is solved in double precision by Yuksel's
 * method (core/roots.h): critical points cut the segment into monotonic
 * pieces, and each piece whose ends differ in sign gives its root by
 * bracketed Newton. Nothing is lost at grazing angles (two close roots
 * are split by the critical point between them) and nothing is invented
 * (a root is only reported where f changes sign). Two things keep the
 * coefficients well-conditioned: the ray is first clipped to the torus's
 * bounding box and the polynomial is written about the entry point, so
 * its coefficients are of the order of the torus's size however far away
 * the ray starts (about its origin they would grow as distance^4 and
 * swamp the roots); and the direction is made unit length, so the leading
 * coefficient is 1 and the unknown is arc length. A ray from inside the
 * tube starts with f < 0 and finds its way out the same way. A segment on
 * which the quartic provably stays above zero (roots_quartic_above: most
 * rays that pass the box's tests but miss the tube) is turned away before
 * the search, which would find nothing there either. */
#include <math.h>
#include <stddef.h>

#include "core/roots.h"
#include "shape.h"
#include "shape_inline.h"

/* Clips t in (tmin, tmax) to the torus's box, enlarged by 1% so that a
 * root is never on its faces; false when nothing is left. */
static bool setup(const struct torus *s, const ray *r, double tmin, double tmax, torus_quartic *q)
{
    double R = s->major, rm = s->minor;
    double o[3] = {(double)r->o.x - s->center.x, (double)r->o.y - s->center.y,
                   (double)r->o.z - s->center.z};
    double d[3] = {r->d.x, r->d.y, r->d.z};
    double ext[3] = {1.01 * (R + rm), 1.01 * rm, 1.01 * (R + rm)};
    /* First the line against the ball of radius ext[0] round the centre,
     * which costs no division: most rays that reach this test pass by. */
    double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double od = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
    double oo = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
    if (od * od < dd * (oo - ext[0] * ext[0]))
        return false;
    /* the three reciprocals from one division: 1 / d_a is the product of
     * the other two over that of all three, a flat axis (d_a = 0) counted
     * as 1 (from floats, the products stay in range) */
    double f[3] = {d[0] == 0.0 ? 1.0 : d[0], d[1] == 0.0 ? 1.0 : d[1], d[2] == 0.0 ? 1.0 : d[2]};
    double f01 = f[0] * f[1], all = 1.0 / (f01 * f[2]);
    double invs[3] = {f[1] * f[2] * all, f[0] * f[2] * all, f01 * all};
    double t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0.0) {
            if (fabs(o[a]) > ext[a])
                return false;
            continue;
        }
        double inv = invs[a];
        double ta = (-ext[a] - o[a]) * inv, tb = (ext[a] - o[a]) * inv;
        if (ta > tb) { /* (fmin and fmax are library calls) */
            double t = ta;
            ta = tb, tb = t;
        }
        t0 = ta > t0 ? ta : t0;
        t1 = tb < t1 ? tb : t1;
    }
    if (!(t0 < t1))
        return false;
    /* Within the slab |y| <= r the tube lies between the cylinders of radius
     * R - r and R + r round the axis: a segment wholly inside the inner one
     * (down the hole) or wholly outside the outer one (past a corner of the
     * box) misses. The squared distance from the axis is a quadratic in t,
     * largest at an end of the segment and least at its vertex, where it
     * is qc - qb^2 / qa: compared times qa, it needs no division. */
    double qa = d[0] * d[0] + d[2] * d[2], qb = o[0] * d[0] + o[2] * d[2];
    double qc = o[0] * o[0] + o[2] * o[2];
    double e0 = qc + t0 * (2.0 * qb + t0 * qa), e1 = qc + t1 * (2.0 * qb + t1 * qa);
    double inner = R > rm ? (R - rm) * (R - rm) * 0.999 : 0.0, outer = (R + rm) * (R + rm) * 1.001;
    if (e0 < inner && e1 < inner)
        return false;
    bool vertex = qa > 0.0 && t0 * qa < -qb && -qb < t1 * qa; /* within the segment */
    double least = vertex ? qa * qc - qb * qb : e0 < e1 ? e0 : e1;
    if (least > (vertex ? outer * qa : outer))
        return false;
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double il = 1.0 / len; /* one division, not three (torus8.h: each waits its turn) */
    double u[3] = {d[0] * il, d[1] * il, d[2] * il};
    double p[3] = {o[0] + t0 * d[0], o[1] + t0 * d[1], o[2] + t0 * d[2]};
    double b = p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
    double beta = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + R * R - rm * rm;
    double k = 4.0 * R * R;
    q->c[4] = 1.0;
    q->c[3] = 4.0 * b;
    q->c[2] = 4.0 * b * b + 2.0 * beta - k * (u[0] * u[0] + u[2] * u[2]);
    q->c[1] = 4.0 * b * beta - 2.0 * k * (p[0] * u[0] + p[2] * u[2]);
    q->c[0] = beta * beta - k * (p[0] * p[0] + p[2] * p[2]);
    q->t0 = t0;
    q->t1 = t1;
    q->py = p[1];
    q->uy = u[1];
    q->len = len;
    q->hi = (t1 - t0) * len;
    return true;
}

bool torus_solve(const torus_quartic *q, const ray *r, shape_hit *hit)
{
    if (roots_quartic_above(q->c, q->hi))
        return false;
    double roots[4];
    int n = roots_quartic(q->c, 0.0, q->hi, roots, 1);
    for (int pass = 0; pass < 2 && n > 0; pass++) {
        for (int i = 0; i < n; i++) {
            float t = (float)(q->t0 + roots[i] / q->len);
            if (ray_in_range(r, t)) {
                if (hit) {
                    hit->t = t;
                    hit->part = 0;
                }
                return true;
            }
        }
        /* The first root rounded onto tmin: look at the others. */
        n = pass == 0 ? roots_quartic(q->c, 0.0, q->hi, roots, 4) : 0;
    }
    return false;
}

bool torus_intersect(const struct torus *s, const ray *r, shape_hit *hit)
{
    torus_quartic q;
    return setup(s, r, r->tmin, r->tmax, &q) && torus_solve(&q, r, hit);
}

/* Whether the quartic, above zero beyond doubt at the entry, is below it
 * beyond doubt at x in (0, hi): by more than 1e-9 of the size of its
 * coefficients on the segment, a million times the rounding of any value
 * the search computes. The search then finds a root before x (some piece
 * between its turning points runs from above zero to below, and Newton's
 * method, started where the quartic bends towards zero, can neither stall
 * nor overshoot when the quartic is that far below zero ahead). */
static bool dips_below(const torus_quartic *q, double x)
{
    double h = q->hi, h2 = h * h;
    double size = fabs(q->c[0]) + fabs(q->c[1] * h) + fabs(q->c[2] * h2) +
                  fabs(q->c[3] * h2 * h) + fabs(q->c[4] * h2 * h2);
    double m = 1e-9 * size;
    return q->c[0] > m && roots_eval(q->c, 4, x) < -m;
}

/* torus_intersect's answer, without the root itself where it can
 * (torus_blocks_at_once): when every t of the clipped segment rounds into
 * (tmin, tmax), any root the search would find counts, and a ray that is
 * inside the tube where it crosses the torus's plane (most shadow rays
 * that a torus blocks) has one. */
bool torus_blocks_at_once(const torus_quartic *q, const ray *r)
{
    double t1 = q->t1;
    if ((float)q->t0 > r->tmin && (float)(t1 + 1e-9 * fabs(t1)) < r->tmax && q->uy != 0.0) {
        double x = -q->py / q->uy;
        return x > 0.0 && x < q->hi && dips_below(q, x);
    }
    return false;
}

bool torus_blocks(const torus_quartic *q, const ray *r)
{
    return torus_blocks_at_once(q, r) || torus_solve(q, r, NULL);
}

bool torus_occluded(const struct torus *s, const ray *r)
{
    torus_quartic q;
    return setup(s, r, r->tmin, r->tmax, &q) && torus_blocks(&q, r);
}

int torus_crossings(const struct torus *s, const ray *r, crossing *out, int max)
{
    torus_quartic q;
    if (!setup(s, r, r->tmin, INFINITY, &q))
        return 0;
    double roots[4];
    int n = roots_quartic(q.c, 0.0, q.hi, roots, 4), k = 0;
    double dc[4] = {q.c[1], 2.0 * q.c[2], 3.0 * q.c[3], 4.0 * q.c[4]};
    for (int i = 0; i < n && k < max; i++) {
        float t = (float)(q.t0 + roots[i] / q.len);
        if (!(t > r->tmin))
            continue;
        out[k++] = (crossing){.h = {.t = t, .part = 0}, .enter = roots_eval(dc, 3, roots[i]) < 0.0};
    }
    return k;
}

void torus_surface_no_uv(const struct torus *s, vec3 p, surface *out)
{
    double q[3];
    torus_nearest(s, p, &out->p, &out->n, q);
    out->u = out->v = 0.0f;
}

/* u runs once round the y axis (0.5 facing +z), v once round the tube (0.5
 * on the outer equator, rising over the top). */
void torus_surface(const struct torus *s, vec3 p, surface *out)
{
    double q[3];
    torus_nearest(s, p, &out->p, &out->n, q);
    double rho = sqrt(q[0] * q[0] + q[2] * q[2]);
    out->u = 0.5f + (float)(atan2(q[0], q[2]) * (0.5 / M_PI));
    out->v = 0.5f + (float)(atan2(q[1], rho - s->major) * (0.5 / M_PI));
}

/* Cone round the +y axis, pointed (top_radius 0) or truncated: the side
 * x^2 + z^2 = R(y)^2 with R(y) = radius + (top_radius - radius) y / height
 * for 0 <= y <= height (coordinates relative to base), plus the two disc
 * caps when capped. The side is a quadric, solved in double precision with
 * the stable form of the quadratic formula (q = -(b + sign(b) sqrt(disc)),
 * roots q / a and c / q: Press et al., Numerical Recipes, section 5.6), so
 * that rays from far away (10^4 x the cone's size) and rays nearly
 * parallel to the side (a close to 0, one root running off) keep their
 * digits. Every candidate (up to two on the side and one per cap) is
 * collected; intersect keeps the nearest in (tmin, tmax), span the first
 * and last (the capped cone is convex). */
#include <math.h>
#include "shape.h"

typedef struct cand {
    double t[4];
    int part[4];
    int n;
} cand;

static void add(cand *c, double t, int part)
{
    c->t[c->n] = t;
    c->part[c->n++] = part;
}

static void side(const struct cone *s, const double o[3], const double d[3], cand *c)
{
    double h = s->height, k = ((double)s->top_radius - s->radius) / h;
    double r0 = s->radius + k * o[1], r1 = k * d[1]; /* R along the ray: r0 + r1 t */
    double a = d[0] * d[0] + d[2] * d[2] - r1 * r1;
    double b = o[0] * d[0] + o[2] * d[2] - r0 * r1; /* half of B */
    double cc = o[0] * o[0] + o[2] * o[2] - r0 * r0;
    double ts[2];
    int n = 0;
    double scale = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (fabs(a) <= 1e-12 * scale) { /* parallel to a line of the side: one root */
        if (b != 0.0)
            ts[n++] = -cc / (2.0 * b);
    } else {
        double disc = b * b - a * cc;
        if (disc < 0.0)
            return;
        double q = -(b + copysign(sqrt(disc), b));
        ts[n++] = q / a;
        if (q != 0.0)
            ts[n++] = cc / q;
    }
    for (int i = 0; i < n; i++) {
        double y = o[1] + d[1] * ts[i];
        if (y >= 0.0 && y <= h && r0 + r1 * ts[i] >= 0.0)
            add(c, ts[i], 0);
    }
}

static cand candidates(const struct cone *s, const ray *r)
{
    double o[3] = {(double)r->o.x - s->base.x, (double)r->o.y - s->base.y,
                   (double)r->o.z - s->base.z};
    double d[3] = {r->d.x, r->d.y, r->d.z};
    cand c = {.n = 0};
    side(s, o, d, &c);
    if (!s->capped || d[1] == 0.0)
        return c;
    for (int i = 0; i < 2; i++) {
        double y = i ? s->height : 0.0, rad = i ? s->top_radius : s->radius;
        if (rad <= 0.0)
            continue;
        double t = (y - o[1]) / d[1];
        double x = o[0] + d[0] * t, z = o[2] + d[2] * t;
        if (x * x + z * z <= rad * rad)
            add(&c, t, 1 + i);
    }
    return c;
}

bool cone_intersect(const struct cone *s, const ray *r, shape_hit *hit)
{
    cand c = candidates(s, r);
    float best = r->tmax;
    int part = -1;
    for (int i = 0; i < c.n; i++) {
        float t = (float)c.t[i];
        if (t > r->tmin && t < best) {
            best = t;
            part = c.part[i];
        }
    }
    if (part < 0)
        return false;
    hit->t = best;
    hit->part = part;
    return true;
}

bool cone_span(const struct cone *s, const ray *r, shape_hit *in, shape_hit *out)
{
    cand c = candidates(s, r);
    if (c.n == 0)
        return false;
    int lo = 0, hi = 0;
    for (int i = 1; i < c.n; i++) {
        if (c.t[i] < c.t[lo])
            lo = i;
        if (c.t[i] > c.t[hi])
            hi = i;
    }
    *in = (shape_hit){.t = (float)c.t[lo], .part = c.part[lo]};
    *out = (shape_hit){.t = (float)c.t[hi], .part = c.part[hi]};
    return true;
}

/* Side: u once round the axis (u = 0.5 facing +z), v up the height; the
 * point moved out from the axis onto the side at its height. Caps: the
 * disc mapped onto [0, 1]^2 seen from outside, as for the cylinder.
 * Without uv, (u, v) are left 0 (the side's u costs an arc tangent). */
static void cone_point(const struct cone *s, vec3 p, const shape_hit *hit, surface *out, bool uv)
{
    float x = p.x - s->base.x, z = p.z - s->base.z;
    out->p = p;
    out->u = out->v = 0.0f;
    if (hit->part == 0) {
        float k = (s->top_radius - s->radius) / s->height;
        float y = fminf(fmaxf(p.y - s->base.y, 0.0f), s->height);
        float rad = fmaxf(s->radius + k * y, 0.0f);
        float len = sqrtf(x * x + z * z);
        float cx = len > 0.0f ? x / len : 0.0f, cz = len > 0.0f ? z / len : 1.0f;
        out->p = v3(s->base.x + cx * rad, s->base.y + y, s->base.z + cz * rad);
        out->n = len > 0.0f ? v3_norm(v3(cx, -k, cz)) : v3(0.0f, 1.0f, 0.0f);
        if (uv) {
            out->u = 0.5f + atan2f(x, z) * (float)(0.5 / M_PI);
            out->v = y / s->height;
        }
        return;
    }
    bool top = hit->part == 2;
    float sign = top ? 1.0f : -1.0f, rad = top ? s->top_radius : s->radius;
    out->p.y = s->base.y + (top ? s->height : 0.0f);
    out->n = v3(0.0f, sign, 0.0f);
    if (uv) {
        out->u = 0.5f + 0.5f * x / rad;
        out->v = 0.5f - 0.5f * sign * z / rad;
    }
}

void cone_surface(const struct cone *s, vec3 p, const shape_hit *hit, surface *out)
{
    cone_point(s, p, hit, out, true);
}

void cone_surface_no_uv(const struct cone *s, vec3 p, const shape_hit *hit, surface *out)
{
    cone_point(s, p, hit, out, false);
}

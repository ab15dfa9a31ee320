/* Sphere: |p - c| = r. The quadratic is solved in the form of Haines et al.,
 * "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems,
 * ch. 7, 2019): the discriminant from the distance of the centre to the
 * ray's line, and the near root from the numerically stable q formula. */
#include <math.h>
#include "shape.h"

bool sphere_intersect(const struct sphere *s, const ray *r, shape_hit *hit)
{
    vec3 f = v3_sub(r->o, s->center);
    float b = -v3_dot(f, r->d); /* half of -B */
    float rr = s->radius * s->radius;
    float c = v3_dot(f, f) - rr;
    /* From outside (c > 0) moving away (b < 0) both roots are negative:
     * q < 0, so c / q and q / a are too. Rays leaving a sphere's surface
     * (reflections, shadow rays) meet this first, before any division. */
    if (c > 0.0f && b < 0.0f && r->tmin >= 0.0f)
        return false;
    float a = v3_dot(r->d, r->d);
    vec3 l = v3_madd(f, r->d, b / a);
    float disc = a * (rr - v3_dot(l, l));
    if (disc < 0.0f)
        return false;
    float q = b + copysignf(sqrtf(disc), b);
    float t0, t1;
    if (q == 0.0f) {
        t0 = t1 = 0.0f;
    } else {
        t0 = c / q;
        t1 = q / a;
    }
    if (t0 > t1) {
        float t = t0;
        t0 = t1;
        t1 = t;
    }
    float t = t0;
    if (!ray_in_range(r, t)) {
        t = t1;
        if (!ray_in_range(r, t))
            return false;
    }
    hit->t = t;
    hit->part = 0;
    return true;
}

void sphere_surface_no_uv(const struct sphere *s, vec3 p, surface *out)
{
    vec3 n = v3_norm(v3_sub(p, s->center));
    out->p = v3_madd(s->center, n, s->radius); /* back onto the surface (shape.h) */
    out->n = n;
    out->u = out->v = 0.0f;
}

/* Longitude/latitude mapping over the whole sphere: u runs once round the
 * y axis with u = 0.5 facing +z and the seam at -z; v = 0 at the south pole,
 * 1 at the north pole. */

void sphere_surface(const struct sphere *s, vec3 p, surface *out)
{
    sphere_surface_no_uv(s, p, out);
    vec3 n = out->n;
    out->u = 0.5f + atan2f(n.x, n.z) * (float)(0.5 / M_PI);
    out->v = 0.5f + asinf(fmaxf(-1.0f, fminf(1.0f, n.y))) * (float)(1.0 / M_PI);
}

bool sphere_span(const struct sphere *s, const ray *r, shape_hit *in, shape_hit *out)
{
    vec3 f = v3_sub(r->o, s->center);
    float a = v3_dot(r->d, r->d);
    float b = -v3_dot(f, r->d);
    vec3 l = v3_madd(f, r->d, b / a);
    float rr = s->radius * s->radius;
    float disc = a * (rr - v3_dot(l, l));
    if (disc < 0.0f)
        return false;
    float c = v3_dot(f, f) - rr;
    float q = b + copysignf(sqrtf(disc), b);
    float t0 = q != 0.0f ? c / q : 0.0f, t1 = q != 0.0f ? q / a : 0.0f;
    *in = (shape_hit){.t = fminf(t0, t1)};
    *out = (shape_hit){.t = fmaxf(t0, t1)};
    return true;
}

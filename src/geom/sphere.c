/* Sphere: the test is geom/shape_inline.h's. */
#include <math.h>
#include "shape_inline.h"

bool sphere_intersect(const struct sphere *s, const ray *r, shape_hit *hit)
{
    return sphere_hit(s, r, hit);
}

/* Longitude/latitude mapping over the whole sphere: u runs once round the
 * y axis with u = 0.5 facing +z and the seam at -z; v = 0 at the south pole,
 * 1 at the north pole. */

void sphere_surface(const struct sphere *s, vec3 p, surface *out)
{
    sphere_surface_plain(s, p, out);
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

/* Infinite plane (p - point) . normal = 0; the test is geom/shape_inline.h's. */
#include <math.h>
#include "shape_inline.h"

bool plane_intersect(const struct plane *s, const ray *r, shape_hit *hit)
{
    return plane_hit(s, r, hit);
}

void plane_surface(const struct plane *s, vec3 p, surface *out)
{
    vec3 d = v3_sub(p, s->point);
    out->p = plane_onto(s, p, d);
    out->n = s->normal;
    out->u = v3_dot(d, s->tu);
    out->v = v3_dot(d, s->tv);
}

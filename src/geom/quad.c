/* Parallelogram: the test is geom/shape_inline.h's. */
#include "shape_inline.h"

bool quad_intersect(const struct quad *s, const ray *r, shape_hit *hit)
{
    return quad_hit(s, r, hit);
}

void quad_surface(const struct quad *s, vec3 p, const shape_hit *hit, surface *out)
{
    (void)p; /* the point from (u, v), on the plane (shape.h) */
    out->p = v3_madd(v3_madd(s->origin, s->edge_u, hit->b1), s->edge_v, hit->b2);
    out->n = s->normal;
    out->u = hit->b1;
    out->v = hit->b2;
}

/* Parallelogram: plane test, then the hit's coordinates along the two edges
 * from the precomputed w = n / (n . n) (Shirley, "Ray Tracing: The Next
 * Week", section 6). */
#include "shape.h"

bool quad_intersect(const struct quad *s, const ray *r, shape_hit *hit)
{
    float t;
    if (!ray_plane(r, s->origin, s->normal, &t))
        return false;
    vec3 q = v3_sub(ray_at(r, t), s->origin);
    float u = v3_dot(s->w, v3_cross(q, s->edge_v));
    float v = v3_dot(s->w, v3_cross(s->edge_u, q));
    if (!(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f))
        return false;
    hit->t = t;
    hit->part = 0;
    hit->b1 = u;
    hit->b2 = v;
    return true;
}

void quad_surface(const struct quad *s, vec3 p, const shape_hit *hit, surface *out)
{
    (void)p; /* the point from (u, v), on the plane (shape.h) */
    out->p = v3_madd(v3_madd(s->origin, s->edge_u, hit->b1), s->edge_v, hit->b2);
    out->n = s->normal;
    out->u = hit->b1;
    out->v = hit->b2;
}

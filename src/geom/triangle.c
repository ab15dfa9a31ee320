/* Triangle by Moller and Trumbore, "Fast, Minimum Storage Ray/Triangle
 * Intersection" (JGT 1997). Rays in the triangle's plane miss. */
#include <math.h>
#include "shape.h"

bool triangle_intersect(const struct triangle *s, const ray *r, shape_hit *hit)
{
    vec3 e1 = v3_sub(s->p1, s->p0), e2 = v3_sub(s->p2, s->p0);
    vec3 pv = v3_cross(r->d, e2);
    float det = v3_dot(e1, pv);
    if (det == 0.0f)
        return false;
    float inv = 1.0f / det;
    vec3 tv = v3_sub(r->o, s->p0);
    float b1 = v3_dot(tv, pv) * inv;
    if (!(b1 >= 0.0f && b1 <= 1.0f))
        return false;
    vec3 qv = v3_cross(tv, e1);
    float b2 = v3_dot(r->d, qv) * inv;
    if (!(b2 >= 0.0f && b1 + b2 <= 1.0f))
        return false;
    float t = v3_dot(e2, qv) * inv;
    if (!(t > r->tmin && t < r->tmax))
        return false;
    hit->t = t;
    hit->part = 0;
    hit->b1 = b1;
    hit->b2 = b2;
    return true;
}

void triangle_surface(const struct triangle *s, vec3 p, const shape_hit *hit, surface *out)
{
    float b0 = 1.0f - hit->b1 - hit->b2;
    out->p = p;
    out->n = v3_norm(v3_cross(v3_sub(s->p1, s->p0), v3_sub(s->p2, s->p0)));
    out->u = b0 * s->uv[0][0] + hit->b1 * s->uv[1][0] + hit->b2 * s->uv[2][0];
    out->v = b0 * s->uv[0][1] + hit->b1 * s->uv[1][1] + hit->b2 * s->uv[2][1];
}

/* A single triangle, by the watertight test (watertight.h). Rays in the
 * triangle's plane miss. */
#include "shape.h"
#include "watertight.h"

triangle_fit triangle_check(vec3 p0, vec3 p1, vec3 p2)
{
    if (!v3_is_finite(p0) || !v3_is_finite(p1) || !v3_is_finite(p2))
        return TRIANGLE_DEGENERATE;
    double ax = (double)p1.x - p0.x, ay = (double)p1.y - p0.y, az = (double)p1.z - p0.z;
    double bx = (double)p2.x - p0.x, by = (double)p2.y - p0.y, bz = (double)p2.z - p0.z;
    double nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    if (nx == 0.0 && ny == 0.0 && nz == 0.0)
        return TRIANGLE_DEGENERATE;
    /* The normal is normalised in floats at every hit: its squared length
     * must be a finite float. */
    vec3 n = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0));
    float len2 = v3_len2(n);
    if (!isfinite(len2))
        return TRIANGLE_TOO_LARGE;
    return len2 > 0.0f ? TRIANGLE_OK : TRIANGLE_DEGENERATE;
}

bool triangle_intersect(const struct triangle *s, const ray *r, shape_hit *hit)
{
    tri_ray tr = tri_ray_make(r);
    float t, b1, b2;
    if (!tri_intersect(&tr, s->p0, s->p1, s->p2, r->tmin, r->tmax, &t, &b1, &b2))
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
    (void)p; /* the point from the barycentrics, on the plane (shape.h) */
    out->p = v3_madd(v3_madd(s->p0, v3_sub(s->p1, s->p0), hit->b1), v3_sub(s->p2, s->p0), hit->b2);
    out->n = v3_norm(v3_cross(v3_sub(s->p1, s->p0), v3_sub(s->p2, s->p0)));
    out->u = b0 * s->uv[0][0] + hit->b1 * s->uv[1][0] + hit->b2 * s->uv[2][0];
    out->v = b0 * s->uv[0][1] + hit->b1 * s->uv[1][1] + hit->b2 * s->uv[2][1];
}

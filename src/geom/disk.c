/* Disk, or annulus when inner > 0: the plane test, then the hit's distance
 * from the centre against the two radii. Rays in the disk's plane miss. */
#include "shape.h"

bool disk_intersect(const struct disk *s, const ray *r, shape_hit *hit)
{
    float t;
    if (!ray_plane(r, s->center, s->normal, &t))
        return false;
    vec3 q = v3_sub(ray_at(r, t), s->center);
    float u = v3_dot(q, s->tu), v = v3_dot(q, s->tv);
    float rr = u * u + v * v;
    if (!(rr <= s->radius * s->radius && rr >= s->inner * s->inner))
        return false;
    hit->t = t;
    hit->part = 0;
    return true;
}

/* (u, v): the disk's square [-radius, radius]^2 along tu, tv mapped onto
 * [0, 1]^2, seen from the side the normal faces; the point is moved onto
 * the plane (shape.h). */
void disk_surface(const struct disk *s, vec3 p, surface *out)
{
    vec3 q = v3_sub(p, s->center);
    out->p = v3_madd(p, s->normal, -v3_dot(q, s->normal));
    out->n = s->normal;
    out->u = 0.5f + 0.5f * v3_dot(q, s->tu) / s->radius;
    out->v = 0.5f + 0.5f * v3_dot(q, s->tv) / s->radius;
}

/* Cylinder round the +y axis: the side (x-xc)^2 + (z-zc)^2 = r^2 with
 * 0 <= y - yb <= h, solved with the stable quadratic (as for the sphere,
 * in two dimensions), plus two disc caps. The nearest of up to four
 * candidate hits wins. */
#include <math.h>
#include "shape.h"

static void consider(float t, int part, const ray *r, float *best, int *best_part)
{
    if (t > r->tmin && t < *best) {
        *best = t;
        *best_part = part;
    }
}

bool cylinder_intersect(const struct cylinder *s, const ray *r, shape_hit *hit)
{
    float ox = r->o.x - s->base.x, oy = r->o.y - s->base.y, oz = r->o.z - s->base.z;
    float dx = r->d.x, dy = r->d.y, dz = r->d.z;
    float best = r->tmax;
    int part = -1;

    float a = dx * dx + dz * dz;
    if (a > 0.0f) {
        float b = -(ox * dx + oz * dz);
        float lx = ox + dx * (b / a), lz = oz + dz * (b / a);
        float rr = s->radius * s->radius;
        float disc = a * (rr - (lx * lx + lz * lz));
        if (disc >= 0.0f) {
            float c = ox * ox + oz * oz - rr;
            float q = b + copysignf(sqrtf(disc), b);
            float ts[2] = {q != 0.0f ? c / q : 0.0f, q / a};
            for (int i = 0; i < 2; i++) {
                float y = oy + dy * ts[i];
                if (y >= 0.0f && y <= s->height)
                    consider(ts[i], 0, r, &best, &part);
            }
        }
    }
    if (s->capped && dy != 0.0f) {
        float caps[2] = {0.0f, s->height};
        for (int i = 0; i < 2; i++) {
            float t = (caps[i] - oy) / dy;
            float x = ox + dx * t, z = oz + dz * t;
            if (x * x + z * z <= s->radius * s->radius)
                consider(t, 1 + i, r, &best, &part);
        }
    }
    if (part < 0)
        return false;
    hit->t = best;
    hit->part = part;
    return true;
}

/* Side: u once round the axis (u = 0.5 facing +z), v up the height. Caps:
 * the disc mapped onto [0, 1]^2 seen from outside. */
void cylinder_surface(const struct cylinder *s, vec3 p, const shape_hit *hit, surface *out)
{
    float x = p.x - s->base.x, z = p.z - s->base.z;
    out->p = p;
    if (hit->part == 0) {
        out->n = v3_norm(v3(x, 0.0f, z));
        out->u = 0.5f + atan2f(x, z) * (float)(0.5 / M_PI);
        out->v = s->height > 0.0f ? (p.y - s->base.y) / s->height : 0.0f;
        return;
    }
    float sign = hit->part == 2 ? 1.0f : -1.0f;
    out->n = v3(0.0f, sign, 0.0f);
    out->u = 0.5f + 0.5f * x / s->radius;
    out->v = 0.5f - 0.5f * sign * z / s->radius;
}

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
 * the disc mapped onto [0, 1]^2 seen from outside. Without uv, (u, v)
 * are left 0 (the side's u costs an arc tangent). */
static void cylinder_point(const struct cylinder *s, vec3 p, const shape_hit *hit, surface *out,
                           bool uv)
{
    float x = p.x - s->base.x, z = p.z - s->base.z;
    out->p = p;
    out->u = out->v = 0.0f;
    if (hit->part == 0) {
        out->n = v3_norm(v3(x, 0.0f, z));
        /* Back onto the side (shape.h). */
        out->p = v3(s->base.x + out->n.x * s->radius, p.y, s->base.z + out->n.z * s->radius);
        if (uv) {
            out->u = 0.5f + atan2f(x, z) * (float)(0.5 / M_PI);
            out->v = s->height > 0.0f ? (p.y - s->base.y) / s->height : 0.0f;
        }
        return;
    }
    float sign = hit->part == 2 ? 1.0f : -1.0f;
    out->p.y = s->base.y + (hit->part == 2 ? s->height : 0.0f);
    out->n = v3(0.0f, sign, 0.0f);
    if (uv) {
        out->u = 0.5f + 0.5f * x / s->radius;
        out->v = 0.5f - 0.5f * sign * z / s->radius;
    }
}

void cylinder_surface(const struct cylinder *s, vec3 p, const shape_hit *hit, surface *out)
{
    cylinder_point(s, p, hit, out, true);
}

void cylinder_surface_no_uv(const struct cylinder *s, vec3 p, const shape_hit *hit, surface *out)
{
    cylinder_point(s, p, hit, out, false);
}

/* The capped cylinder's entry and exit: the slab 0 <= y <= height met with
 * the infinite cylinder, each end keeping the part that bounds it. */
bool cylinder_span(const struct cylinder *s, const ray *r, shape_hit *in, shape_hit *out)
{
    float ox = r->o.x - s->base.x, oy = r->o.y - s->base.y, oz = r->o.z - s->base.z;
    float dx = r->d.x, dy = r->d.y, dz = r->d.z;
    float t0 = -INFINITY, t1 = INFINITY;
    int p0 = 0, p1 = 0;
    float a = dx * dx + dz * dz, rr = s->radius * s->radius;
    if (a > 0.0f) {
        float b = -(ox * dx + oz * dz);
        float lx = ox + dx * (b / a), lz = oz + dz * (b / a);
        float disc = a * (rr - (lx * lx + lz * lz));
        if (disc < 0.0f)
            return false;
        float c = ox * ox + oz * oz - rr;
        float q = b + copysignf(sqrtf(disc), b);
        float ra = q != 0.0f ? c / q : 0.0f, rb = q / a;
        t0 = fminf(ra, rb), t1 = fmaxf(ra, rb);
    } else if (ox * ox + oz * oz > rr) {
        return false;
    }
    if (dy != 0.0f) {
        float ya = -oy / dy, yb = (s->height - oy) / dy;
        int pa = 1, pb = 2;
        if (ya > yb) {
            float t = ya;
            ya = yb, yb = t;
            pa = 2, pb = 1;
        }
        if (ya > t0)
            t0 = ya, p0 = pa;
        if (yb < t1)
            t1 = yb, p1 = pb;
    } else if (oy < 0.0f || oy > s->height) {
        return false;
    }
    if (!(t0 <= t1))
        return false;
    *in = (shape_hit){.t = t0, .part = p0};
    *out = (shape_hit){.t = t1, .part = p1};
    return true;
}

/* Axis-aligned box by the slab method (Kay and Kajiya, "Ray Tracing Complex
 * Scenes", SIGGRAPH 1986), keeping which face bounds the interval so the
 * normal comes out exact. A ray parallel to a slab and outside it misses; one
 * inside it is unconstrained by that slab (IEEE infinities, NaN-free). */
#include <math.h>
#include "shape.h"

bool box_intersect(const struct box *s, const ray *r, shape_hit *hit)
{
    float tnear = -INFINITY, tfar = INFINITY;
    int near_face = -1, far_face = -1;
    const float o[3] = {r->o.x, r->o.y, r->o.z};
    const float d[3] = {r->d.x, r->d.y, r->d.z};
    const float lo[3] = {s->lo.x, s->lo.y, s->lo.z};
    const float hi[3] = {s->hi.x, s->hi.y, s->hi.z};
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0.0f) {
            if (o[a] < lo[a] || o[a] > hi[a])
                return false;
            continue;
        }
        float inv = 1.0f / d[a];
        float t0 = (lo[a] - o[a]) * inv, t1 = (hi[a] - o[a]) * inv;
        int f0 = 2 * a, f1 = 2 * a + 1;
        if (t0 > t1) {
            float t = t0;
            t0 = t1;
            t1 = t;
            f0 = 2 * a + 1;
            f1 = 2 * a;
        }
        if (t0 > tnear) {
            tnear = t0;
            near_face = f0;
        }
        if (t1 < tfar) {
            tfar = t1;
            far_face = f1;
        }
        if (tnear > tfar)
            return false;
    }
    if (ray_in_range(r, tnear)) {
        hit->t = tnear;
        hit->part = near_face;
        return true;
    }
    if (ray_in_range(r, tfar)) {
        hit->t = tfar;
        hit->part = far_face;
        return true;
    }
    return false;
}

/* Face f = axis*2 + side (side 1: the max face). (u, v) run over the face
 * along the next two axes in cyclic order, in [0, 1]. */
void box_surface(const struct box *s, vec3 p, const shape_hit *hit, surface *out)
{
    int axis = hit->part / 2, side = hit->part % 2;
    float n[3] = {0.0f, 0.0f, 0.0f};
    n[axis] = side ? 1.0f : -1.0f;
    int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    /* The face's coordinate exactly (shape.h). */
    float q[3] = {p.x, p.y, p.z};
    q[axis] = v3_at(side ? s->hi : s->lo, axis);
    p = v3(q[0], q[1], q[2]);
    vec3 ext = v3_sub(s->hi, s->lo), rel = v3_sub(p, s->lo);
    out->p = p;
    out->n = v3(n[0], n[1], n[2]);
    out->u = v3_at(ext, ua) > 0.0f ? v3_at(rel, ua) / v3_at(ext, ua) : 0.0f;
    out->v = v3_at(ext, va) > 0.0f ? v3_at(rel, va) / v3_at(ext, va) : 0.0f;
}

bool box_span(const struct box *s, const ray *r, shape_hit *in, shape_hit *out)
{
    float tnear = -INFINITY, tfar = INFINITY;
    int near_face = -1, far_face = -1;
    for (int a = 0; a < 3; a++) {
        float o = v3_at(r->o, a), d = v3_at(r->d, a);
        float lo = v3_at(s->lo, a), hi = v3_at(s->hi, a);
        if (d == 0.0f) {
            if (o < lo || o > hi)
                return false;
            continue;
        }
        float t0 = (lo - o) / d, t1 = (hi - o) / d;
        int f0 = 2 * a, f1 = 2 * a + 1;
        if (t0 > t1) {
            float t = t0;
            t0 = t1, t1 = t;
            f0 = 2 * a + 1, f1 = 2 * a;
        }
        if (t0 > tnear)
            tnear = t0, near_face = f0;
        if (t1 < tfar)
            tfar = t1, far_face = f1;
    }
    if (!(tnear <= tfar) || near_face < 0 || far_face < 0)
        return false;
    *in = (shape_hit){.t = tnear, .part = near_face};
    *out = (shape_hit){.t = tfar, .part = far_face};
    return true;
}

/* Rays against polyhedra (polyhedron.h): the half-space clipping of Haines
 * for convex ones, the faces' triangles for the others. */
#include <math.h>

#include "polyhedron.h"
#include "shape.h"
#include "watertight.h"

/* The line's interval inside a convex polyhedron and the faces it enters
 * and leaves by; false when the line misses. */
static bool convex_span(const polyhedron *p, const ray *r, float *tn, int *fn, float *tf, int *ff)
{
    float tnear = -INFINITY, tfar = INFINITY;
    int near_face = -1, far_face = -1;
    for (int f = 0; f < p->nfaces; f++) {
        const poly_face *F = &p->faces[f];
        float vn = v3_dot(F->n, r->d), dist = F->d - v3_dot(F->n, r->o);
        if (vn == 0.0f) {
            if (dist < 0.0f)
                return false; /* parallel and outside this face's half-space */
            continue;
        }
        float t = dist / vn;
        if (vn < 0.0f) {
            if (t > tnear)
                tnear = t, near_face = f;
        } else if (t < tfar) {
            tfar = t, far_face = f;
        }
        if (tnear > tfar)
            return false;
    }
    if (near_face < 0 || far_face < 0)
        return false;
    *tn = tnear, *fn = near_face, *tf = tfar, *ff = far_face;
    return true;
}

static bool polyhedron_span(const polyhedron *p, const ray *r, shape_hit *in, shape_hit *out)
{
    float tn, tf;
    int fn, ff;
    if (!convex_span(p, r, &tn, &fn, &tf, &ff))
        return false;
    *in = (shape_hit){.t = tn, .part = fn};
    *out = (shape_hit){.t = tf, .part = ff};
    return true;
}

static bool in_bounds(const polyhedron *p, const ray *r, float tmax)
{
    vec3 inv = v3(1.0f / r->d.x, 1.0f / r->d.y, 1.0f / r->d.z);
    aabb b = p->bounds;
    vec3 pad = v3s(1e-5f * v3_max_comp(aabb_extent(b)));
    return aabb_hit((aabb){v3_sub(b.lo, pad), v3_add(b.hi, pad)}, r->o, inv, r->tmin, tmax);
}

bool polyhedron_intersect(const polyhedron *p, const ray *r, shape_hit *hit)
{
    if (p->convex) {
        float tn, tf;
        int fn, ff;
        if (!convex_span(p, r, &tn, &fn, &tf, &ff))
            return false;
        if (ray_in_range(r, tn))
            *hit = (shape_hit){.t = tn, .part = fn};
        else if (ray_in_range(r, tf))
            *hit = (shape_hit){.t = tf, .part = ff};
        else
            return false;
        return true;
    }
    if (!in_bounds(p, r, r->tmax))
        return false;
    tri_ray tr = tri_ray_make(r);
    float best = r->tmax, t, b1, b2;
    int face = -1;
    for (int i = 0; i < p->ntris; i++) {
        const uint32_t *c = p->tri[i];
        if (tri_intersect(&tr, p->verts[c[0]], p->verts[c[1]], p->verts[c[2]], r->tmin, best, &t,
                          &b1, &b2)) {
            best = t;
            face = p->tri_face[i];
        }
    }
    if (face < 0)
        return false;
    *hit = (shape_hit){.t = best, .part = face};
    return true;
}

/* Every face crossing after tmin, nearest first, at most max (the nearest
 * kept when there are more). */
int polyhedron_crossings(const polyhedron *p, const ray *r, crossing *out, int max, bool *more)
{
    *more = false;
    if (p->convex) {
        shape_hit in, exit;
        if (!polyhedron_span(p, r, &in, &exit))
            return 0;
        int n = 0;
        if (in.t > r->tmin && max > n)
            out[n++] = (crossing){in, true};
        if (exit.t > r->tmin && max > n)
            out[n++] = (crossing){exit, false};
        return n;
    }
    if (!in_bounds(p, r, INFINITY))
        return 0;
    tri_ray tr = tri_ray_make(r);
    int n = 0;
    float t, b1, b2;
    for (int i = 0; i < p->ntris; i++) {
        const uint32_t *c = p->tri[i];
        if (!tri_intersect(&tr, p->verts[c[0]], p->verts[c[1]], p->verts[c[2]], r->tmin,
                           INFINITY, &t, &b1, &b2))
            continue;
        int f = p->tri_face[i];
        bool seen = false; /* the ray crossed an edge between two triangles of one face */
        for (int k = 0; k < n && !seen; k++)
            seen = out[k].h.part == f && out[k].h.t == t;
        if (seen)
            continue;
        crossing x = {{.t = t, .part = f}, v3_dot(p->faces[f].n, r->d) < 0.0f};
        int j = n < max ? n++ : n;
        if (j == max) { /* full: keep it only if nearer than the farthest */
            *more = true;
            if (t >= out[max - 1].h.t)
                continue;
            j = max - 1;
        }
        for (; j > 0 && out[j - 1].h.t > t; j--)
            out[j] = out[j - 1];
        out[j] = x;
    }
    return n;
}

void polyhedron_surface(const polyhedron *p, vec3 pt, const shape_hit *hit, surface *out)
{
    const poly_face *F = &p->faces[hit->part];
    out->p = v3_madd(pt, F->n, F->d - v3_dot(F->n, pt)); /* onto the face's plane (shape.h) */
    out->n = F->n;
    vec3 q = v3_sub(out->p, F->uo);
    out->u = v3_dot(q, F->su);
    out->v = v3_dot(q, F->sv);
}

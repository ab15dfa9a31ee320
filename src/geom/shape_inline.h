/* shape_inline: the intersection tests of the shapes that small scenes are
 * made of (sphere, quad, plane), as inline functions, so that the scene's walks
 * (scene/scene_trace.h) test them without a call through shape_intersect's
 * switch. sphere.c, quad.c and plane.c export the same tests for every
 * other caller, so there is one copy of each routine. */
#ifndef GLINT_GEOM_SHAPE_INLINE_H
#define GLINT_GEOM_SHAPE_INLINE_H

#include <math.h>
#include "geom/mesh.h"
#include "geom/shape.h"

/* Sphere: |p - c| = r. The quadratic is solved in the form of Haines et al.,
 * "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems,
 * ch. 7, 2019): the discriminant from the distance of the centre to the
 * ray's line, and the near root from the numerically stable q formula. */
/* Both roots of the ray's line with the sphere, *t0 <= *t1; false when
 * it misses, or when both roots lie behind a ray from tmin >= 0. The roots
 * do not depend on tmin, so a shadow ray's crossings of a sphere come from
 * one call (scene_shadow_object). */
__attribute__((always_inline)) static inline bool sphere_roots(const struct sphere *s, const ray *r,
                                                               float *t0, float *t1)
{
    vec3 f = v3_sub(r->o, s->center);
    float b = -v3_dot(f, r->d); /* half of -B */
    float rr = s->radius * s->radius;
    float c = v3_dot(f, f) - rr;
    /* From outside (c > 0) moving away (b < 0) both roots are negative:
     * q < 0, so c / q and q / a are too. Rays leaving a sphere's surface
     * (reflections, shadow rays) meet this first, before any division. */
    if (c > 0.0f && b < 0.0f && r->tmin >= 0.0f)
        return false;
    float a = v3_dot(r->d, r->d);
    vec3 l = v3_madd(f, r->d, b / a);
    float disc = a * (rr - v3_dot(l, l));
    if (disc < 0.0f)
        return false;
    float q = b + copysignf(sqrtf(disc), b);
    if (q == 0.0f) {
        *t0 = *t1 = 0.0f;
    } else {
        *t0 = c / q;
        *t1 = q / a;
    }
    if (*t0 > *t1) {
        float t = *t0;
        *t0 = *t1;
        *t1 = t;
    }
    return true;
}

__attribute__((always_inline)) static inline bool sphere_hit(const struct sphere *s, const ray *r, shape_hit *hit)
{
    float t0, t1;
    if (!sphere_roots(s, r, &t0, &t1))
        return false;
    float t = t0;
    if (!ray_in_range(r, t)) {
        t = t1;
        if (!ray_in_range(r, t))
            return false;
    }
    hit->t = t;
    hit->part = 0;
    return true;
}

/* Parallelogram: plane test, then the hit's coordinates along the two edges
 * from the precomputed w = n / (n . n) (Shirley, "Ray Tracing: The Next
 * Week", section 6). */
__attribute__((always_inline)) static inline bool quad_hit(const struct quad *s, const ray *r, shape_hit *hit)
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

/* The surface of a sphere at p without (u, v) (left 0), which cost two
 * inverse trigonometric functions: for surfaces whose material has no
 * texture; sphere_surface adds them. The geometric normal is set too. Inline,
 * because the point and the normal travel in registers then: passed to a
 * function and stored, a vec3's parts are written and read back in
 * different widths, and the read waits for the writes to reach memory. */
__attribute__((always_inline)) static inline void sphere_surface_plain(const struct sphere *s,
                                                                       vec3 p, surface *out)
{
    vec3 n = v3_norm(v3_sub(p, s->center));
    out->p = v3_madd(s->center, n, s->radius); /* back onto the surface (shape.h) */
    out->n = n;
    out->ng = n;
    out->u = out->v = 0.0f;
}

/* The point of the surface nearest p, and the outward normal there, in
 * closed form. f factors as (|q - a|^2 - r^2)(|q - b|^2 - r^2), a and b
 * the points of the centre circle nearest q and farthest from it (at
 * distance R from the axis, towards q and away from it); a point near the
 * surface is near the sphere of radius r round one of them, and its
 * nearest point there is that centre plus r along the way to q. The
 * normal is the gradient's direction, which points out of the tube: away
 * from a, and, on the lens a spindle torus (r > R) holds round its
 * centre, towards b. Exact, where Newton steps along the gradient would
 * take three divisions each and land only near it. q is left as the
 * point relative to the centre. Inline, so that the shading of a turned
 * torus (trace/shading.c) keeps the point and normal in registers. */
__attribute__((always_inline)) static inline void torus_nearest(const struct torus *s, vec3 p,
                                                                vec3 *point, vec3 *normal,
                                                                double q[3])
{
    double R = s->major, rm = s->minor;
    q[0] = (double)p.x - s->center.x, q[1] = (double)p.y - s->center.y;
    q[2] = (double)p.z - s->center.z;
    double rho = sqrt(q[0] * q[0] + q[2] * q[2]);
    double ax = R, az = 0.0; /* on the axis every circle point is as near */
    if (rho > 0.0) {
        double f = R / rho;
        ax = q[0] * f, az = q[2] * f;
    }
    double w[3] = {q[0] - ax, q[1], q[2] - az}, sgn = 1.0;
    double wa = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    double wb = (q[0] + ax) * (q[0] + ax) + q[1] * q[1] + (q[2] + az) * (q[2] + az);
    if (fabs(wb - rm * rm) < fabs(wa - rm * rm)) { /* on the lens */
        ax = -ax, az = -az, sgn = -1.0;
        w[0] = q[0] - ax, w[2] = q[2] - az;
        wa = wb;
    }
    double wl = sqrt(wa), inv = wl > 0.0 ? 1.0 / wl : 0.0, k = rm * inv;
    if (wl > 0.0)
        q[0] = ax + w[0] * k, q[1] = w[1] * k, q[2] = az + w[2] * k;
    *point = v3((float)(q[0] + s->center.x), (float)(q[1] + s->center.y),
                (float)(q[2] + s->center.z));
    inv *= sgn;
    *normal = wl > 0.0 ? v3((float)(w[0] * inv), (float)(w[1] * inv), (float)(w[2] * inv))
                       : v3(0.0f, 1.0f, 0.0f);
}

/* The point p, d = p - the plane's point, moved onto the plane along its
 * normal (shape.h), as plane_surface puts it there. */
__attribute__((always_inline)) static inline vec3 plane_onto(const struct plane *s, vec3 p, vec3 d)
{
    return v3_madd(p, s->normal, -v3_dot(d, s->normal));
}

/* Infinite plane: plane_intersect, which plane.c exports. */
__attribute__((always_inline)) static inline bool plane_hit(const struct plane *s, const ray *r,
                                                            shape_hit *hit)
{
    float t;
    if (!ray_plane(r, s->point, s->normal, &t))
        return false;
    hit->t = t;
    hit->part = 0;
    return true;
}

/* shape_intersect with the three tests above inlined (a plane is an
 * unbounded object, which every ray of the scene meets first). */
__attribute__((always_inline)) static inline bool shape_intersect_inline(const shape *s,
                                                                         const ray *r,
                                                                         shape_hit *hit)
{
    if (s->kind == SHAPE_SPHERE)
        return sphere_hit(&s->sphere, r, hit);
    if (s->kind == SHAPE_QUAD)
        return quad_hit(&s->quad, r, hit);
    if (s->kind == SHAPE_PLANE)
        return plane_hit(&s->plane, r, hit);
    if (s->kind == SHAPE_MESH)
        return mesh_intersect(s->mesh, r, hit);
    return shape_intersect(s, r, hit);
}

/* shape_occluded likewise: an analytic shape's occlusion test is its
 * intersection test. */
__attribute__((always_inline)) static inline bool shape_occluded_inline(const shape *s,
                                                                        const ray *r)
{
    shape_hit h;
    if (s->kind == SHAPE_SPHERE)
        return sphere_hit(&s->sphere, r, &h);
    if (s->kind == SHAPE_QUAD)
        return quad_hit(&s->quad, r, &h);
    if (s->kind == SHAPE_PLANE)
        return plane_hit(&s->plane, r, &h);
    if (s->kind == SHAPE_MESH)
        return mesh_occluded(s->mesh, r);
    return shape_occluded(s, r);
}

#endif

/* scene_cone: the objects a bundle of rays from one point may meet, found
 * once for the bundle (a tile's camera rays, or the shadow rays from their
 * hits to a light, seen from the light), which the bundle's packets are
 * then tested against alone instead of walking the tree (scene_packet.c:
 * scene_intersect8_among, scene_shadow8_among). */
#include <math.h>

#include "scene.h"

/* fmin and fmax of numbers (no NaN here), without libm's calls. */
static inline double lesser(double a, double b) { return a < b ? a : b; }
static inline double greater(double a, double b) { return a > b ? a : b; }

/* Whether a ray o + t d, 0 <= t <= tmax, with d anywhere in [dlo, dhi] (each
 * component on its own: a superset of the bundle), may meet box b grown
 * by a margin far beyond rounding (1e-4 of the coordinates' size: a
 * shape's hit found in floats lies within a few units in the last place
 * of its box). Each axis bounds the t at which some direction of the
 * interval is inside the box's slab; the bundle misses the box where the
 * three ranges of t do not meet. Where it may meet it, *reach (when not
 * NULL) grows to hold the grown box's part that the bundle's rays cross
 * in that range of t. In doubles, whose rounding the margin dwarfs. */
static bool cone_meets(aabb b, vec3 o, vec3 dlo, vec3 dhi, double tmax, aabb *reach)
{
    const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    const float oo[3] = {o.x, o.y, o.z}, p[3] = {dlo.x, dlo.y, dlo.z}, q[3] = {dhi.x, dhi.y, dhi.z};
    double tlo = 0.0, thi = tmax, l[3], h[3], pad[3];
    for (int a = 0; a < 3; a++) {
        pad[a] = 1e-4 * (fabs((double)lo[a]) + fabs((double)hi[a]) + fabs((double)oo[a])) + 1e-30;
        l[a] = (double)lo[a] - pad[a] - oo[a], h[a] = (double)hi[a] + pad[a] - oo[a];
        /* some t * d <= h, d >= p */
        if (p[a] > 0.0f) {
            if (h[a] < 0.0)
                return false;
            thi = lesser(thi, h[a] / p[a]);
        } else if (h[a] < 0.0) {
            if (p[a] == 0.0f)
                return false;
            tlo = greater(tlo, h[a] / p[a]);
        }
        /* some t * d >= l, d <= q */
        if (q[a] < 0.0f) {
            if (l[a] > 0.0)
                return false;
            thi = lesser(thi, l[a] / q[a]);
        } else if (l[a] > 0.0) {
            if (q[a] == 0.0f)
                return false;
            tlo = greater(tlo, l[a] / q[a]);
        }
    }
    if (!(tlo <= thi * (1.0 + 1e-6)))
        return false;
    if (!reach)
        return true;
    double part[2][3];
    for (int a = 0; a < 3; a++) {
        part[0][a] = l[a], part[1][a] = h[a];
        if (isfinite(thi)) { /* t in [tlo, thi] times d in [p, q] */
            double t0 = lesser(tlo, thi), c[4] = {t0 * p[a], t0 * q[a], thi * p[a], thi * q[a]};
            double cl = lesser(lesser(c[0], c[1]), lesser(c[2], c[3]));
            double ch = greater(greater(c[0], c[1]), greater(c[2], c[3]));
            part[0][a] = greater(part[0][a], cl - pad[a]);
            part[1][a] = lesser(part[1][a], ch + pad[a]);
        }
    }
    /* back in floats, whose rounding (half a unit in the last place) the
     * margin takes many times over */
    vec3 plo = v3((float)(part[0][0] + oo[0]), (float)(part[0][1] + oo[1]),
                  (float)(part[0][2] + oo[2]));
    vec3 phi = v3((float)(part[1][0] + oo[0]), (float)(part[1][1] + oo[1]),
                  (float)(part[1][2] + oo[2]));
    *reach = aabb_union(*reach, (aabb){plo, phi});
    return true;
}

/* Whether the hits on object ob, unbounded, of rays from o with
 * directions in [dlo, dhi] can be bounded, and if so their box into
 * *reach. Only an unturned plane can: the point a direction d meets it at
 * is o + d c / (n.d), c = n.(p - o), a projective function of d, so where
 * n.d keeps c's sign over the whole box of directions (the ray heads for
 * the plane, never along it), the points lie in the hull of those its
 * eight corners meet it at. The renderer works t = c / (n.d) out in floats
 * (ray_plane), within 4 units of 2^-24 times the two dot products'
 * condition numbers (sum |n_i x_i| / |n.x|) of the exact t, relatively;
 * near the horizon, or with the eye close to the plane for its distance
 * from the origin, those grow without bound, and there the plane is not
 * bounded. Elsewhere that error, and a hit's own rounding, stay far below
 * the margin, 1e-4 of the largest coordinate's size on every axis. In
 * doubles, whose rounding the margin dwarfs. */
static bool plane_reach(const object *ob, vec3 o, vec3 dlo, vec3 dhi, aabb *reach)
{
    if (ob->shape.kind != SHAPE_PLANE || ob->xform >= 0 || ob->moving)
        return false;
    const struct plane *pl = &ob->shape.plane;
    const double n[3] = {pl->normal.x, pl->normal.y, pl->normal.z};
    const double oo[3] = {o.x, o.y, o.z}, p[3] = {pl->point.x, pl->point.y, pl->point.z};
    const double lo[3] = {dlo.x, dlo.y, dlo.z}, hi[3] = {dhi.x, dhi.y, dhi.z};
    double c = 0.0, cmag = 0.0, worst = 0.0, qlo[3], qhi[3];
    for (int a = 0; a < 3; a++) {
        c += n[a] * (p[a] - oo[a]);
        cmag += fabs(n[a] * (p[a] - oo[a]));
        qlo[a] = INFINITY, qhi[a] = -INFINITY;
    }
    if (!(fabs(c) > 0.0))
        return false; /* the eye on the plane (or no number) */
    for (int corner = 0; corner < 8; corner++) {
        double d[3], nd = 0.0, ndmag = 0.0;
        for (int a = 0; a < 3; a++) {
            d[a] = corner >> a & 1 ? hi[a] : lo[a];
            nd += n[a] * d[a];
            ndmag += fabs(n[a] * d[a]);
        }
        if (!(nd * c > 0.0))
            return false; /* a direction along the plane, or away from it */
        worst = greater(worst, ndmag / fabs(nd));
        double t = c / nd;
        for (int a = 0; a < 3; a++) {
            qlo[a] = lesser(qlo[a], oo[a] + t * d[a]);
            qhi[a] = greater(qhi[a], oo[a] + t * d[a]);
        }
    }
    if (!(4.0 * 0x1p-24 * (cmag / fabs(c) + worst + 2.0) <= 1e-5))
        return false; /* grazing: the renderer's hits may stray too far */
    double size = 0.0;
    for (int a = 0; a < 3; a++)
        size = greater(size, fabs(qlo[a]) + fabs(qhi[a]) + fabs(oo[a]));
    double pad = 1e-4 * size + 1e-30;
    float flo[3], fhi[3];
    for (int a = 0; a < 3; a++) {
        flo[a] = (float)(qlo[a] - pad), fhi[a] = (float)(qhi[a] + pad);
        if (!isfinite(flo[a]) || !isfinite(fhi[a]))
            return false;
    }
    *reach = aabb_union(*reach, (aabb){v3(flo[0], flo[1], flo[2]), v3(fhi[0], fhi[1], fhi[2])});
    return true;
}

/* The objects of the tree that rays from o with directions in [dlo, dhi]
 * may meet up to tmax, and where (scene_cone_objects). */
static int cone_objects(const scene *s, vec3 o, vec3 dlo, vec3 dhi, double tmax, int32_t *list,
                        int cap, aabb *reach)
{
    if (reach)
        *reach = aabb_empty();
    if (!s->flat && !(s->bvh.width == 8 && s->bvh.nnodes > 0))
        return -1;
    if (s->bvh.nprims > cap)
        return -1;
    const float c[9] = {o.x, o.y, o.z, dlo.x, dlo.y, dlo.z, dhi.x, dhi.y, dhi.z};
    if (!floats_finite(c, 9))
        return -1;
    bool anywhere = false; /* whether some hit may be anywhere */
    for (int i = 0; i < s->nunbounded; i++)
        anywhere |= !(reach && plane_reach(&s->objects[s->unbounded[i]], o, dlo, dhi, reach));
    int n = 0;
    for (int i = 0; i < s->bvh.nprims; i++) {
        int32_t k = s->bvh.prims[i];
        bool unbounded = aabb_is_unbounded(s->bounds[k]);
        if (unbounded || cone_meets(s->bounds[k], o, dlo, dhi, tmax, reach)) {
            list[n++] = k;
            anywhere |= unbounded;
        }
    }
    if (reach && anywhere)
        *reach = (aabb){v3s(-INFINITY), v3s(INFINITY)};
    return n;
}

int scene_cone_objects(const scene *s, vec3 o, vec3 dlo, vec3 dhi, int32_t *list, int cap,
                       aabb *reach)
{
    return cone_objects(s, o, dlo, dhi, INFINITY, list, cap, reach);
}

/* A shadow ray from a point p on an object leaves from p moved by
 * ray_epsilon(p) along the normal (core/ray.h) and ends at the light: the
 * segment lies in the cone from the light through the points' box grown
 * by that distance, out to them (t <= 1). The directions' interval is
 * widened by far more than its rounding, as cone_meets's boxes are. */
int scene_shadow_cone_objects(const scene *s, aabb from, vec3 light_at, int32_t *list, int cap)
{
    if (aabb_is_empty(from))
        return 0; /* no hits, no shadow rays */
    if (aabb_is_unbounded(from))
        return -1;
    float e = 2.0f * RAY_EPS_REL * (1.0f + maxf(v3_max_abs(from.lo), v3_max_abs(from.hi)));
    vec3 lo = v3_sub(v3_sub(from.lo, v3s(e)), light_at);
    vec3 hi = v3_sub(v3_add(from.hi, v3s(e)), light_at);
    float slack = 1e-4f * (maxf(v3_max_abs(lo), v3_max_abs(hi)) + v3_max_abs(light_at));
    return cone_objects(s, light_at, v3_sub(lo, v3s(slack)), v3_add(hi, v3s(slack)), 1.0 + 1e-3,
                        list, cap, NULL);
}

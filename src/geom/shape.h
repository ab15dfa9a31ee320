/* shape: the closed set of geometric primitives. Each shape is described in
 * its own coordinates; an object (scene.h) may add a transform on top.
 *
 * Every shape answers these questions, dispatched by one switch each in
 * shape.c:
 *   intersect  nearest hit with t in (ray.tmin, ray.tmax); fills a shape_hit
 *   occluded   whether any hit exists in (ray.tmin, ray.tmax) (shadow rays)
 *   surface    point, unit outward normal and (u, v) at a hit found above;
 *              the point is put back onto the surface (see below)
 *   bounds     an axis-aligned box around the shape (empty for planes)
 *   crossings  for closed solids (the operands of csg): every place where
 *              the ray's line crosses the boundary after tmin, in order,
 *              each marked entering or leaving
 * intersect keeps only what it needs to finish the hit later (t and, for
 * some shapes, which part was hit), so the cost of normals and texture
 * coordinates is paid once per shaded point, not once per candidate.
 *
 * The hit point. o + t d rounds to within about |t d| * 2^-24 of the
 * surface, which from far away (t ~ 10^4 x the object's size) is more than
 * the offset new rays get (core/ray.h) and shows as acne. So surface()
 * returns the point moved back onto the surface along the normal
 * (Wächter and Binder, "A Fast and Robust Method for Avoiding
 * Self-Intersection", Ray Tracing Gems ch. 6, 2019, take the same view:
 * the offset only has to cover the error of a point computed from the
 * surface itself, which is a few ulps of its coordinates). */
#ifndef GLINT_GEOM_SHAPE_H
#define GLINT_GEOM_SHAPE_H

#include <stdbool.h>
#include "core/aabb.h"
#include "core/mat4.h"
#include "core/ray.h"

typedef enum shape_kind {
    SHAPE_SPHERE,
    SHAPE_PLANE,
    SHAPE_QUAD,
    SHAPE_BOX,
    SHAPE_CYLINDER,
    SHAPE_TRIANGLE,
    SHAPE_MESH,
    SHAPE_CONE,
    SHAPE_DISK,
    SHAPE_TORUS,
    SHAPE_POLYHEDRON,
    SHAPE_CSG,
    SHAPE_COUNT /* not a shape: the number of kinds, for tables indexed by kind */
} shape_kind;

/* Whether shape8_hit (shape8.h) tests the kind against eight rays at once. */
static inline bool shape_tests_eight(shape_kind k)
{
    return k == SHAPE_SPHERE || k == SHAPE_QUAD || k == SHAPE_PLANE || k == SHAPE_BOX ||
           k == SHAPE_CYLINDER;
}

struct mesh;
struct polyhedron;
struct csg;

struct sphere {
    vec3 center;
    float radius;
};

/* Infinite plane through point, with unit normal; (u, v) are coordinates in
 * world units along two tangents (tu, tv) chosen so that tu x tv = normal. */
struct plane {
    vec3 point, normal;
    vec3 tu, tv;
};

/* Parallelogram origin + u*edge_u + v*edge_v, u, v in [0, 1]; its normal is
 * edge_u x edge_v, normalised. w is precomputed as n / (n.n) for n the
 * unnormalised normal (see quad.c). */
struct quad {
    vec3 origin, edge_u, edge_v;
    vec3 normal, w;
};

struct box {
    vec3 lo, hi;
};

/* Cylinder around the +y axis: base centre, radius, height; caps optional. */
struct cylinder {
    vec3 base;
    float radius, height;
    bool capped;
};

/* Cone round the +y axis: radius at the base, top_radius (0: pointed) at
 * base + height; caps optional (a pointed cone has only the bottom one). */
struct cone {
    vec3 base;
    float radius, top_radius, height;
    bool capped;
};

/* Disk (annulus when inner > 0) in the plane through center with unit
 * normal; tu, tv as for the plane. */
struct disk {
    vec3 center, normal;
    vec3 tu, tv;
    float radius, inner;
};

/* Torus round the +y axis through center: the tube of radius minor round
 * the circle of radius major in the xz plane. */
struct torus {
    vec3 center;
    float major, minor;
};

/* Triangle p0 p1 p2, front face counter-clockwise; optional per-vertex (u, v). */
struct triangle {
    vec3 p0, p1, p2;
    float uv[3][2];
};

typedef struct shape {
    shape_kind kind;
    union {
        struct sphere sphere;
        struct plane plane;
        struct quad quad;
        struct box box;
        struct cylinder cylinder;
        struct triangle triangle;
        struct cone cone;
        struct disk disk;
        struct torus torus;
        const struct mesh *mesh;             /* these three are owned by the scene */
        const struct polyhedron *polyhedron;
        const struct csg *csg;
    };
} shape;

/* What intersect leaves for surface: t, and shape-specific detail. */
typedef struct shape_hit {
    float t;
    int part;     /* box face 0..5 (axis*2 + max side); cylinder and cone 0 side,
                     1 bottom, 2 top; polyhedron face; mesh triangle */
    float b1, b2; /* triangle barycentrics, quad (u, v) */
    int leaf;     /* csg: the solid hit (part, b1, b2 are its own) */
} shape_hit;

/* A hit at t with every other field cleared, one field at a time (a
 * clear of the whole struct became a rep stos, whose start costs more than
 * a small object's test, in blocks a profile-guided build rarely saw). */
static inline void shape_hit_at(shape_hit *h, float t)
{
    h->t = t, h->part = 0, h->b1 = 0.0f, h->b2 = 0.0f, h->leaf = 0;
}

/* A place where a line crosses the boundary of a closed solid. */
typedef struct crossing {
    shape_hit h;
    bool enter; /* into the solid as t grows */
} crossing;

typedef struct surface {
    vec3 p;   /* hit point in the shape's space */
    vec3 n;   /* unit outward shading normal in the shape's space */
    vec3 ng;  /* unit outward geometric normal: differs from n only on meshes
                 with vertex normals; new rays are offset along it */
    float u, v;
    vec3 color; /* multiplies the material's colour: a mesh's vertex colours, else 1 */
} surface;

/* Constructors validate nothing; loaders check ranges first. */
shape shape_sphere(vec3 center, float radius);
shape shape_plane(vec3 point, vec3 normal);
shape shape_quad(vec3 origin, vec3 edge_u, vec3 edge_v);
shape shape_box(vec3 lo, vec3 hi);
shape shape_cylinder(vec3 base, float radius, float height, bool capped);
shape shape_triangle(vec3 p0, vec3 p1, vec3 p2);
shape shape_mesh(const struct mesh *m);
/* top_radius 0 makes a pointed cone. */
shape shape_cone(vec3 base, float radius, float top_radius, float height, bool capped);
shape shape_disk(vec3 center, vec3 normal, float radius, float inner_radius);
shape shape_torus(vec3 center, float major_radius, float minor_radius);
shape shape_polyhedron(const struct polyhedron *p);
shape shape_csg(const struct csg *c);

/* What a triangle's corners allow: its normal (the cross product of two
 * edges) is worked out in double, so a triangle too large for single
 * precision is told from one with no area. */
typedef enum triangle_fit {
    TRIANGLE_OK,
    TRIANGLE_DEGENERATE, /* corners on one line (or not finite, or too small for floats) */
    TRIANGLE_TOO_LARGE,  /* its normal overflows single precision (edges of about 4e9 or more) */
} triangle_fit;
triangle_fit triangle_check(vec3 p0, vec3 p1, vec3 p2);

bool shape_intersect(const shape *s, const ray *r, shape_hit *hit);
bool shape_occluded(const shape *s, const ray *r);
/* Eight rays' hits on a shape, lane by lane: shape_hit's t, part, b1 and
 * b2 (b1, b2 0 but for a quad, part 0 but for a box or a cylinder). */
typedef struct shape_hits8 {
    float t[8], b1[8], b2[8];
    int part[8];
} shape_hits8;

/* The test of a shape of shape_tests_eight's kinds against the rays of
 * active (bit k: ray k of r), as shape_intersect finds each: returns the
 * rays hit, -1 for other shapes. With best NULL, up to each ray's tmax.
 * Otherwise up to best[k] inclusive (as far as the nearest hit so far),
 * with the hits in *out and those nearer than best[k] in *nearer (the
 * others are as near). On the eight-wide paths (geom/shape8.h), where the
 * CPU has them. */
int shape8_hit_avx2(const shape *sh, const ray8 *r, const float *best, int active,
                    shape_hits8 *out, int *nearer);
int shape8_hit_avx512(const shape *sh, const ray8 *r, const float *best, int active,
                      shape_hits8 *out, int *nearer);
/* A shadow ray's crossings of a sphere in the world's space, as the scene's
 * shadow walk finds them one ray at a time (scene_shadow_object): for the
 * rays of active, t[j][k] is ray k's crossing j within (tmin, tmax), and
 * took[j] the rays that have a crossing j. */
void sphere8_crossings_avx2(const struct sphere *s, const ray8 *r, int active, float t[2][8],
                            int took[2]);
void sphere8_crossings_avx512(const struct sphere *s, const ray8 *r, int active, float t[2][8],
                              int took[2]);
void shape_surface(const shape *s, const ray *r, const shape_hit *hit, surface *out);
/* shape_surface without (u, v), left 0, where they cost an inverse
 * trigonometric call (spheres, cylinders, cones, tori); the same as
 * shape_surface for every other shape. For materials that read no (u, v)
 * (material_uses_uv). */
void shape_surface_no_uv(const shape *s, const ray *r, const shape_hit *hit, surface *out);
aabb shape_bounds(const shape *s);
/* The box of the shape carried by the affine map m (object to world):
 * round a torus or a sphere the image's own extent, a little enlarged for
 * rounding (much tighter than the box round its turned box); round any
 * other shape the box of its box's mapped corners. */
aabb shape_bounds_mapped(const shape *s, const mat4 *m);
/* True when a ray leaving the surface can never meet the shape again. */
bool shape_is_convex(const shape *s);
/* Whether the shape bounds a solid, so that it can be an operand of csg:
 * spheres, boxes, capped cylinders and cones, tori, polyhedra, meshes (the
 * loader checks that they are closed) and csg. */
bool shape_is_solid(const shape *s);

/* The crossings of a solid along r after r->tmin (r->tmax is ignored), in
 * order, at most max of them. When there are more, *more is set and the
 * ones returned are the nearest. Whether the ray starts inside follows
 * from the first crossing (leaving: inside); with none, it is outside. */
int shape_crossings(const shape *s, const ray *r, crossing *out, int max, bool *more);
/* The material index a hit names when the object has none of its own: a
 * mesh triangle's, or that of the csg operand hit; -1 when there is none. */
int shape_hit_material(const shape *s, const shape_hit *hit);

/* Per-shape routines, called by the dispatchers above. */
bool sphere_intersect(const struct sphere *s, const ray *r, shape_hit *hit);
void sphere_surface(const struct sphere *s, vec3 p, surface *out);
bool plane_intersect(const struct plane *s, const ray *r, shape_hit *hit);
void plane_surface(const struct plane *s, vec3 p, surface *out);
bool quad_intersect(const struct quad *s, const ray *r, shape_hit *hit);
void quad_surface(const struct quad *s, vec3 p, const shape_hit *hit, surface *out);
bool box_intersect(const struct box *s, const ray *r, shape_hit *hit);
void box_surface(const struct box *s, vec3 p, const shape_hit *hit, surface *out);
bool cylinder_intersect(const struct cylinder *s, const ray *r, shape_hit *hit);
void cylinder_surface(const struct cylinder *s, vec3 p, const shape_hit *hit, surface *out);
void cylinder_surface_no_uv(const struct cylinder *s, vec3 p, const shape_hit *hit, surface *out);
bool triangle_intersect(const struct triangle *s, const ray *r, shape_hit *hit);
void triangle_surface(const struct triangle *s, vec3 p, const shape_hit *hit, surface *out);
bool cone_intersect(const struct cone *s, const ray *r, shape_hit *hit);
void cone_surface(const struct cone *s, vec3 p, const shape_hit *hit, surface *out);
void cone_surface_no_uv(const struct cone *s, vec3 p, const shape_hit *hit, surface *out);
bool disk_intersect(const struct disk *s, const ray *r, shape_hit *hit);
void disk_surface(const struct disk *s, vec3 p, surface *out);
bool torus_intersect(const struct torus *s, const ray *r, shape_hit *hit);
bool torus_occluded(const struct torus *s, const ray *r);
/* torus_intersect in two steps: the ray clipped to the torus's box and its
 * quartic written about the entry point, in s = (t - t0) |d| for s in
 * (0, hi) (torus.c for one ray, torus8_hit_<isa> for eight in vector
 * registers, to the bit the same), then the nearest root in (tmin, tmax),
 * into hit unless it is NULL. */
typedef struct torus_quartic {
    double c[5];
    double t0, len, hi;
    double t1; /* the clip's end, from which hi = (t1 - t0) len */
    double py, uy; /* the entry point's and the direction's y */
} torus_quartic;
bool torus_solve(const torus_quartic *q, const ray *r, shape_hit *hit);
/* torus_occluded's answer from the quartic (torus.c). */
bool torus_blocks(const torus_quartic *q, const ray *r);
/* Its first test, which needs no root: true when the ray is inside the
 * tube where it crosses the torus's plane (then torus_blocks is true). */
bool torus_blocks_at_once(const torus_quartic *q, const ray *r);
/* torus_intersect against the rays of active, each up to its own tmax:
 * returns the rays hit, with hit[k] as torus_intersect sets it (the rest
 * of it zero). On the eight-wide paths (geom/shape8.h). */
int torus8_hit_avx2(const struct torus *s, const ray8 *r, int active, shape_hit *hit);
int torus8_hit_avx512(const struct torus *s, const ray8 *r, int active, shape_hit *hit);
/* torus_occluded for the rays of active: those blocked. */
int torus8_occluded_avx2(const struct torus *s, const ray8 *r, int active);
int torus8_occluded_avx512(const struct torus *s, const ray8 *r, int active);
void torus_surface(const struct torus *s, vec3 p, surface *out);
/* The same without (u, v) (left 0), which cost two arc tangents. */
void torus_surface_no_uv(const struct torus *s, vec3 p, surface *out);

/* Crossings of the convex solids: the whole line's entry and exit, of
 * which those after r->tmin are kept (shape_span_crossings). Each
 * returns false when the line misses. */
bool sphere_span(const struct sphere *s, const ray *r, shape_hit *in, shape_hit *out);
bool box_span(const struct box *s, const ray *r, shape_hit *in, shape_hit *out);
bool cylinder_span(const struct cylinder *s, const ray *r, shape_hit *in, shape_hit *out);
bool cone_span(const struct cone *s, const ray *r, shape_hit *in, shape_hit *out);
int torus_crossings(const struct torus *s, const ray *r, crossing *out, int max);
/* A convex solid's crossings from its span (found: the line meets it):
 * the entry and the exit, those after tmin, at most max of them. */
static inline int shape_span_crossings(bool found, shape_hit in, shape_hit out, float tmin,
                                       crossing *x, int max)
{
    int n = 0;
    if (!found)
        return 0;
    if (in.t > tmin && n < max)
        x[n++] = (crossing){in, true};
    if (out.t > tmin && n < max)
        x[n++] = (crossing){out, false};
    return n;
}

#endif

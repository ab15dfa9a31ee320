/* shape: the closed set of geometric primitives. Each shape is described in
 * its own coordinates; an object (scene.h) may add a transform on top.
 *
 * Every shape answers four questions, dispatched by one switch each:
 *   intersect  nearest hit with t in (ray.tmin, ray.tmax); fills a shape_hit
 *   occluded   whether any hit exists in (ray.tmin, ray.tmax) (shadow rays)
 *   surface    point, unit outward normal and (u, v) at a hit found above
 *   bounds     an axis-aligned box around the shape (empty for planes)
 * intersect keeps only what it needs to finish the hit later (t and, for
 * some shapes, which part was hit), so the cost of normals and texture
 * coordinates is paid once per shaded point, not once per candidate. */
#ifndef GLINT_GEOM_SHAPE_H
#define GLINT_GEOM_SHAPE_H

#include <stdbool.h>
#include "core/aabb.h"
#include "core/ray.h"

typedef enum shape_kind {
    SHAPE_SPHERE,
    SHAPE_PLANE,
    SHAPE_QUAD,
    SHAPE_BOX,
    SHAPE_CYLINDER,
    SHAPE_TRIANGLE,
    SHAPE_MESH,
} shape_kind;

struct mesh;

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
        const struct mesh *mesh; /* owned by the scene */
    };
} shape;

/* What intersect leaves for surface: t, and shape-specific detail. */
typedef struct shape_hit {
    float t;
    int part;     /* box face 0..5 (axis*2 + max side), cylinder 0 side 1 bottom 2 top,
                     mesh triangle */
    float b1, b2; /* triangle barycentrics, quad (u, v) */
} shape_hit;

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

bool shape_intersect(const shape *s, const ray *r, shape_hit *hit);
bool shape_occluded(const shape *s, const ray *r);
void shape_surface(const shape *s, const ray *r, const shape_hit *hit, surface *out);
aabb shape_bounds(const shape *s);
/* True when a ray leaving the surface can never meet the shape again. */
bool shape_is_convex(const shape *s);

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
bool triangle_intersect(const struct triangle *s, const ray *r, shape_hit *hit);
void triangle_surface(const struct triangle *s, vec3 p, const shape_hit *hit, surface *out);

#endif

/* mat4: 4x4 matrices for affine transforms, and xform, a matrix kept
 * together with its inverse so that objects can map rays into their own
 * space and normals back out (normals use the inverse transpose).
 * Row-major; points are column vectors (p' = M p). */
#ifndef GLINT_CORE_MAT4_H
#define GLINT_CORE_MAT4_H

#include <stdbool.h>
#include "ray.h"
#include "vec3.h"

typedef struct mat4 {
    float m[4][4];
} mat4;

typedef struct xform {
    mat4 fwd; /* object -> world */
    mat4 inv; /* world -> object */
} xform;

mat4 mat4_identity(void);
mat4 mat4_mul(const mat4 *a, const mat4 *b); /* a * b: apply b first, then a */
mat4 mat4_transpose(const mat4 *a);
/* Returns false when the matrix is singular (or nearly so). */
bool mat4_invert(const mat4 *a, mat4 *out);

xform xform_identity(void);
xform xform_translate(vec3 t);
xform xform_scale(vec3 s);                 /* components must be non-zero */
xform xform_rotate(vec3 axis, float degrees); /* right-handed, axis any non-zero vector */
/* A shear: x' = x + xy*y + xz*z, y' = y + yx*x + yz*z, z' = z + zx*x + zy*y. */
xform xform_shear(float xy, float xz, float yx, float yz, float zx, float zy);
/* Builds an xform from a general matrix; false when it is not invertible. */
bool xform_from_matrix(const mat4 *m, xform *out);
/* The transform that applies a first, then b. */
xform xform_then(const xform *a, const xform *b);
/* The same for affine a and b (last rows 0, 0, 0, 1) with finite entries,
 * equal to xform_then to the bit at under half its cost. */
xform xform_then_affine(const xform *a, const xform *b);
bool xform_is_identity(const xform *x);
/* Whether every entry of the matrix and its inverse is finite. */
bool xform_is_finite(const xform *x);

static inline vec3 mat4_point(const mat4 *m, vec3 p)
{
    const float(*a)[4] = m->m;
    return v3(a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3],
              a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3],
              a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3]);
}

static inline vec3 mat4_vector(const mat4 *m, vec3 v)
{
    const float(*a)[4] = m->m;
    return v3(a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
              a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
              a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z);
}

/* The ray r in the space m maps into (m an inverse transform): its origin
 * as a point, its direction as a vector, the rest as it is. */
static inline ray mat4_ray(const mat4 *m, const ray *r)
{
    return (ray){.o = mat4_point(m, r->o), .d = mat4_vector(m, r->d), .tmin = r->tmin,
                 .tmax = r->tmax, .time = r->time};
}

/* Normal n given in object space, mapped to world space through the
 * transpose of the inverse; the result is not normalised. */
static inline vec3 xform_normal(const xform *x, vec3 n)
{
    const float(*a)[4] = x->inv.m;
    return v3(a[0][0] * n.x + a[1][0] * n.y + a[2][0] * n.z,
              a[0][1] * n.x + a[1][1] * n.y + a[2][1] * n.z,
              a[0][2] * n.x + a[1][2] * n.y + a[2][2] * n.z);
}

#endif

/* polyhedron: a closed solid bounded by flat polygons, given as vertices
 * and faces (lists of vertex indices, counter-clockwise seen from outside)
 * or made from one of the five Platonic solids. polyhedron_init checks the
 * input (each face planar and with area, the solid closed, manifold and
 * consistently wound) and says what is wrong in a poly_error the loader
 * turns into a message at the right place in the file.
 *
 * A convex polyhedron is intersected as the intersection of its faces'
 * half-spaces (Haines, "Fast Ray-Convex Polyhedron Intersection",
 * Graphics Gems II, 1991), which has no cracks between faces by
 * construction. Any other is cut into triangles (ear clipping, so faces
 * may be non-convex polygons) tested with the watertight test
 * (watertight.h), face by face after the bounding box: meant for solids
 * of up to a few hundred faces written by hand; bigger models are meshes.
 * Either way a hit's part is the face, whose plane gives the normal and
 * whose own frame gives (u, v). */
#ifndef GLINT_GEOM_POLYHEDRON_H
#define GLINT_GEOM_POLYHEDRON_H

#include <stdint.h>
#include "glint.h"
#include "core/aabb.h"
#include "core/ray.h"

struct surface;
struct shape_hit;
struct crossing;

typedef struct poly_face {
    vec3 n;          /* unit outward normal */
    float d;         /* the plane: n . p = d */
    vec3 uo, su, sv; /* (u, v) = ((p - uo) . su, (p - uo) . sv), the face in [0, 1]^2 */
    int first, count; /* its vertices: idx[first .. first + count) */
} poly_face;

typedef struct polyhedron {
    vec3 *verts;
    int nverts;
    int32_t *idx; /* every face's vertex indices, one face after another */
    int nidx;
    poly_face *faces;
    int nfaces;
    uint32_t (*tri)[3]; /* the faces cut into triangles; tri_face[i] is i's face */
    int32_t *tri_face;
    int ntris;
    bool convex;
    aabb bounds;
} polyhedron;

typedef enum poly_problem {
    POLY_OK,
    POLY_FEW_VERTICES, /* face has fewer than 3 vertices */
    POLY_INDEX,        /* face names a vertex that does not exist (at corner) */
    POLY_REPEAT,       /* face names a vertex twice (at corner) */
    POLY_FLAT,         /* face has no area */
    POLY_NOT_PLANAR,   /* vertex a, at corner, is dist from the face's plane */
    POLY_TANGLED,      /* face crosses itself (not a simple polygon) */
    POLY_OPEN,         /* edge a-b of face belongs to no other face */
    POLY_NOT_MANIFOLD, /* edge a-b belongs to more than two faces (face, other) */
    POLY_WINDING,      /* face and other run along edge a-b the same way */
    POLY_INSIDE_OUT,   /* the faces are clockwise seen from outside */
    POLY_NOMEM,
} poly_problem;

typedef struct poly_error {
    poly_problem what;
    int face, corner, other;
    int a, b;
    float dist, size; /* POLY_NOT_PLANAR: the distance, and the face's size */
} poly_error;

typedef enum poly_preset {
    POLY_TETRAHEDRON,
    POLY_CUBE,
    POLY_OCTAHEDRON,
    POLY_DODECAHEDRON,
    POLY_ICOSAHEDRON,
    POLY_PRESET_COUNT
} poly_preset;

/* Their names in the scene format, NULL-terminated. */
extern const char *const poly_preset_names[POLY_PRESET_COUNT + 1];

/* Takes verts (nverts, malloc'ed), idx (malloc'ed) and the faces' vertex
 * counts (sizes[nfaces], borrowed); on failure frees what it took and
 * fills why. A face may lean off its plane by up to 0.1% of its size. */
bool polyhedron_init(polyhedron *p, vec3 *verts, int nverts, int32_t *idx, const int *sizes,
                     int nfaces, poly_error *why);
/* The Platonic solid with the given centre and circumradius. */
bool polyhedron_preset(polyhedron *p, poly_preset kind, vec3 center, float radius,
                       poly_error *why);
void polyhedron_free(polyhedron *p);
/* What is wrong, in words (without where: the caller says that), into buf. */
void polyhedron_explain(const poly_error *e, char *buf, size_t size);

bool polyhedron_intersect(const polyhedron *p, const ray *r, struct shape_hit *hit);
void polyhedron_surface(const polyhedron *p, vec3 pt, const struct shape_hit *hit,
                        struct surface *out);
int polyhedron_crossings(const polyhedron *p, const ray *r, struct crossing *out, int max,
                         bool *more);

#endif

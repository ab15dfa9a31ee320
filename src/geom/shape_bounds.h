/* shape_bounds_inline: a shape's box in its own space, inline for the
 * loop of scene_build that bounds every object; shape_bounds (shape.c) is
 * the same for every other caller. Called, it returned the box through
 * memory in pieces that the caller read back across two stores, which
 * made each read wait (building 10^6 spheres on a Xeon, Emerald Rapids:
 * 1% of the time). */
#ifndef GLINT_GEOM_SHAPE_BOUNDS_H
#define GLINT_GEOM_SHAPE_BOUNDS_H

#include <math.h>
#include "geom/csg.h"
#include "geom/mesh.h"
#include "geom/polyhedron.h"
#include "geom/shape.h"

static inline aabb cylinder_box(vec3 base, float radius, float height)
{
    return (aabb){v3(base.x - radius, base.y, base.z - radius),
                  v3(base.x + radius, base.y + height, base.z + radius)};
}

/* A disk's box: along each axis the rim reaches radius * sqrt(1 - n_i^2). */
static inline aabb disk_box(const struct disk *d)
{
    vec3 n = d->normal;
    vec3 e = v3(d->radius * sqrtf(fmaxf(0.0f, 1.0f - n.x * n.x)),
                d->radius * sqrtf(fmaxf(0.0f, 1.0f - n.y * n.y)),
                d->radius * sqrtf(fmaxf(0.0f, 1.0f - n.z * n.z)));
    return (aabb){v3_sub(d->center, e), v3_add(d->center, e)};
}

__attribute__((always_inline)) static inline aabb shape_bounds_inline(const shape *s)
{
    switch (s->kind) {
    case SHAPE_SPHERE: {
        vec3 r = v3s(s->sphere.radius);
        return (aabb){v3_sub(s->sphere.center, r), v3_add(s->sphere.center, r)};
    }
    case SHAPE_PLANE:
        return aabb_empty();
    case SHAPE_QUAD: {
        const struct quad *q = &s->quad;
        aabb b = aabb_point(q->origin);
        b = aabb_grow(b, v3_add(q->origin, q->edge_u));
        b = aabb_grow(b, v3_add(q->origin, q->edge_v));
        return aabb_grow(b, v3_add(v3_add(q->origin, q->edge_u), q->edge_v));
    }
    case SHAPE_BOX:
        return (aabb){s->box.lo, s->box.hi};
    case SHAPE_CYLINDER:
        return cylinder_box(s->cylinder.base, s->cylinder.radius, s->cylinder.height);
    case SHAPE_TRIANGLE:
        return aabb_grow(aabb_grow(aabb_point(s->triangle.p0), s->triangle.p1), s->triangle.p2);
    case SHAPE_MESH:
        return s->mesh->bounds;
    case SHAPE_CONE:
        return cylinder_box(s->cone.base, fmaxf(s->cone.radius, s->cone.top_radius),
                            s->cone.height);
    case SHAPE_DISK:
        return disk_box(&s->disk);
    case SHAPE_TORUS: {
        float a = s->torus.major + s->torus.minor;
        vec3 e = v3(a, s->torus.minor, a);
        return (aabb){v3_sub(s->torus.center, e), v3_add(s->torus.center, e)};
    }
    case SHAPE_POLYHEDRON:
        return s->polyhedron->bounds;
    case SHAPE_CSG:
        return s->csg->bounds;
    case SHAPE_COUNT:
        break;
    }
    return aabb_empty();
}

#endif

/* scene_surface inline, for the shading of every hit (trace/shading.c);
 * scene.c's scene_surface is the same, out of line, for everyone else. */
#ifndef GLINT_SCENE_SCENE_SURFACE_H
#define GLINT_SCENE_SCENE_SURFACE_H

#include "scene/scene_trace.h"

__attribute__((always_inline)) static inline void scene_surface_inline(const scene *s,
                                                                       const ray *r,
                                                                       const scene_hit *hit,
                                                                       surface *out)
{
    const object *o = &s->objects[hit->object];
    bool uv = material_uses_uv(scene_hit_material(s, hit));
    xform moved;
    const xform *x = NULL; /* the object's, where it is turned or moving */
    if (o->xform >= 0) {
        x = &s->xforms[o->xform];
        if (o->moving) {
            moved = scene_object_xform_at(s, o, r->time);
            x = &moved;
        }
    }
    ray lr; /* the ray in the object's space, as scene_object_ray carries it */
    const ray *q = r;
    if (x) {
        lr = mat4_ray(&x->inv, r);
        q = &lr;
    }
    out->color = v3s(1.0f);
    (uv ? shape_surface : shape_surface_no_uv)(&o->shape, q, &hit->h, out);
    if (o->material >= 0) /* a material given in the scene replaces the file's colours */
        out->color = v3s(1.0f);
    if (!x)
        return;
    out->p = mat4_point(&x->fwd, out->p); /* on the surface, as the shape left it */
    out->n = v3_norm(xform_normal(x, out->n));
    /* Only meshes (vertex normals) and csg (a mesh leaf) have two normals. */
    bool one_normal = o->shape.kind != SHAPE_MESH && o->shape.kind != SHAPE_CSG;
    out->ng = one_normal ? out->n : v3_norm(xform_normal(x, out->ng));
}

#endif

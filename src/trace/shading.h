/* shading: what a hit looks like before it is lit. The surface, its
 * material, the base colour (the texture's), the shading normal (bumped),
 * both normals turned to face the incoming ray, and what the ray crossed to
 * get there (fog in the open, absorption inside a transmitting object). */
#ifndef GLINT_TRACE_SHADING_H
#define GLINT_TRACE_SHADING_H

#include <stdbool.h>
#include "core/ray.h"
#include "geom/csg.h"
#include "geom/shape_inline.h"
#include "scene/scene.h"
#include "trace/whitted.h"

typedef struct shade_point {
    vec3 p;      /* world point */
    vec3 n, ng;  /* unit shading and geometric normals, facing the ray */
    vec3 d;      /* unit direction of the incoming ray */
    bool inside; /* the ray hit the surface from behind */
    vec3 base;   /* colour times texture */
    const material *m;
} shade_point;

/* The shading points of a packet's eight lanes, field by field (the
 * packet's tracing in whitted.c and lighting.c; the eight-wide kernels
 * load each field of all lanes at once). A lane's fields are set only
 * when its ray hit something. */
typedef struct shade8 {
    float p[3][8], n[3][8], ng[3][8], d[3][8], base[3][8];
    int inside; /* bit k: lane k's ray hit the surface from behind */
    const material *m[8];
    const material *same; /* every lane's material, when the lanes share one; else NULL */
    bool lanewise; /* some lane was put one by one (shade8_put): the eight-wide kernels
                      then load each field lane by lane (simd8.h: simd8_field), as a
                      whole load would wait for those stores to reach the cache */
} shade8;

/* Lane k of a packet's shading points, and a point put into lane k. */
static inline shade_point shade8_get(const shade8 *s, int k)
{
    return (shade_point){v3(s->p[0][k], s->p[1][k], s->p[2][k]),
                         v3(s->n[0][k], s->n[1][k], s->n[2][k]),
                         v3(s->ng[0][k], s->ng[1][k], s->ng[2][k]),
                         v3(s->d[0][k], s->d[1][k], s->d[2][k]),
                         (s->inside >> k & 1) != 0,
                         v3(s->base[0][k], s->base[1][k], s->base[2][k]),
                         s->m[k]};
}

static inline void shade8_put(shade8 *s, int k, const shade_point *sp)
{
    const vec3 *f[5] = {&sp->p, &sp->n, &sp->ng, &sp->d, &sp->base};
    float(*to[5])[8] = {s->p, s->n, s->ng, s->d, s->base};
    for (int i = 0; i < 5; i++) {
        to[i][0][k] = f[i]->x;
        to[i][1][k] = f[i]->y;
        to[i][2][k] = f[i]->z;
    }
    s->inside = (s->inside & ~(1 << k)) | (int)sp->inside << k;
    s->m[k] = sp->m;
}

/* A colour for each of a packet's lanes, component by component. */
typedef struct color8 {
    float c[3][8];
} color8;

static inline vec3 color8_get(const color8 *c, int k)
{
    return v3(c->c[0][k], c->c[1][k], c->c[2][k]);
}

static inline void color8_put(color8 *c, int k, vec3 v)
{
    c->c[0][k] = v.x, c->c[1][k] = v.y, c->c[2][k] = v.z;
}

/* The shading point of material m at point p with shading normal n and
 * geometric normal ng, for a ray of unit direction d: both normals turned
 * to face the ray; the geometric one decides the side, the shading one
 * the lighting. */
__attribute__((always_inline)) static inline void facing(shade_point *out, const material *m,
                                                         vec3 d, vec3 p, vec3 n, vec3 ng,
                                                         vec3 base)
{
    out->m = m;
    out->p = p;
    out->d = d;
    out->base = base;
    out->inside = v3_dot(d, ng) > 0.0f;
    out->ng = out->inside ? v3_neg(ng) : ng;
    out->n = out->inside ? v3_neg(n) : n;
    if (v3_dot(out->n, out->ng) < 0.0f)
        out->n = out->ng;
}

/* shade_prepare past its commonest case, for material m (shading.c). The
 * ray's unit direction is worked out there again rather than passed: a
 * vec3 argument was stored in two widths and read back in a third, which
 * stalled the read. */
void shade_prepare_surface(trace_ctx *ctx, const ray *r, const scene_hit *hit, const material *m,
                           shade_point *out);

/* Whether a hit on object o of material m is shade_prepare's commonest
 * case: an untextured, unturned sphere. */
static inline bool shade_plain_sphere(const object *o, const material *m)
{
    return o->xform < 0 && o->shape.kind == SHAPE_SPHERE && !material_uses_uv(m);
}

/* Whether it is one of the plain surfaces shade_prepare_surface takes
 * first (shading.c: plain_surface): an untextured, unturned plane, or an
 * untextured torus turned by a fixed transform. */
static inline bool shade_plain_plane(const object *o, const material *m)
{
    return o->xform < 0 && o->shape.kind == SHAPE_PLANE && !material_uses_uv(m);
}

static inline bool shade_plain_torus(const object *o, const material *m)
{
    return o->xform >= 0 && !o->moving && o->shape.kind == SHAPE_TORUS && !material_uses_uv(m);
}

/* Whether texture t is one the packet kernels look up themselves
 * (trace/prepare8_texture.h): a chequer or an image on (u, v), which no
 * transform moves. */
static inline bool shade_flat_texture(const texture *t)
{
    if (t->space != SPACE_UV || t->has_xform)
        return false;
    return t->kind == TEXTURE_CHECKER ||
           (t->kind == TEXTURE_IMAGE && t->image.mapping == MAPPING_UV);
}

/* The shapes the packet kernels also prepare, though shade_prepare takes
 * them the general way (shade_prepare_surface): an unturned quad,
 * untextured or with a flat texture (shade_flat_texture) and unbumped; a
 * box or a cylinder, untextured, unturned or turned by a fixed
 * transform. */
static inline bool shade_plain_quad(const scene *s, const object *o, const material *m)
{
    return o->xform < 0 && o->shape.kind == SHAPE_QUAD && m->bump < 0 &&
           (m->texture < 0 || shade_flat_texture(&s->textures[m->texture]));
}

static inline bool shade_plain_solid(const object *o, const material *m)
{
    return (o->shape.kind == SHAPE_BOX || o->shape.kind == SHAPE_CYLINDER) &&
           !(o->xform >= 0 && o->moving) && !material_uses_uv(m);
}

/* A hit on a csg object, unturned or turned by a fixed transform, whose
 * leaf is an untextured sphere, box or cylinder in the csg's own space
 * (csg_surface, without a leaf transform). */
static inline bool shade_plain_leaf(const object *o, const scene_hit *hit, const material *m)
{
    if (o->shape.kind != SHAPE_CSG || (o->xform >= 0 && o->moving) || material_uses_uv(m))
        return false;
    const csg_leaf *l = &o->shape.csg->leaves[hit->h.leaf];
    shape_kind k = l->shape.kind;
    return !l->moved && (k == SHAPE_SPHERE || k == SHAPE_BOX || k == SHAPE_CYLINDER);
}

/* The shading point of a hit. Inline for its commonest case, an
 * untextured, unturned sphere, whose surface then stays in registers
 * (written to memory and read back in other widths, it stalled the
 * loads); any other in shade_prepare_surface. */
__attribute__((always_inline)) static inline void shade_prepare(trace_ctx *ctx, const ray *r,
                                                                const scene_hit *hit,
                                                                shade_point *out)
{
    const scene *s = ctx->scene;
    const material *m = scene_hit_material(s, hit);
    const object *o = &s->objects[hit->object];
    if (shade_plain_sphere(o, m)) {
        surface plain;
        sphere_surface_plain(&o->shape.sphere, ray_at(r, hit->h.t), &plain);
        facing(out, m, v3_norm(r->d), plain.p, plain.n, plain.ng, v3_mul(m->color, v3s(1.0f)));
        return;
    }
    shade_prepare_surface(ctx, r, hit, m, out);
}

/* What is seen through the segment of r from its origin to t (INFINITY
 * for a ray that hit nothing, sp NULL) of colour c at its end: fogged in
 * the open, absorbed when the segment ran inside a transmitting object. */
vec3 shade_segment_crossed(const scene *s, const ray *r, float t, const shade_point *sp,
                           vec3 c);

/* Whether a segment inside material m changes the light it carries:
 * inside a transmitting material that absorbs (shade_segment_crossed
 * leaves the colour of any other as it is, and fogs none). */
static inline bool shade_absorbs_inside(const material *m)
{
    return m->transmit > 0.0f && material_absorbs(m);
}

/* shade_segment_crossed, or c at once where the segment crosses neither
 * fog nor the inside of a transmitting object that absorbs. */
static inline vec3 shade_segment(const scene *s, const ray *r, float t, const shade_point *sp,
                                 vec3 c)
{
    if (s->fog.kind == FOG_NONE && !(sp && sp->inside && shade_absorbs_inside(sp->m)))
        return c;
    return shade_segment_crossed(s, r, t, sp, c);
}

#endif

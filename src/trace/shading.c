#include "shading.h"

#include <math.h>

#include "scene/scene_surface.h"
#include "shade/texture.h"

/* The point where a texture of this space is looked up, into *tp. Set
 * in place, field by field: a struct returned and copied was read back
 * in 16-byte loads just after its 4-byte stores, which stalled them. */
static void texture_at(const scene *s, const scene_hit *hit, const surface *sf,
                       texture_space space, texture_point *tp)
{
    tp->p = sf->p;
    tp->n = sf->n;
    tp->u = sf->u;
    tp->v = sf->v;
    if (space == SPACE_OBJECT)
        scene_object_point(s, hit->object, sf->p, sf->n, &tp->p, &tp->n);
}

/* The outward normal n tilted by the bump pattern: the surface is raised
 * by strength * value along n, so the normal leans against the value's
 * gradient across the surface. */
static vec3 bump(const trace_ctx *ctx, const scene_hit *hit, const surface *sf,
                 const material *m)
{
    const scene *s = ctx->scene;
    const texture *t = &s->textures[m->bump];
    texture_point tp;
    texture_at(s, hit, sf, t->space, &tp);
    vec3 g = texture_gradient(t, s->images, ctx->decode, &tp);
    const object *o = &s->objects[hit->object];
    if (t->space == SPACE_OBJECT && o->xform >= 0)
        g = xform_normal(&s->xforms[o->xform], g); /* d/dp of f(inverse(p)) */
    vec3 tangential = v3_madd(g, sf->n, -v3_dot(g, sf->n));
    vec3 n = v3_norm(v3_madd(sf->n, tangential, -m->bump_strength));
    return v3_is_finite(n) ? n : sf->n;
}

/* shade_prepare_surface below for an untextured, unbumped hit on an
 * unturned plane or on a torus turned by a fixed transform (bench/tori.awk's
 * ground and ten thousand tori): the same floats, with the point and
 * normal kept in registers instead of passing through a surface in memory,
 * whose parts were read back in other widths than they were written in,
 * which stalled the reads. */
static bool plain_surface(const scene *s, const ray *r, const scene_hit *hit, const material *m,
                          vec3 d, shade_point *out)
{
    const object *o = &s->objects[hit->object];
    vec3 base = v3_mul(m->color, v3s(1.0f));
    if (shade_plain_plane(o, m)) {
        const struct plane *pl = &o->shape.plane;
        vec3 p = ray_at(r, hit->h.t);
        facing(out, m, d, plane_onto(pl, p, v3_sub(p, pl->point)), pl->normal, pl->normal, base);
        return true;
    }
    if (!shade_plain_torus(o, m))
        return false;
    const xform *x = &s->xforms[o->xform];
    ray lr = mat4_ray(&x->inv, r);
    vec3 p, n;
    double q[3];
    torus_nearest(&o->shape.torus, ray_at(&lr, hit->h.t), &p, &n, q);
    n = v3_norm(xform_normal(x, n));
    facing(out, m, d, mat4_point(&x->fwd, p), n, n, base);
    return true;
}

void shade_prepare_surface(trace_ctx *ctx, const ray *r, const scene_hit *hit, const material *m,
                           shade_point *out)
{
    const scene *s = ctx->scene;
    vec3 d = v3_norm(r->d);
    if (plain_surface(s, r, hit, m, d, out))
        return;
    surface sf;
    scene_surface_inline(s, r, hit, &sf);
    vec3 base = v3_mul(m->color, sf.color); /* a mesh's vertex colours, else 1 */
    if (m->texture >= 0) {
        const texture *t = &s->textures[m->texture];
        texture_point tp;
        texture_at(s, hit, &sf, t->space, &tp);
        base = v3_mul(base, texture_eval(t, s->images, ctx->decode, &tp));
    }
    vec3 n = m->bump >= 0 ? bump(ctx, hit, &sf, m) : sf.n;
    facing(out, m, d, sf.p, n, sf.ng, base);
}

vec3 shade_segment_crossed(const scene *s, const ray *r, float t, const shade_point *sp,
                           vec3 c)
{
    if (sp && sp->inside && sp->m->transmit > 0.0f) {
        if (!material_absorbs(sp->m))
            return c;
        float len = t * v3_len(r->d);
        vec3 a = sp->m->absorption;
        return v3_mul(c, v3(expf(-a.x * len), expf(-a.y * len), expf(-a.z * len)));
    }
    if (s->fog.kind == FOG_NONE)
        return c;
    float dl = v3_len(r->d);
    return fog_apply(&s->fog, r->o, v3_scale(r->d, 1.0f / dl), t * dl, c);
}

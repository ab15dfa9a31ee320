#include "whitted.h"

#include <math.h>

#include "scene/scene.h"
#include "shade/optics.h"

/* More crossings than this on one shadow ray count as full shadow. */
#define SHADOW_MAX_CROSSINGS 64

vec3 whitted_shadow(trace_ctx *ctx, vec3 p, vec3 ng, vec3 to)
{
    const scene *s = ctx->scene;
    vec3 o = ray_offset(p, ng, v3_sub(to, p));
    ray sr = ray_make(o, v3_sub(to, o), 1.0f);
    ctx->shadow_rays++;
    if (scene_occluded_opaque(s, &sr))
        return v3s(0.0f);
    if (!s->any_transmit)
        return v3s(1.0f);
    /* Only transmitting surfaces remain between p and the light: walk
     * through them in order, filtering at each crossing. */
    vec3 filter = v3s(1.0f);
    scene_hit hit;
    float dlen = v3_len(sr.d);
    for (int i = 0; i < SHADOW_MAX_CROSSINGS; i++) {
        if (!scene_intersect(s, &sr, &hit))
            return filter;
        const material *m = scene_hit_material(s, &hit);
        filter = v3_scale(v3_mul(filter, m->tint), m->transmit);
        if (v3_max_comp(filter) <= 0.0f)
            return filter;
        sr.tmin = hit.h.t + ray_epsilon(ray_at(&sr, hit.h.t)) / dlen;
    }
    return v3s(0.0f);
}

/* Adaptive depth control: whether a secondary ray with factor k, out of
 * total for both of a surface's rays, is traced from a ray carrying share
 * of the pixel; if so, ctx->weight becomes its own share. Shares are scaled
 * so that the two never add up to more than the parent's, even for
 * materials that gain energy (reflect + transmit above 1, a tint above 1):
 * every level of the tree then holds at most 1 / bailout traced rays, and a
 * sample costs at most max_depth / bailout secondary rays. */
static bool adc_keep(trace_ctx *ctx, float share, float k, float total)
{
    float w = share * k / fmaxf(1.0f, total);
    if (!(k > 0.0f) || w < ctx->bailout)
        return false;
    ctx->weight = w;
    return true;
}

vec3 whitted_trace(trace_ctx *ctx, const ray *r, int depth)
{
    const scene *s = ctx->scene;
    scene_hit hit;
    if (!scene_intersect(s, r, &hit))
        return s->background;

    surface sf;
    scene_surface(s, r, &hit, &sf);
    const material *m = scene_hit_material(s, &hit);
    vec3 d = v3_norm(r->d);
    /* Both normals turned to face the incoming ray; the geometric one
     * decides the side, the shading one the lighting. */
    bool inside = v3_dot(d, sf.ng) > 0.0f;
    vec3 ng = inside ? v3_neg(sf.ng) : sf.ng;
    vec3 n = inside ? v3_neg(sf.n) : sf.n;
    if (v3_dot(n, ng) < 0.0f)
        n = ng;

    vec3 base = v3_mul(m->color, sf.color);
    if (m->texture >= 0)
        base = v3_mul(base, texture_eval(&s->textures[m->texture], s->images, ctx->decode,
                                         sf.u, sf.v));

    /* Split between reflection and transmission (see material.h). */
    float kr = m->reflect, kt = m->transmit;
    vec3 tdir = d;
    if (kt > 0.0f && m->ior != 1.0f) {
        float n1 = inside ? m->ior : 1.0f, n2 = inside ? 1.0f : m->ior;
        if (!optics_refract(d, n, n1 / n2, &tdir)) {
            kr += kt; /* total internal reflection */
            kt = 0.0f;
        } else {
            float cosine = n1 > n2 ? -v3_dot(tdir, n) : -v3_dot(d, n);
            float f = optics_schlick(cosine, n1, n2);
            kr += kt * f;
            kt *= 1.0f - f;
        }
    }

    float w = fmaxf(0.0f, 1.0f - m->transmit);
    vec3 diffuse_light = v3_scale(s->ambient, m->ambient);
    vec3 specular_light = v3s(0.0f);
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        vec3 ld = v3_sub(l->position, sf.p);
        vec3 lu = v3_norm(ld);
        float ndl = v3_dot(n, lu);
        if (ndl <= 0.0f)
            continue;
        vec3 vis = whitted_shadow(ctx, sf.p, ng, l->position);
        if (v3_is_zero(vis))
            continue;
        vec3 lc = v3_mul(l->color, vis);
        diffuse_light = v3_madd(diffuse_light, lc, m->diffuse * ndl);
        if (m->specular > 0.0f) {
            float rv = -v3_dot(v3_reflect(v3_neg(lu), n), d);
            if (rv > 0.0f)
                specular_light = v3_madd(specular_light, lc, m->specular * powf(rv, m->shininess));
        }
    }
    vec3 c = v3_add(v3_scale(v3_mul(diffuse_light, base), w), specular_light);

    if (depth < ctx->max_depth) {
        float share = ctx->weight, gt = kt * v3_max_comp(m->tint);
        if (adc_keep(ctx, share, kr, kr + gt)) {
            vec3 rd = v3_reflect(d, n);
            ray rr = ray_make(ray_offset(sf.p, ng, rd), rd, INFINITY);
            ctx->secondary_rays++;
            c = v3_madd(c, whitted_trace(ctx, &rr, depth + 1), kr);
        }
        if (kt > 0.0f && adc_keep(ctx, share, gt, kr + gt)) {
            ray tr = ray_make(ray_offset(sf.p, ng, tdir), tdir, INFINITY);
            ctx->secondary_rays++;
            c = v3_add(c, v3_scale(v3_mul(whitted_trace(ctx, &tr, depth + 1), m->tint), kt));
        }
        ctx->weight = share;
    }
    return c;
}

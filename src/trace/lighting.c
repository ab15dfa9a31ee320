#include "lighting.h"

#include <math.h>

#include "core/hash.h"

/* Beer-Lambert over the part of the shadow ray inside the object whose
 * surface it crosses at hit, if it leaves the object there: the segment
 * since the previous crossing at t_prev. */
static vec3 shadow_absorb(const scene *s, const ray *sr, const scene_hit *hit,
                          const material *m, float t_prev, float dlen)
{
    surface sf;
    scene_surface(s, sr, hit, &sf);
    if (v3_dot(sr->d, sf.ng) <= 0.0f)
        return v3s(1.0f); /* entering */
    float len = (hit->h.t - t_prev) * dlen;
    vec3 a = m->absorption;
    return v3(expf(-a.x * len), expf(-a.y * len), expf(-a.z * len));
}

vec3 lighting_shadow(trace_ctx *ctx, vec3 p, vec3 ng, const light_ray *lr)
{
    const scene *s = ctx->scene;
    vec3 o = ray_offset(p, ng, lr->dir);
    ray sr = isinf(lr->dist) ? ray_make(o, lr->dir, INFINITY)
                             : ray_make(o, v3_sub(lr->pos, o), 1.0f);
    sr.time = ctx->time;
    ctx->shadow_rays++;
    if (!s->any_transmit)
        return v3s(scene_occluded_opaque(s, &sr) ? 0.0f : 1.0f);
    /* One walk finds an opaque blocker or every transmitting surface in the
     * way; those filter the light in order along the ray. */
    scene_crossings cross;
    if (scene_shadow(s, &sr, &cross))
        return v3s(0.0f);
    vec3 filter = v3s(1.0f);
    float dlen = v3_len(sr.d), t_prev = 0.0f;
    for (int i = 0; i < cross.n; i++) {
        const scene_hit *hit = &cross.hit[i];
        const material *m = scene_hit_material(s, hit);
        filter = v3_scale(v3_mul(filter, m->tint), m->transmit);
        if (material_absorbs(m))
            filter = v3_mul(filter, shadow_absorb(s, &sr, hit, m, t_prev, dlen));
        if (v3_max_comp(filter) <= 0.0f)
            return filter;
        t_prev = hit->h.t;
    }
    return filter;
}

/* One light sample's diffuse and specular share, shadowed. */
static inline void add_sample(trace_ctx *ctx, const shade_point *sp, const light_ray *lr,
                       vec3 *diffuse, vec3 *specular)
{
    const material *m = sp->m;
    if (v3_is_zero(lr->color))
        return;
    float ndl = v3_dot(sp->n, lr->dir);
    if (ndl <= 0.0f)
        return;
    vec3 vis = lighting_shadow(ctx, sp->p, sp->ng, lr);
    if (v3_is_zero(vis))
        return;
    vec3 lc = v3_mul(lr->color, vis);
    *diffuse = v3_madd(*diffuse, lc, m->diffuse * ndl);
    if (m->specular > 0.0f) {
        float rv = -v3_dot(v3_reflect(v3_neg(lr->dir), sp->n), sp->d);
        if (rv > 0.0f)
            *specular = v3_madd(*specular, lc, m->specular * powf(rv, m->shininess));
    }
}

/* Every sample of light i (lighting.h: the jitter). */
static inline void add_light(trace_ctx *ctx, const shade_point *sp, int i, uint32_t event,
                             vec3 *diffuse, vec3 *specular)
{
    const light *l = &ctx->scene->lights[i];
    int ns = light_sample_count(l);
    if (ns == 1) {
        light_ray lr = light_sample(l, sp->p, 0, 0.5f, 0.5f);
        add_sample(ctx, sp, &lr, diffuse, specular);
        return;
    }
    uint32_t h = hash_add(hash_add(trace_sample_hash(ctx), event), (uint32_t)i);
    for (int k = 0; k < ns; k++) {
        uint32_t hk = hash_add(h, (uint32_t)k);
        light_ray lr = light_sample(l, sp->p, k, hash_unit(hk), hash_unit(hash_u32(hk)));
        add_sample(ctx, sp, &lr, diffuse, specular);
    }
}

vec3 lighting_local(trace_ctx *ctx, const shade_point *sp)
{
    const scene *s = ctx->scene;
    const material *m = sp->m;
    uint32_t event = ctx->events++;
    vec3 diffuse = v3_scale(s->ambient, m->ambient);
    vec3 specular = v3s(0.0f);
    for (int i = 0; i < s->nlights; i++)
        add_light(ctx, sp, i, event, &diffuse, &specular);
    float w = maxf(1.0f - m->transmit, 0.0f);
    vec3 c = v3_add(v3_scale(v3_mul(diffuse, sp->base), w), specular);
    return v3_add(c, m->emission);
}

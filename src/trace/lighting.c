#include "lighting.h"

#include <math.h>

#include "accel/isa.h"
#include "core/hash.h"
#include "trace/light8_api.h"

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

/* The shadow ray from p, whose geometric normal is ng, towards light
 * sample lr, at the time of the sample being traced. */
__attribute__((always_inline)) static inline ray shadow_ray(const trace_ctx *ctx, vec3 p, vec3 ng,
                                                            const light_ray *lr)
{
    vec3 o = ray_offset(p, ng, lr->dir);
    ray sr = isinf(lr->dist) ? ray_make(o, lr->dir, INFINITY)
                             : ray_make(o, v3_sub(lr->pos, o), 1.0f);
    sr.time = ctx->time;
    return sr;
}

/* The light a crossing of material m lets through of filter. */
static inline vec3 crossing_step(vec3 filter, const material *m)
{
    return v3_scale(v3_mul(filter, m->tint), m->transmit);
}

/* What reaches the end of shadow ray sr through its crossings of
 * transmitting objects, which filter the light in order along the ray;
 * sr may be NULL where no material at all absorbs (scene.any_absorb: the
 * crossings of a transmitting csg or mesh include its opaque parts). */
static vec3 crossings_filter(const scene *s, const ray *sr, const scene_crossings *cross)
{
    vec3 filter = v3s(1.0f);
    float dlen = -1.0f, t_prev = 0.0f; /* the ray's length, once an absorber needs it */
    for (int i = 0; i < cross->n; i++) {
        const scene_hit *hit = &cross->hit[i];
        const material *m = scene_hit_material(s, hit);
        filter = crossing_step(filter, m);
        if (material_absorbs(m)) {
            /* worked out only here: its square root, on the ray just put
             * together, held up every crossing ray that needs none */
            dlen = dlen < 0.0f ? v3_len(sr->d) : dlen;
            filter = v3_mul(filter, shadow_absorb(s, sr, hit, m, t_prev, dlen));
        }
        if (v3_max_comp(filter) <= 0.0f)
            return filter;
        t_prev = hit->h.t;
    }
    return filter;
}

/* crossings_filter for a ray that crosses object obj only, count times
 * (0 to 2), whose material does not absorb. */
static vec3 one_object_filter(const scene *s, int32_t obj, int count)
{
    vec3 filter = v3s(1.0f);
    if (!count)
        return filter;
    const material *m = &s->materials[s->objects[obj].material];
    for (int i = 0; i < count; i++) {
        filter = crossing_step(filter, m);
        if (v3_max_comp(filter) <= 0.0f)
            return filter;
    }
    return filter;
}

/* What reaches the end of shadow ray sr (lighting_shadow). */
static vec3 shadow_filter(const scene *s, const ray *sr)
{
    if (!s->any_transmit)
        return v3s(scene_occluded_opaque(s, sr) ? 0.0f : 1.0f);
    /* One walk finds an opaque blocker or every transmitting surface in the
     * way. */
    scene_crossings cross;
    return scene_shadow(s, sr, &cross) ? v3s(0.0f) : crossings_filter(s, sr, &cross);
}

vec3 lighting_shadow(trace_ctx *ctx, vec3 p, vec3 ng, const light_ray *lr)
{
    ray sr = shadow_ray(ctx, p, ng, lr);
    ctx->shadow_rays++;
    return shadow_filter(ctx->scene, &sr);
}

/* Whether light sample lr can light the point, before shadows, with the
 * cosine *ndl at the normal. */
static inline bool lit(const shade_point *sp, const light_ray *lr, float *ndl)
{
    if (v3_is_zero(lr->color))
        return false;
    *ndl = v3_dot(sp->n, lr->dir);
    return !(*ndl <= 0.0f);
}

/* The highlight's factor of a light seen in unit direction dir: the
 * material's specular times max(0, r.v)^shininess, 0 where either is.
 * The light kernels (light8.h) work it out eight lanes at once. */
__attribute__((always_inline)) static inline float highlight(const shade_point *sp, vec3 dir)
{
    const material *m = sp->m;
    if (!(m->specular > 0.0f))
        return 0.0f;
    float rv = -v3_dot(v3_reflect(v3_neg(dir), sp->n), sp->d);
    return rv > 0.0f ? m->specular * material_highlight(rv, m->shininess) : 0.0f;
}

/* The share of a light sample of colour `color`, at cosine ndl and with
 * highlight factor hl, in diffuse and specular, given vis (not zero),
 * what reaches the point of it. */
__attribute__((always_inline)) static inline void add_seen(const shade_point *sp, vec3 color,
                                                           float ndl, float hl, vec3 vis,
                                                           vec3 *diffuse, vec3 *specular)
{
    vec3 lc = v3_mul(color, vis);
    *diffuse = v3_madd(*diffuse, lc, sp->m->diffuse * ndl);
    if (hl > 0.0f)
        *specular = v3_madd(*specular, lc, hl);
}

/* add_seen for a light seen in unit direction dir. */
__attribute__((always_inline)) static inline void add_lit(const shade_point *sp, vec3 dir,
                                                          vec3 color, float ndl, vec3 vis,
                                                          vec3 *diffuse, vec3 *specular)
{
    if (!v3_is_zero(vis))
        add_seen(sp, color, ndl, highlight(sp, dir), vis, diffuse, specular);
}

/* One light sample's diffuse and specular share, shadowed. */
static inline void add_sample(trace_ctx *ctx, const shade_point *sp, const light_ray *lr,
                              vec3 *diffuse, vec3 *specular)
{
    float ndl;
    if (lit(sp, lr, &ndl))
        add_lit(sp, lr->dir, lr->color, ndl, lighting_shadow(ctx, sp->p, sp->ng, lr), diffuse,
                specular);
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

/* Ambient and lights summed into the point's colour. */
__attribute__((always_inline)) static inline vec3 local_sum(const shade_point *sp, vec3 diffuse,
                                                            vec3 specular)
{
    const material *m = sp->m;
    float w = maxf(1.0f - m->transmit, 0.0f);
    vec3 c = v3_add(v3_scale(v3_mul(diffuse, sp->base), w), specular);
    return v3_add(c, m->emission);
}

vec3 lighting_local(trace_ctx *ctx, const shade_point *sp)
{
    const scene *s = ctx->scene;
    uint32_t event = ctx->events++;
    vec3 diffuse = v3_scale(s->ambient, sp->m->ambient);
    vec3 specular = v3s(0.0f);
    for (int i = 0; i < s->nlights; i++)
        add_light(ctx, sp, i, event, &diffuse, &specular);
    return local_sum(sp, diffuse, specular);
}

/* The shadow rays of lanes `need` in the lanes of *p (the others hold
 * numbers): what reaches each ray's end into *vis, as shadow_filter
 * finds it. Three or more go through the scene together
 * (scene_shadow8, or scene_shadow8_among the n objects of among where n
 * >= 0), and only those that cross a transmitting object, or cannot go
 * together, one by one. */
static void shadow8_rays(trace_ctx *ctx, const ray8 *p, int need, const int32_t *among, int n,
                         vis8 *vis)
{
    const scene *s = ctx->scene;
    int blocked = 0, crosses = 0, alone = need, listed = 0;
    scene_crossings cross[8];
    int32_t obj[8];
    int count[8];
    if (ray8_three_or_more(need) &&
        (n >= 0 ? scene_shadow8_among(s, p, need, among, n, &blocked, &crosses)
                : scene_shadow8(s, p, need, &blocked, &crosses))) {
        alone = 0;
        /* their crossings together, which filter each: listed in order
         * along each ray only where it crosses more than one object, or
         * one that absorbs */
        if (crosses)
            listed = scene_shadow_one_crossed8(s, p, crosses, obj, count);
        for (int m = crosses & ~listed; m && s->any_absorb; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            if (count[k] && material_absorbs(&s->materials[s->objects[obj[k]].material]))
                listed |= 1 << k;
        }
        if (listed)
            blocked |= scene_shadow_unblocked8(s, p, listed, cross);
    }
    vis->blocked = blocked;
    vis->filtered = need & (alone | (crosses & ~blocked)); /* the lanes that need their ray */
    if (vis->filtered) /* every lane set, so that all eight may be read */
        for (int k = 0; k < 8; k++)
            color8_put(&vis->filter, k, v3s(blocked >> k & 1 ? 0.0f : 1.0f));
    for (int m = vis->filtered; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        vec3 f;
        if (!(alone >> k & 1) && !(listed >> k & 1)) {
            f = one_object_filter(s, obj[k], count[k]);
        } else if (!(alone >> k & 1) && !s->any_absorb) { /* the ray itself is not needed */
            f = crossings_filter(s, NULL, &cross[k]);
        } else {
            ray sr = ray8_get(p, k);
            f = alone >> k & 1 ? shadow_filter(s, &sr) : crossings_filter(s, &sr, &cross[k]);
        }
        color8_put(&vis->filter, k, f);
    }
    ctx->shadow_rays += (uint64_t)ray8_count(need);
}

/* The shadow rays of lanes `need` towards their light samples lr[k]
 * (shadow_ray, at each lane's time), through shadow8_rays. */
static void shadow8(trace_ctx *ctx, const trace_lanes *tl, const shade8 *sp,
                    const light_ray lr[8], int need, const int32_t *among, int n, vis8 *vis)
{
    ray8 p; /* the rays go straight into their lanes */
    for (int m = need; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ctx->time = tl->time[k];
        shade_point spk = shade8_get(sp, k);
        ray sr = shadow_ray(ctx, spk.p, spk.ng, &lr[k]);
        ray8_put(&p, k, &sr);
    }
    if (need)
        ray8_fill(&p, need);
    shadow8_rays(ctx, &p, need, among, n, vis);
}

/* The light kernels of light8_api.h on the scene's path; point NULL
 * where it has none, and the lanes go one by one. */
typedef struct light8_kernels {
    int (*point)(const light *, const shade8 *, int, const float *, ray8 *, light8_seen *);
    void (*start)(const shade8 *, int, vec3, light8_acc *);
    void (*add)(const shade8 *, int, const light8_seen *, const vis8 *, light8_acc *);
    void (*end)(const shade8 *, int, const light8_acc *, color8 *);
} light8_kernels;

static light8_kernels kernels8(const trace_ctx *ctx)
{
#if defined(GLINT_WIDE_KERNELS)
    accel_isa isa = ctx->scene->bvh.isa;
    if (isa == ACCEL_AVX512)
        return (light8_kernels){light8_point_avx512, light8_start_avx512, light8_add_avx512,
                                light8_end_avx512};
    if (isa == ACCEL_AVX2)
        return (light8_kernels){light8_point_avx2, light8_start_avx2, light8_add_avx2,
                                light8_end_avx2};
#endif
    (void)ctx;
    return (light8_kernels){NULL, NULL, NULL, NULL};
}

/* Lane k of acc, and lane k put back. */
static void acc_get(const light8_acc *acc, int k, vec3 *diffuse, vec3 *specular)
{
    *diffuse = color8_get(&acc->diffuse, k), *specular = color8_get(&acc->specular, k);
}

static void acc_put(light8_acc *acc, int k, vec3 diffuse, vec3 specular)
{
    color8_put(&acc->diffuse, k, diffuse);
    color8_put(&acc->specular, k, specular);
}

/* add_lit for lane k of acc. */
static void add_lit8(const shade8 *sp, int k, vec3 dir, vec3 color, float ndl, vec3 vis,
                     light8_acc *acc)
{
    shade_point spk = shade8_get(sp, k);
    vec3 diffuse, specular;
    acc_get(acc, k, &diffuse, &specular);
    add_lit(&spk, dir, color, ndl, vis, &diffuse, &specular);
    acc_put(acc, k, diffuse, specular);
}

/* The one-sample light l at the points of lanes, added to *acc: a point
 * light's terms eight at a time where the path has them (light8_point,
 * light8_add), any other lane by lane; the shadow rays together. */
static void add_light8(trace_ctx *ctx, const trace_lanes *tl, const light *l, const shade8 *sp,
                       int lanes, const light8_kernels *k8, const int32_t *among, int n,
                       light8_acc *acc)
{
    ray8 p;
    light8_seen seen;
    vis8 vis;
    if (l->kind == LIGHT_POINT && k8->point) {
        int need = k8->point(l, sp, lanes, tl->time, &p, &seen);
        if (need >= 0) {
            shadow8_rays(ctx, &p, need, among, n, &vis);
            for (int m = need & ~seen.highlit; m; m &= m - 1) { /* a powf each */
                int k = __builtin_ctz((unsigned)m);
                shade_point spk = shade8_get(sp, k);
                seen.hl[k] = highlight(&spk, v3(seen.dir[0][k], seen.dir[1][k], seen.dir[2][k]));
            }
            k8->add(sp, need, &seen, &vis, acc);
            return;
        }
    }
    light_ray lr[8];
    float ndl[8];
    int need = 0;
    for (int m = lanes; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade_point spk = shade8_get(sp, k);
        lr[k] = light_sample(l, spk.p, 0, 0.5f, 0.5f);
        need |= lit(&spk, &lr[k], &ndl[k]) << k;
    }
    shadow8(ctx, tl, sp, lr, need, among, n, &vis);
    for (int m = need; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        add_lit8(sp, k, lr[k].dir, lr[k].color, ndl[k], vis8_get(&vis, k), acc);
    }
}

void lighting_local8(trace_ctx *ctx, const trace_lanes *tl, const shade8 *sp, int lanes,
                     const uint32_t event[8], const trace_tile_shadows *tile, color8 *out)
{
    const scene *s = ctx->scene;
    light8_kernels k8 = kernels8(ctx);
    light8_acc acc;
    if (k8.start) {
        k8.start(sp, lanes, s->ambient, &acc);
    } else {
        for (int m = lanes; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            acc_put(&acc, k, v3_scale(s->ambient, sp->m[k]->ambient), v3s(0.0f));
        }
    }
    for (int i = 0; i < s->nlights; i++) {
        if (light_sample_count(&s->lights[i]) == 1) {
            bool listed = tile && i < TRACE_TILE_LIGHTS;
            add_light8(ctx, tl, &s->lights[i], sp, lanes, &k8, listed ? tile->list[i] : NULL,
                       listed ? tile->n[i] : -1, &acc);
            continue;
        }
        for (int m = lanes; m; m &= m - 1) { /* jittered samples, lane by lane */
            int k = __builtin_ctz((unsigned)m);
            trace_lanes_begin(ctx, tl, k);
            shade_point spk = shade8_get(sp, k);
            vec3 diffuse, specular;
            acc_get(&acc, k, &diffuse, &specular);
            add_light(ctx, &spk, i, event[k], &diffuse, &specular);
            acc_put(&acc, k, diffuse, specular);
        }
    }
    if (k8.end) {
        k8.end(sp, lanes, &acc, out);
        return;
    }
    for (int m = lanes; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade_point spk = shade8_get(sp, k);
        vec3 diffuse, specular;
        acc_get(&acc, k, &diffuse, &specular);
        color8_put(out, k, local_sum(&spk, diffuse, specular));
    }
}

#include "whitted.h"

#include <math.h>

#include "accel/isa.h"
#include "scene/scene.h"
#include "shade/optics.h"
#include "trace/bounce8_api.h"
#include "trace/lighting.h"
#include "trace/shading.h"

/* The split between reflection (*kr) and transmission (*kt) at the point,
 * and the transmitted direction (material.h). */
__attribute__((always_inline)) static inline void split(const shade_point *sp, float *kr,
                                                        float *kt, vec3 *tdir)
{
    const material *m = sp->m;
    *kr = m->reflect;
    *kt = m->transmit;
    *tdir = sp->d;
    if (*kt <= 0.0f || m->ior == 1.0f)
        return;
    float n1 = sp->inside ? m->ior : 1.0f, n2 = sp->inside ? 1.0f : m->ior;
    if (!optics_refract(sp->d, sp->n, n1 / n2, tdir)) {
        *kr += *kt; /* total internal reflection */
        *kt = 0.0f;
    } else if (m->fresnel) {
        float cosine = n1 > n2 ? -v3_dot(*tdir, sp->n) : -v3_dot(sp->d, sp->n);
        float f = optics_schlick(cosine, n1, n2);
        *kr += *kt * f;
        *kt *= 1.0f - f;
    }
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
    float w = share * k / maxf(total, 1.0f);
    if (!(k > 0.0f) || w < ctx->bailout)
        return false;
    ctx->weight = w;
    return true;
}

/* Radiance along r from its nearest hit *hitp, shaded at sp, whose local
 * light c is known: the reflected and transmitted rays added, and the
 * segment's fog or absorption. */
static vec3 trace_rest(trace_ctx *ctx, const ray *r, int depth, const scene_hit *hitp,
                       const shade_point *sp, vec3 c)
{
    float kr, kt;
    vec3 tdir;
    split(sp, &kr, &kt, &tdir);
    if (depth < ctx->max_depth) {
        float share = ctx->weight, gt = kt * v3_max_comp(sp->m->tint);
        if (adc_keep(ctx, share, kr, kr + gt)) {
            vec3 rd = v3_reflect(sp->d, sp->n);
            ray rr = ray_make(ray_offset(sp->p, sp->ng, rd), rd, INFINITY);
            rr.time = r->time;
            ctx->secondary_rays++;
            c = v3_madd(c, whitted_trace(ctx, &rr, depth + 1), kr);
        }
        if (kt > 0.0f && adc_keep(ctx, share, gt, kr + gt)) {
            ray tr = ray_make(ray_offset(sp->p, sp->ng, tdir), tdir, INFINITY);
            tr.time = r->time;
            ctx->secondary_rays++;
            c = v3_add(c, v3_scale(v3_mul(whitted_trace(ctx, &tr, depth + 1), sp->m->tint), kt));
        }
        ctx->weight = share;
    }
    return shade_segment(ctx->scene, r, hitp->h.t, sp, c);
}

/* Radiance along r, whose nearest hit is *hitp (NULL: it hit nothing). */
static vec3 trace_hit(trace_ctx *ctx, const ray *r, int depth, const scene_hit *hitp)
{
    const scene *s = ctx->scene;
    if (!hitp)
        return shade_segment(s, r, INFINITY, NULL, s->background);
    shade_point sp;
    shade_prepare(ctx, r, hitp, &sp);
    vec3 c = lighting_local(ctx, &sp);
    return trace_rest(ctx, r, depth, hitp, &sp, c);
}

vec3 whitted_trace(trace_ctx *ctx, const ray *r, int depth)
{
    scene_hit hit;
    return trace_hit(ctx, r, depth, scene_intersect(ctx->scene, r, &hit) ? &hit : NULL);
}

vec3 whitted_camera(trace_ctx *ctx, const ray *r, float *coverage)
{
    scene_hit hit;
    return whitted_camera_hit(ctx, r, scene_intersect(ctx->scene, r, &hit) ? &hit : NULL,
                              coverage);
}

vec3 whitted_camera_hit(trace_ctx *ctx, const ray *r, const struct scene_hit *hit,
                        float *coverage)
{
    *coverage = hit ? 1.0f : 0.0f;
    return trace_hit(ctx, r, 0, hit);
}

/* ---- eight samples at once ----------------------------------------------
 * The lanes of a packet go down their trees together: the rays the lanes
 * reflect (or transmit) at one level are traced as one packet
 * (scene_intersect8_spread) and lit together (lighting_local8), reflected
 * subtrees before transmitted ones as in trace_rest. Each lane keeps its
 * own shading events and share of the pixel, so it meets its events in
 * the order whitted_trace would and gets its colour to the bit. */

/* What each lane carries down its tree besides its rays. */
typedef struct lanes8 {
    const trace_lanes *tl;
    uint32_t events[8]; /* trace_ctx.events, lane by lane */
    float weight[8];    /* trace_ctx.weight, lane by lane */
} lanes8;

static void trace8(trace_ctx *ctx, lanes8 *ls, const ray r[8], const ray8 *p, int active,
                   int depth, vec3 out[8]);

/* bounce8 on the scene's path; -1 where it has none. */
static int bounce8_on_path(const trace_ctx *ctx, const bounce8_from *f, int found, bool reflect,
                           ray rs[8], ray8 *p, float weight[8])
{
#if defined(GLINT_WIDE_KERNELS)
    accel_isa isa = ctx->scene->bvh.isa;
    if (isa == ACCEL_AVX512)
        return bounce8_avx512(f, found, reflect, rs, p, weight);
    if (isa == ACCEL_AVX2)
        return bounce8_avx2(f, found, reflect, rs, p, weight);
#endif
    (void)ctx, (void)f, (void)found, (void)reflect, (void)rs, (void)p, (void)weight;
    return -1;
}

/* The reflected (reflect) or transmitted rays of the lanes of `found`
 * that adc_keep keeps, from f: returns those lanes, with the ray in rs[k]
 * and lane k of *p, and its share in ls->weight[k]. Eight at a time where
 * the path has the kernels (bounce8.h), the same floats either way. */
static int secondaries(trace_ctx *ctx, lanes8 *ls, const bounce8_from *f, int found,
                       bool reflect, ray rs[8], ray8 *p)
{
    int keep = bounce8_on_path(ctx, f, found, reflect, rs, p, ls->weight);
    if (keep < 0) {
        keep = 0;
        for (int m = found; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            const shade_point *sp = &f->sp[k];
            float kr = f->kr[k], gt = f->gt[k];
            if (reflect ? !adc_keep(ctx, f->share[k], kr, kr + gt)
                        : !(f->kt[k] > 0.0f && adc_keep(ctx, f->share[k], gt, kr + gt)))
                continue;
            ls->weight[k] = ctx->weight;
            vec3 d = reflect ? v3_reflect(sp->d, sp->n) : f->tdir[k];
            rs[k] = ray_make(ray_offset(sp->p, sp->ng, d), d, INFINITY);
            rs[k].time = f->time[k];
            keep |= 1 << k;
        }
        if (keep)
            ray8_pack(p, rs, keep);
    }
    ctx->secondary_rays += (uint64_t)ray8_count(keep);
    return keep;
}

/* trace_rest for the lanes of `found`, with their local light in c[k]. */
static void rest8(trace_ctx *ctx, lanes8 *ls, const ray r[8], int found, int depth,
                  const scene_hit hit[8], const shade_point sp[8], vec3 c[8], vec3 out[8])
{
    if (depth < ctx->max_depth) {
        float kr[8], kt[8], gt[8], share[8], time[8];
        vec3 tdir[8], sub[8];
        ray rs[8];
        ray8 p;
        int reflects = 0, transmits = 0; /* the lanes adc_keep may keep */
        for (int m = found; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            split(&sp[k], &kr[k], &kt[k], &tdir[k]);
            gt[k] = kt[k] * v3_max_comp(sp[k].m->tint);
            share[k] = ls->weight[k];
            time[k] = r[k].time;
            reflects |= (kr[k] > 0.0f) << k;
            transmits |= (kt[k] > 0.0f) << k;
        }
        bounce8_from f = {sp, share, kr, kt, gt, time, tdir, ctx->bailout};
        int keep = reflects ? secondaries(ctx, ls, &f, reflects, true, rs, &p) : 0;
        if (keep)
            trace8(ctx, ls, rs, &p, keep, depth + 1, sub);
        for (int m = keep; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            c[k] = v3_madd(c[k], sub[k], kr[k]);
        }
        keep = transmits ? secondaries(ctx, ls, &f, transmits, false, rs, &p) : 0;
        if (keep)
            trace8(ctx, ls, rs, &p, keep, depth + 1, sub);
        for (int m = keep; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            c[k] = v3_add(c[k], v3_scale(v3_mul(sub[k], sp[k].m->tint), kt[k]));
        }
        for (int m = found; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ls->weight[k] = share[k];
        }
    }
    for (int m = found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        out[k] = shade_segment(ctx->scene, &r[k], hit[k].h.t, &sp[k], c[k]);
    }
}

/* shade_prepare for the lanes of found. Out of line: the caller's sp is
 * then not taken for read before it is set (-Wmaybe-uninitialized), and it
 * is not cleared for lanes nobody reads. */
static __attribute__((noinline)) void prepare8(trace_ctx *ctx, const ray r[8], int found,
                                               const scene_hit hit[8], shade_point sp[8])
{
    for (int m = found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade_prepare(ctx, &r[k], &hit[k], &sp[k]);
    }
}

/* The lanes of active, whose nearest hits are hit[k] for the lanes of
 * found (the others saw the background), shaded into out[k]. */
static void shade8(trace_ctx *ctx, lanes8 *ls, const ray r[8], int active, int found,
                   int depth, const scene_hit hit[8], vec3 out[8])
{
    shade_point sp[8]; /* set for the lanes of found, the only ones used */
    vec3 c[8];
    prepare8(ctx, r, found, hit, sp);
    lighting_local8(ctx, ls->tl, sp, found, ls->events, c);
    for (int m = found; m; m &= m - 1)
        ls->events[__builtin_ctz((unsigned)m)]++;
    for (int m = active & ~found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        out[k] = trace_hit(ctx, &r[k], depth, NULL);
    }
    rest8(ctx, ls, r, found, depth, hit, sp, c, out);
}

/* whitted_trace for the rays r[k] of the lanes of active, which are also
 * the lanes of packet *p: three or more together, fewer one by one. */
static void trace8(trace_ctx *ctx, lanes8 *ls, const ray r[8], const ray8 *p, int active,
                   int depth, vec3 out[8])
{
    if (!ray8_three_or_more(active)) {
        float weight = ctx->weight;
        for (int m = active; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            trace_lanes_begin(ctx, ls->tl, k);
            ctx->events = ls->events[k];
            ctx->weight = ls->weight[k];
            out[k] = whitted_trace(ctx, &r[k], depth);
            ls->events[k] = ctx->events;
        }
        ctx->weight = weight;
        return;
    }
    scene_hit hit[8];
    int found = scene_intersect8_spread(ctx->scene, p, active, hit);
    shade8(ctx, ls, r, active, found, depth, hit, out);
}

void whitted_camera8(trace_ctx *ctx, const trace_lanes *tl, const ray r[8], int active,
                     int found, const scene_hit *hit, vec3 out[8], float coverage[8])
{
    float weight = ctx->weight; /* adc_keep changes it */
    lanes8 ls = {.tl = tl};
    for (int k = 0; k < 8; k++) {
        ls.events[k] = 0;
        ls.weight[k] = weight;
        coverage[k] = found >> k & 1 ? 1.0f : 0.0f;
    }
    shade8(ctx, &ls, r, active, found & active, 0, hit, out);
    ctx->weight = weight;
}

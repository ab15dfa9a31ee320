#include "whitted.h"

#include <math.h>

#include "scene/scene.h"
#include "shade/optics.h"
#include "trace/lighting.h"
#include "trace/shading.h"

/* The split between reflection (*kr) and transmission (*kt) at the point,
 * and the transmitted direction (material.h). */
static void split(const shade_point *sp, float *kr, float *kt, vec3 *tdir)
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

void whitted_camera8(trace_ctx *ctx, const trace_lanes *tl, const ray r[8], int active,
                     int found, const scene_hit *hit, vec3 out[8], float coverage[8])
{
    shade_point sp[8] = {0};
    vec3 local[8];
    found &= active;
    for (int m = found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade_prepare(ctx, &r[k], &hit[k], &sp[k]);
    }
    lighting_local8(ctx, tl, sp, found, local);
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        trace_lanes_begin(ctx, tl, k);
        coverage[k] = found >> k & 1 ? 1.0f : 0.0f;
        if (!(found >> k & 1)) {
            out[k] = trace_hit(ctx, &r[k], 0, NULL);
            continue;
        }
        ctx->events = 1; /* lighting_local8 had event 0 */
        out[k] = trace_rest(ctx, &r[k], 0, &hit[k], &sp[k], local[k]);
    }
}

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

static void trace8(trace_ctx *ctx, lanes8 *ls, const ray8 *p, int active, int depth,
                   color8 *out);

/* The packet kernels of the scene's path (bounce8_api.h), NULL where it
 * has none: the lanes then go one by one. */
static const shade8_kernels *kernels8(const trace_ctx *ctx)
{
#if defined(GLINT_WIDE_KERNELS)
    accel_isa isa = ctx->scene->bvh.isa;
    if (isa == ACCEL_AVX512)
        return &shade8_kernels_avx512;
    if (isa == ACCEL_AVX2)
        return &shade8_kernels_avx2;
#endif
    (void)ctx;
    return NULL;
}

/* The reflected (reflect) or transmitted rays of the lanes of `found`
 * that adc_keep keeps, from f: returns those lanes, with the ray in lane
 * k of *p, and its share in ls->weight[k]. Eight at a time where the path
 * has the kernels (bounce8.h), the same floats either way. */
static int secondaries(trace_ctx *ctx, lanes8 *ls, const bounce8_from *f, int found,
                       bool reflect, ray8 *p)
{
    const shade8_kernels *k8 = kernels8(ctx);
    int keep = 0;
    if (k8) {
        keep = k8->bounce(f, found, reflect, p, ls->weight);
    } else {
        ray rs[8];
        for (int m = found; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            shade_point sp = shade8_get(f->sp, k);
            float kr = f->kr[k], gt = f->gt[k];
            if (reflect ? !adc_keep(ctx, f->share[k], kr, kr + gt)
                        : !(f->kt[k] > 0.0f && adc_keep(ctx, f->share[k], gt, kr + gt)))
                continue;
            ls->weight[k] = ctx->weight;
            vec3 d = reflect ? v3_reflect(sp.d, sp.n)
                             : color8_get(f->tdir, k);
            rs[k] = ray_make(ray_offset(sp.p, sp.ng, d), d, INFINITY);
            rs[k].time = f->time[k];
            keep |= 1 << k;
        }
        if (keep)
            ray8_pack(p, rs, keep);
    }
    ctx->secondary_rays += (uint64_t)ray8_count(keep);
    return keep;
}

/* split for the lanes of found, into kr, kt and tdir, with gt = kt * the
 * tint's largest component; returns the lanes that reflect (kr > 0), and
 * those that transmit (kt > 0) into *transmits. */
static int split8(const trace_ctx *ctx, const shade8 *sp, int found, float kr[8], float kt[8],
                  float gt[8], color8 *tdir, int *transmits)
{
    const shade8_kernels *k8 = kernels8(ctx);
    if (k8)
        return k8->split(sp, found, kr, kt, gt, tdir, transmits);
    int reflects = 0;
    *transmits = 0;
    for (int m = found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade_point spk = shade8_get(sp, k);
        vec3 td;
        split(&spk, &kr[k], &kt[k], &td);
        color8_put(tdir, k, td);
        gt[k] = kt[k] * v3_max_comp(spk.m->tint);
        reflects |= (kr[k] > 0.0f) << k;
        *transmits |= (kt[k] > 0.0f) << k;
    }
    return reflects;
}

/* c[k] += sub[k] * kr[k] (reflect), or c[k] += (sub[k] * tint) * kt[k],
 * for the lanes of keep. */
static void mix8(const trace_ctx *ctx, const shade8 *sp, int keep, bool reflect,
                 const color8 *sub, const float kr[8], const float kt[8], color8 *c)
{
    const shade8_kernels *k8 = kernels8(ctx);
    if (k8) {
        k8->mix(sp, keep, reflect, sub, reflect ? kr : kt, c);
        return;
    }
    for (int m = keep; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        vec3 v = color8_get(c, k), s = color8_get(sub, k);
        v = reflect ? v3_madd(v, s, kr[k]) : v3_add(v, v3_scale(v3_mul(s, sp->m[k]->tint), kt[k]));
        color8_put(c, k, v);
    }
}

/* trace_rest for the lanes of `found`, with their local light in c, into
 * c. */
static void rest8(trace_ctx *ctx, lanes8 *ls, const ray8 *r, int found, int depth,
                  const scene_hit hit[8], const shade8 *sp, color8 *c)
{
    /* where no material reflects or transmits, no lane has a secondary ray */
    if (depth < ctx->max_depth && (ctx->scene->any_reflect || ctx->scene->any_transmit)) {
        float kr[8], kt[8], gt[8], share[8];
        color8 sub, tdir;
        ray8 p;
        int transmits, reflects = split8(ctx, sp, found, kr, kt, gt, &tdir, &transmits);
        for (int k = 0; k < 8; k++)
            share[k] = ls->weight[k];
        bounce8_from f = {sp, share, kr, kt, gt, r->time, &tdir, ctx->bailout};
        int keep = reflects ? secondaries(ctx, ls, &f, reflects, true, &p) : 0;
        if (keep) {
            trace8(ctx, ls, &p, keep, depth + 1, &sub);
            mix8(ctx, sp, keep, true, &sub, kr, kt, c);
        }
        keep = transmits ? secondaries(ctx, ls, &f, transmits, false, &p) : 0;
        if (keep) {
            trace8(ctx, ls, &p, keep, depth + 1, &sub);
            mix8(ctx, sp, keep, false, &sub, kr, kt, c);
        }
        for (int k = 0; k < 8; k++)
            ls->weight[k] = share[k];
    }
    /* lanes whose segment runs through fog or inside a transmitting object
     * that absorbs (shade_segment_crossed leaves any other's colour as it
     * is) */
    int crossed = 0;
    if (ctx->scene->fog.kind != FOG_NONE)
        crossed = found;
    else if (sp->same)
        crossed = shade_absorbs_inside(sp->same) ? found & sp->inside : 0;
    else
        for (int m = found & sp->inside; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            crossed |= shade_absorbs_inside(sp->m[k]) << k;
        }
    for (int m = crossed; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade_point spk = shade8_get(sp, k);
        ray rk = ray8_get(r, k);
        color8_put(c, k, shade_segment_crossed(ctx->scene, &rk, hit[k].h.t, &spk,
                                               color8_get(c, k)));
    }
}

/* Puts lane `bit`, whose hit on object o of material m is on one of the
 * plain surfaces (shading.h), into its kind's lanes of *plain; false for
 * any other hit. */
static bool plain_lane(const scene *s, const object *o, const scene_hit *hit,
                       const material *m, int bit, shade8_plain *plain)
{
    if (shade_plain_sphere(o, m))
        plain->sphere |= bit;
    else if (shade_plain_plane(o, m))
        plain->plane |= bit;
    else if (shade_plain_torus(o, m))
        plain->torus |= bit;
    else if (shade_plain_quad(s, o, m))
        plain->quad |= bit;
    else if (shade_plain_solid(o, m))
        *(o->shape.kind == SHAPE_BOX ? &plain->box : &plain->cylinder) |= bit;
    else if (shade_plain_leaf(o, hit, m))
        plain->csg |= bit;
    else
        return false;
    plain->turned |= o->xform >= 0 ? bit : 0;
    return true;
}

/* shade_prepare for the lanes of found into sp: those on plain surfaces
 * (shading.h: untextured spheres and planes, unturned; tori turned by a
 * fixed transform; quads, boxes and cylinders) eight at a time where the
 * path has the kernels, any other lane one by one as the lanes are looked
 * at, each object read once. */
static void prepare8(trace_ctx *ctx, const ray8 *p, int found, const scene_hit hit[8],
                     shade8 *sp)
{
    const scene *s = ctx->scene;
    const shade8_kernels *k8 = kernels8(ctx);
    shade_point done[8];
    shade8_plain plain = {0, 0, 0, 0, 0, 0, 0, 0};
    sp->same = found ? scene_hit_material(s, &hit[__builtin_ctz((unsigned)found)]) : NULL;
    for (int m = found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        const object *o = &s->objects[hit[k].object];
        const material *mk = scene_hit_material(s, &hit[k]);
        sp->same = mk == sp->same ? mk : NULL;
        sp->m[k] = mk;
        if (!k8 || !plain_lane(s, o, &hit[k], mk, 1 << k, &plain)) {
            ray rk = ray8_get(p, k);
            shade_prepare(ctx, &rk, &hit[k], &done[k]);
        }
    }
    int vector = plain.sphere | plain.plane | plain.torus | plain.quad | plain.box |
                 plain.cylinder | plain.csg;
    sp->inside = 0;
    if (vector)
        k8->prepare(s, ctx->decode, p, &plain, hit, sp); /* by address: plain_lane's
            4-byte stores, read back as one 32-byte copy, waited to reach the cache */
    for (int m = found & ~vector; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        shade8_put(sp, k, &done[k]);
    }
    sp->lanewise = (found & ~vector) != 0;
}

/* The lanes of active, whose nearest hits are hit[k] for the lanes of
 * found (the others saw the background), shaded into out. */
static void shade_lanes(trace_ctx *ctx, lanes8 *ls, const ray8 *p, int active, int found,
                        int depth, const scene_hit hit[8], color8 *out)
{
    shade8 sp; /* set for the lanes of found, the only ones used */
    prepare8(ctx, p, found, hit, &sp);
    /* into out itself: the mix kernel's loads of a copy made here, 16 bytes
     * at a time, would wait for its stores */
    lighting_local8(ctx, ls->tl, &sp, found, ls->events, depth == 0 ? ctx->tile : NULL, out);
    for (int m = found; m; m &= m - 1)
        ls->events[__builtin_ctz((unsigned)m)]++;
    rest8(ctx, ls, p, found, depth, hit, &sp, out);
    const scene *s = ctx->scene; /* the misses: the background, fogged */
    for (int m = active & ~found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray rk = ray8_get(p, k);
        vec3 v = s->fog.kind == FOG_NONE ? s->background : trace_hit(ctx, &rk, depth, NULL);
        color8_put(out, k, v);
    }
}

/* whitted_trace for the rays of the lanes of active of packet *p: three
 * or more together, fewer one by one. */
static void trace8(trace_ctx *ctx, lanes8 *ls, const ray8 *p, int active, int depth,
                   color8 *out)
{
    if (!ray8_three_or_more(active)) {
        float weight = ctx->weight;
        for (int m = active; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            trace_lanes_begin(ctx, ls->tl, k);
            ctx->events = ls->events[k];
            ctx->weight = ls->weight[k];
            ray rk = ray8_get(p, k);
            color8_put(out, k, whitted_trace(ctx, &rk, depth));
            ls->events[k] = ctx->events;
        }
        ctx->weight = weight;
        return;
    }
    scene_hit hit[8];
    int found = scene_intersect8_spread(ctx->scene, p, active, hit);
    shade_lanes(ctx, ls, p, active, found, depth, hit, out);
}

void whitted_camera8(trace_ctx *ctx, const trace_lanes *tl, const ray8 *p, int active,
                     int found, const scene_hit *hit, vec3 out[8], float coverage[8])
{
    float weight = ctx->weight; /* adc_keep changes it */
    lanes8 ls = {.tl = tl};
    for (int k = 0; k < 8; k++) {
        ls.events[k] = 0;
        ls.weight[k] = weight;
        coverage[k] = found >> k & 1 ? 1.0f : 0.0f;
    }
    color8 c;
    shade_lanes(ctx, &ls, p, active, found & active, 0, hit, &c);
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        out[k] = color8_get(&c, k);
    }
    ctx->weight = weight;
}

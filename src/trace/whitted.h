/* whitted: the recursive ray tracing integrator of Whitted, "An Improved
 * Illumination Model for Shaded Display" (CACM 1980): Phong local shading
 * with shadow rays to each light, plus reflected and transmitted rays, as
 * spelled out in material.h. What a hit looks like before lighting is
 * shading.c; light and shadows are lighting.c. */
#ifndef GLINT_TRACE_WHITTED_H
#define GLINT_TRACE_WHITTED_H

#include <stdint.h>
#include "core/hash.h"
#include "core/ray.h"

struct glint_scene;

/* The objects the shadow rays from a tile's camera hits may meet, light
 * by light, for the first lights (the renderer's tile_cone, from
 * scene_shadow_cone_objects): n[i] of list[i], or n[i] -1 where light i's
 * shadow rays walk the scene's tree. */
#define TRACE_TILE_LIGHTS 4
#define TRACE_TILE_OBJECTS 32
typedef struct trace_tile_shadows {
    int n[TRACE_TILE_LIGHTS];
    int32_t list[TRACE_TILE_LIGHTS][TRACE_TILE_OBJECTS];
} trace_tile_shadows;

/* Per-thread state for tracing; counters are summed by the renderer. */
typedef struct trace_ctx {
    const struct glint_scene *scene;
    const float *decode; /* 256 entries: texture byte -> shading value */
    int max_depth;
    uint64_t secondary_rays, shadow_rays;
    /* Adaptive depth control (Hall and Greenberg, "A Testbed for Realistic
     * Image Synthesis", IEEE CG&A 1983): weight is the share of the pixel
     * the ray being traced carries (1 for a primary ray); a secondary ray
     * whose share would fall below bailout is not traced. */
    float bailout, weight;
    /* The camera sample being traced (trace_begin_sample) and the shading
     * events since it began: each event draws its light samples from a hash
     * of the two, so they depend on the pixel and sample alone. The hash
     * of the sample is worked out the first time a light needs it
     * (trace_sample_hash): lights with one sample never do. */
    uint32_t id[3], sample, events;
    bool sample_hashed;
    float time; /* the camera ray's time, which every ray it leads to shares */
    /* The shadow lists of the tile whose camera rays whitted_camera8 is
     * given, for the lighting of their hits alone; NULL: none. */
    const trace_tile_shadows *tile;
} trace_ctx;

/* Names the camera sample about to be traced by three numbers that
 * identify it in the image (a pixel's x, y and the sample's index). */
static inline void trace_begin_sample(trace_ctx *ctx, uint32_t x, uint32_t y, uint32_t index)
{
    ctx->id[0] = x;
    ctx->id[1] = y;
    ctx->id[2] = index;
    ctx->sample_hashed = false;
    ctx->events = 0;
}

/* The camera samples of a packet's lanes: lane k is sample `index` of
 * pixel (x0 + k, y), its rays at time[k]. */
typedef struct trace_lanes {
    uint32_t x0, y, index;
    float time[8];
} trace_lanes;

/* trace_begin_sample for lane k, and its time. */
static inline void trace_lanes_begin(trace_ctx *ctx, const trace_lanes *tl, int k)
{
    trace_begin_sample(ctx, tl->x0 + (uint32_t)k, tl->y, tl->index);
    ctx->time = tl->time[k];
}

static inline uint32_t trace_sample_hash(trace_ctx *ctx)
{
    if (!ctx->sample_hashed) {
        ctx->sample = hash_add(hash_add(hash_u32(ctx->id[0]), ctx->id[1]), ctx->id[2]);
        ctx->sample_hashed = true;
    }
    return ctx->sample;
}

/* Radiance arriving along r; depth counts the bounces so far (0 for a
 * primary ray). */
vec3 whitted_trace(trace_ctx *ctx, const ray *r, int depth);

/* whitted_trace for a camera ray, also saying whether it hit something:
 * *coverage 1 when it did, 0 when it saw the background. */
vec3 whitted_camera(trace_ctx *ctx, const ray *r, float *coverage);

/* whitted_camera for a camera ray whose nearest hit is already known
 * (hit; NULL: none), as scene_intersect8 finds it for eight at once. */
struct scene_hit;
vec3 whitted_camera_hit(trace_ctx *ctx, const ray *r, const struct scene_hit *hit,
                        float *coverage);

/* whitted_camera_hit for the lanes of active of a packet of camera rays
 * *p (tl names their samples), with the hits hit[k] of the lanes in
 * found: colours into out[k], coverage into coverage[k]. The same colours
 * to the bit. The lanes go down their trees together: each level's
 * reflected (then transmitted) rays of three or more lanes go through the
 * scene as one packet (scene_intersect8) and their shadow rays likewise
 * (lighting_local8); fewer go one ray at a time. */
void whitted_camera8(trace_ctx *ctx, const trace_lanes *tl, const ray8 *p, int active,
                     int found, const struct scene_hit *hit, vec3 out[8], float coverage[8]);

#endif

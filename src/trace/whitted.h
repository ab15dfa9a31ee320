/* whitted: the recursive ray tracing integrator of Whitted, "An Improved
 * Illumination Model for Shaded Display" (CACM 1980): Phong local shading
 * with shadow rays to each light, plus reflected and transmitted rays, as
 * spelled out in material.h. */
#ifndef GLINT_TRACE_WHITTED_H
#define GLINT_TRACE_WHITTED_H

#include <stdint.h>
#include "core/ray.h"

struct glint_scene;

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
} trace_ctx;

/* Radiance arriving along r; depth counts the bounces so far (0 for a
 * primary ray). */
vec3 whitted_trace(trace_ctx *ctx, const ray *r, int depth);

/* Fraction of light that reaches p from the point `to` (a light's
 * position): 0 behind an opaque object, tinted through transmitting ones.
 * ng is the geometric normal at p on the side facing `to`. */
vec3 whitted_shadow(trace_ctx *ctx, vec3 p, vec3 ng, vec3 to);

#endif

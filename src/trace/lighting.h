/* lighting: the local part of material.h's formula at a shaded point:
 * ambient, every sample of every light with its shadow ray, and emission.
 *
 * Samples. A light with several samples per point (an area light's N x N
 * grid) places sample k at a point of its own cell, jittered by a hash of
 * the camera sample (pixel and index, trace_begin_sample), the shading
 * event along that sample's path, the light and k. The jitter turns what
 * would be N^2 hard-edged copies of each shadow (banding) into fine noise
 * that supersampling averages away, and the image stays the same for any
 * number of threads. */
#ifndef GLINT_TRACE_LIGHTING_H
#define GLINT_TRACE_LIGHTING_H

#include "shade/light.h"
#include "trace/shading.h"

/* ambient * base * (1 - transmit) + lights (diffuse, specular) + emission. */
vec3 lighting_local(trace_ctx *ctx, const shade_point *sp);

/* lighting_local for the points of the lanes in `lanes` of a packet
 * (tl names their samples), shading event event[k] of lane k's sample,
 * into lane k of out: the same colours, with the shadow rays towards each point,
 * spot or directional light traced together (scene_shadow8), and a point
 * light's terms worked out for the eight points at once on the eight-wide
 * paths (light8.h). The points are camera hits of the tile whose shadow
 * lists `tile` holds (NULL: no lists), and each light's shadow rays meet
 * only its list's objects (scene_shadow8_among). May leave ctx at any
 * lane's sample; ctx->events is not used. */
void lighting_local8(trace_ctx *ctx, const trace_lanes *tl, const shade8 *sp, int lanes,
                     const uint32_t event[8], const trace_tile_shadows *tile, color8 *out);

/* Fraction of light reaching p from the light sample lr: 0 behind an
 * opaque object, filtered by transmit * tint at each transmitting surface
 * crossed and by Beer-Lambert absorption inside those that absorb. ng is
 * the geometric normal at p on the side facing the light. Counts one
 * shadow ray. */
vec3 lighting_shadow(trace_ctx *ctx, vec3 p, vec3 ng, const light_ray *lr);

#endif

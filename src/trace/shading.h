/* shading: what a hit looks like before it is lit. The surface, its
 * material, the base colour (the texture's), the shading normal (bumped),
 * both normals turned to face the incoming ray, and what the ray crossed to
 * get there (fog in the open, absorption inside a transmitting object). */
#ifndef GLINT_TRACE_SHADING_H
#define GLINT_TRACE_SHADING_H

#include <stdbool.h>
#include "core/ray.h"
#include "scene/scene.h"
#include "trace/whitted.h"

typedef struct shade_point {
    vec3 p;      /* world point */
    vec3 n, ng;  /* unit shading and geometric normals, facing the ray */
    vec3 d;      /* unit direction of the incoming ray */
    bool inside; /* the ray hit the surface from behind */
    vec3 base;   /* colour times texture */
    const material *m;
} shade_point;

void shade_prepare(trace_ctx *ctx, const ray *r, const scene_hit *hit, shade_point *out);

/* What is seen through the segment of r from its origin to t (INFINITY
 * for a ray that hit nothing, sp NULL) of colour c at its end: fogged in
 * the open, absorbed when the segment ran inside a transmitting object. */
vec3 shade_segment_crossed(const scene *s, const ray *r, float t, const shade_point *sp,
                           vec3 c);

/* shade_segment_crossed, or c at once where the segment crosses neither
 * fog nor a transmitting object's inside. */
static inline vec3 shade_segment(const scene *s, const ray *r, float t, const shade_point *sp,
                                 vec3 c)
{
    if (s->fog.kind == FOG_NONE && !(sp && sp->inside && sp->m->transmit > 0.0f))
        return c;
    return shade_segment_crossed(s, r, t, sp, c);
}

#endif

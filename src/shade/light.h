/* light: the closed set of light sources, an enum + union like the shapes,
 * with one switch per question (here, inline, for the shading loop):
 *
 *   point        a position; intensity = color / (c + l d + q d^2) at
 *                distance d, attenuation (c, l, q) = (1, 0, 0) by default
 *                (no fall-off, the classic Whitted model)
 *   directional  parallel light travelling along a direction, from infinitely
 *                far away (the sun): no fall-off, shadow rays to infinity
 *   spot         a point light that shines in a cone round the axis from its
 *                position to look_at: full intensity within inner_angle of
 *                the axis, none beyond outer_angle, and between them
 *                t^2 (3 - 2t) with t = (cos a - cos outer) / (cos inner -
 *                cos outer) (POV-Ray's spotlight falloff); attenuated like a
 *                point light
 *   area         a rectangle centred on position with edges edge_u and
 *                edge_v, shining from both faces: an N x N grid of point
 *                lights, each color / N^2 and each moved to a point of its
 *                own cell chosen by the caller (stratified jitter), which
 *                gives soft shadows with penumbrae and soft highlights
 *
 * The colour carries the intensity and may exceed 1. */
#ifndef GLINT_SHADE_LIGHT_H
#define GLINT_SHADE_LIGHT_H

#include <math.h>
#include "core/vec3.h"

typedef enum light_kind {
    LIGHT_POINT,
    LIGHT_DIRECTIONAL,
    LIGHT_SPOT,
    LIGHT_AREA,
    LIGHT_KIND_COUNT
} light_kind;

/* Largest N of an area light's N x N grid. */
#define LIGHT_MAX_AREA_SAMPLES 64

struct point_light {
    vec3 position;
    vec3 attenuation; /* c, l, q */
};

struct directional_light {
    vec3 direction; /* unit: the way the light travels */
};

struct spot_light {
    vec3 position, look_at;
    vec3 axis; /* unit, from position towards look_at (light_refresh) */
    float cos_inner, cos_outer;
    vec3 attenuation;
};

struct area_light {
    vec3 position; /* the centre */
    vec3 corner;   /* position - edge_u / 2 - edge_v / 2 (light_refresh) */
    vec3 edge_u, edge_v;
    int n; /* the grid is n x n */
    vec3 attenuation;
};

typedef struct light {
    light_kind kind;
    vec3 color;
    union {
        struct point_light point;
        struct directional_light directional;
        struct spot_light spot;
        struct area_light area;
    };
} light;

/* Constructors validate nothing; front ends check ranges first (angles in
 * degrees, 0 < inner < outer < 180 for a spot; n >= 1 for an area light). */
light light_point(vec3 position, vec3 color, vec3 attenuation);
light light_directional(vec3 direction, vec3 color);
light light_spot(vec3 position, vec3 look_at, float inner_deg, float outer_deg, vec3 color,
                 vec3 attenuation);
light light_area(vec3 position, vec3 edge_u, vec3 edge_v, int n, vec3 color, vec3 attenuation);
/* Recomputes what a light derives from the values a scene may animate (a
 * spot's axis, an area light's corner, a directional light's unit
 * direction) once animation has changed them. A direction that has no
 * length at that moment keeps the last one. */
void light_refresh(light *l);

/* What one sample of a light gives a point: the unit direction towards the
 * light, the distance to it (INFINITY for directional light: shadow rays
 * run to infinity), the point sampled on the light (for shadow rays; unused
 * when dist is infinite) and the intensity arriving before shadowing (zero
 * outside a spot's cone). */
typedef struct light_ray {
    vec3 dir;
    float dist;
    vec3 pos;
    vec3 color;
} light_ray;

/* The attenuation factor 1 / (c + l d + q d^2) (1 for the default). */
static inline float light_attenuation(vec3 att, float d)
{
    float k = att.x + d * (att.y + d * att.z);
    return k > 0.0f ? 1.0f / k : 0.0f;
}

/* A spot light's factor in [0, 1] for a direction at cosine cos_a from
 * its axis. */
static inline float light_spot_factor(const struct spot_light *s, float cos_a)
{
    if (cos_a >= s->cos_inner)
        return 1.0f;
    if (cos_a <= s->cos_outer)
        return 0.0f;
    float t = (cos_a - s->cos_outer) / (s->cos_inner - s->cos_outer);
    return t * t * (3.0f - 2.0f * t);
}

/* How many samples the light takes per shaded point: N^2 for an area
 * light, 1 for the others. */
static inline int light_sample_count(const light *l)
{
    switch (l->kind) {
    case LIGHT_POINT:
    case LIGHT_DIRECTIONAL:
    case LIGHT_SPOT:
        return 1;
    case LIGHT_AREA:
        return l->area.n * l->area.n;
    case LIGHT_KIND_COUNT:
        break;
    }
    return 0;
}

/* Towards a point light source at pos, attenuated. */
static inline light_ray light_toward(vec3 p, vec3 pos, vec3 color, vec3 att)
{
    vec3 d = v3_sub(pos, p);
    float dist = v3_len(d);
    light_ray r = {v3_scale(d, dist > 0.0f ? 1.0f / dist : 0.0f), dist, pos, color};
    if (!(att.x == 1.0f && att.y == 0.0f && att.z == 0.0f))
        r.color = v3_scale(color, light_attenuation(att, dist));
    return r;
}

/* Sample k (0 <= k < light_sample_count) of the light as seen from p.
 * (u1, u2) in [0, 1)^2 place an area light's sample within its cell k
 * (row k / N, column k % N); other lights ignore them. The one switch over
 * the kinds that shading uses. */
__attribute__((always_inline)) static inline light_ray light_sample(const light *l, vec3 p, int k,
                                                                    float u1, float u2)
{
    switch (l->kind) {
    case LIGHT_POINT:
        return light_toward(p, l->point.position, l->color, l->point.attenuation);
    case LIGHT_DIRECTIONAL:
        return (light_ray){v3_neg(l->directional.direction), INFINITY, p, l->color};
    case LIGHT_SPOT: {
        const struct spot_light *s = &l->spot;
        light_ray r = light_toward(p, s->position, l->color, s->attenuation);
        float f = light_spot_factor(s, -v3_dot(r.dir, s->axis));
        r.color = v3_scale(r.color, f);
        return r;
    }
    case LIGHT_AREA: {
        const struct area_light *a = &l->area;
        float inv = 1.0f / (float)a->n;
        float su = ((float)(k % a->n) + u1) * inv, sv = ((float)(k / a->n) + u2) * inv;
        vec3 pos = v3_madd(v3_madd(a->corner, a->edge_u, su), a->edge_v, sv);
        return light_toward(p, pos, v3_scale(l->color, inv * inv), a->attenuation);
    }
    case LIGHT_KIND_COUNT:
        break;
    }
    return (light_ray){v3s(0.0f), 0.0f, p, v3s(0.0f)};
}

#endif

/* light: the closed set of light sources, an enum + union like the shapes,
 * with one switch per question (light.c):
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
    vec3 position;
    vec3 axis; /* unit, from position towards look_at */
    float cos_inner, cos_outer;
    vec3 attenuation;
};

struct area_light {
    vec3 corner; /* position - edge_u / 2 - edge_v / 2 */
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

/* How many samples the light takes per shaded point: N^2 for an area
 * light, 1 for the others. */
int light_sample_count(const light *l);

/* Sample k (0 <= k < light_sample_count) of the light as seen from p.
 * (u1, u2) in [0, 1)^2 place an area light's sample within its cell k
 * (row k / N, column k % N); other lights ignore them. */
light_ray light_sample(const light *l, vec3 p, int k, float u1, float u2);

/* The attenuation factor 1 / (c + l d + q d^2) (1 for the default). */
float light_attenuation(vec3 att, float d);

/* A spot light's factor in [0, 1] for a direction at cosine cos_a from
 * its axis. */
float light_spot_factor(const struct spot_light *s, float cos_a);

#endif

/* light8_api: the kernels of light8.h for the lighting of a packet
 * (lighting.c), on the eight-wide paths: a point light's sample and the
 * lanes' local light. */
#ifndef GLINT_TRACE_LIGHT8_API_H
#define GLINT_TRACE_LIGHT8_API_H

#include "shade/light.h"
#include "trace/shading.h"

/* A light's sample as each lane's point sees it: the unit direction to
 * it, its colour there, and the cosine at the shading normal; and for
 * the lanes of `highlit`, its highlight factor (lighting.c: highlight),
 * the others' left to be worked out one by one (a shininess that is not
 * a whole number, for powf). */
typedef struct light8_seen {
    float dir[3][8], color[3][8], ndl[8], hl[8];
    int highlit;
} light8_seen;

/* What reaches each lane's point of a light: nothing for the lanes of
 * blocked, filter[k] for those of filtered, all of it for the others. */
typedef struct vis8 {
    int blocked, filtered;
    color8 filter;
} vis8;

static inline vec3 vis8_get(const vis8 *v, int k)
{
    if (v->filtered >> k & 1)
        return color8_get(&v->filter, k);
    return v3s(v->blocked >> k & 1 ? 0.0f : 1.0f);
}

/* The light each lane has gathered so far (lighting.c's lighting_local8). */
typedef struct light8_acc {
    color8 diffuse, specular;
} light8_acc;

/* Point light l (one sample) from the points of the lanes of lanes, whose
 * samples are at time[k]: returns the lanes it lights (lit), with their
 * shadow rays in the lanes of *p (the others repeat one of them, as
 * ray8_fill leaves them) and what each sees in *out; -1 where a shadow ray
 * would have no end. */
int light8_point_avx2(const light *l, const shade8 *sp, int lanes, const float time[8], ray8 *p,
                      light8_seen *out);
int light8_point_avx512(const light *l, const shade8 *sp, int lanes, const float time[8],
                        ray8 *p, light8_seen *out);

/* lighting_local8's steps for the lanes of `lanes`, eight at a time, the
 * same floats as lighting.c's lane-by-lane loops: the start (diffuse, the
 * ambient light times each material's ambient; specular 0), a point
 * light's sample added where it is seen (the lanes of need, whose
 * highlights seen->hl holds for every lane of need), and the end
 * (local_sum) into out. */
void light8_start_avx2(const shade8 *sp, int lanes, vec3 ambient, light8_acc *acc);
void light8_start_avx512(const shade8 *sp, int lanes, vec3 ambient, light8_acc *acc);
void light8_add_avx2(const shade8 *sp, int need, const light8_seen *seen, const vis8 *vis,
                     light8_acc *acc);
void light8_add_avx512(const shade8 *sp, int need, const light8_seen *seen, const vis8 *vis,
                       light8_acc *acc);
void light8_end_avx2(const shade8 *sp, int lanes, const light8_acc *acc, color8 *out);
void light8_end_avx512(const shade8 *sp, int lanes, const light8_acc *acc, color8 *out);

#endif

/* light8_api: what the point-light kernels of light8.h give the lighting
 * of a packet (lighting.c), on the eight-wide paths. */
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

/* Point light l (one sample) from the points sp[k] of the lanes of lanes,
 * whose samples are at time[k]: returns the lanes it lights (lit), with
 * their shadow rays in the lanes of *p (the others repeat one of them,
 * as ray8_fill leaves them) and what each sees in *out; -1 where a shadow
 * ray would have no end. */
int light8_point_avx2(const light *l, const shade_point *sp, int lanes, const float time[8],
                      ray8 *p, light8_seen *out);
int light8_point_avx512(const light *l, const shade_point *sp, int lanes, const float time[8],
                        ray8 *p, light8_seen *out);

#endif

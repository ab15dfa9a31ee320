/* bounce8_api: the kernels of bounce8.h, which make a packet's reflected
 * or transmitted rays eight at a time (trace/whitted.c), on the
 * eight-wide paths. */
#ifndef GLINT_TRACE_BOUNCE8_API_H
#define GLINT_TRACE_BOUNCE8_API_H

#include "trace/shading.h"

/* What the secondary rays of a packet's lanes start from: each lane's
 * shading point, its share of the pixel, its reflected and transmitted
 * factors kr and kt, gt the light its transmission carries, its
 * transmitted direction tdir, and its rays' time. */
typedef struct bounce8_from {
    const shade_point *sp;
    const float *share, *kr, *kt, *gt, *time;
    const vec3 *tdir;
    float bailout;
} bounce8_from;

/* The reflected (reflect) or transmitted rays of the lanes of found that
 * adaptive depth control keeps (whitted.c's adc_keep): returns those
 * lanes, each with its ray in rs[k] and lane k of *p (the other lanes of
 * *p hold numbers) and its share in weight[k]; the same floats as
 * whitted.c's secondaries. */
int bounce8_avx2(const bounce8_from *f, int found, bool reflect, ray rs[8], ray8 *p,
                 float weight[8]);
int bounce8_avx512(const bounce8_from *f, int found, bool reflect, ray rs[8], ray8 *p,
                   float weight[8]);

#endif

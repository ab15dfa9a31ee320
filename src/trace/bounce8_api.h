/* bounce8_api: the kernels of a packet's shading on the eight-wide paths
 * (bounce8.h; trace/whitted.c calls them): its shading points, the split
 * between reflection and transmission, the secondary rays, and the light
 * they bring back. */
#ifndef GLINT_TRACE_BOUNCE8_API_H
#define GLINT_TRACE_BOUNCE8_API_H

#include "trace/shading.h"

/* What the secondary rays of a packet's lanes start from: each lane's
 * shading point, its share of the pixel, its reflected and transmitted
 * factors kr and kt, gt the light its transmission carries, its
 * transmitted direction tdir, and its rays' time. */
typedef struct bounce8_from {
    const shade8 *sp;
    const float *share, *kr, *kt, *gt, *time;
    const color8 *tdir;
    float bailout;
} bounce8_from;

/* The lanes of a packet whose hits are on shade_prepare's plain surfaces
 * (shading.h), by kind, and in `turned` those whose objects are turned
 * (which the boxes, cylinders and csg leaves are prepared by). */
typedef struct shade8_plain {
    int sphere, plane, torus, quad, box, cylinder, csg, turned;
} shade8_plain;

typedef struct shade8_kernels {
    /* shade_prepare for the lanes of kinds (not empty), whose materials
     * are sp->m[k] (set, and sp->same: shading.h), their images' stored
     * values read through decode, from their rays (lanes
     * of p) and hits: each field of sp stored whole, the other lanes
     * holding numbers, and sp->inside's bits of those lanes set. */
    void (*prepare)(const struct glint_scene *s, const float decode[256], const ray8 *p,
                    const shade8_plain *kinds, const struct scene_hit *hit, shade8 *sp);
    /* whitted.c's split for the lanes of found: kr, kt and tdir; gt = kt
     * times the tint's largest component; returns the lanes with kr > 0,
     * those with kt > 0 in *transmits. */
    int (*split)(const shade8 *sp, int found, float kr[8], float kt[8], float gt[8],
                 color8 *tdir, int *transmits);
    /* For the lanes of keep: c += sub * k (reflect), or c += (sub * the
     * material's tint) * k. */
    void (*mix)(const shade8 *sp, int keep, bool reflect, const color8 *sub, const float k[8],
                color8 *c);
    /* The reflected (reflect) or transmitted rays of the lanes of found
     * that adaptive depth control keeps (whitted.c's adc_keep): returns
     * those lanes, each with its ray in lane k of *p (the other lanes of
     * *p repeat one of them) and its share in weight[k]; the same floats
     * as whitted.c's secondaries. */
    int (*bounce)(const bounce8_from *f, int found, bool reflect, ray8 *p, float weight[8]);
} shade8_kernels;

extern const shade8_kernels shade8_kernels_avx2, shade8_kernels_avx512;

#endif

/* sphere_field: the random spheres of row 7 (spheres.c) and of row 3's
 * sphere build (raybench.c), placed the same way in both: centres uniform
 * in [-20, 20] x [-15, 15] x [-80, -30] from a fixed seed, one radius that
 * makes the spheres' total volume 3% of the box's whatever their number. */
#ifndef GLINT_BENCH_SPHERE_FIELD_H
#define GLINT_BENCH_SPHERE_FIELD_H

#include <math.h>
#include "core/rng.h"

static inline float sphere_field_radius(int n)
{
    double box = 40.0 * 30.0 * 50.0;
    return (float)cbrt(0.03 * box / n / (4.0 / 3.0 * M_PI));
}

static inline rng sphere_field_rng(void) { return rng_seed(12345, 1); }

/* The next centre from r: z, y and x drawn in that order, the order in
 * which the rows' earlier runs drew them, so that the spheres stay where
 * they were. */
static inline vec3 sphere_field_next(rng *r)
{
    float z = -80 + 50 * rng_float(r);
    float y = -15 + 30 * rng_float(r);
    float x = -20 + 40 * rng_float(r);
    return v3(x, y, z);
}

#endif

/* rng: PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
 * Statistically Good Algorithms for Random Number Generation"). State lives
 * wherever the caller keeps it (a per-thread or per-pixel context); there is
 * no global generator. */
#ifndef GLINT_CORE_RNG_H
#define GLINT_CORE_RNG_H

#include <math.h>
#include <stdint.h>

#include "vec3.h"

typedef struct rng {
    uint64_t state, inc;
} rng;

static inline uint32_t rng_u32(rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

static inline rng rng_seed(uint64_t seed, uint64_t stream)
{
    rng r = {0u, (stream << 1u) | 1u};
    rng_u32(&r);
    r.state += seed;
    rng_u32(&r);
    return r;
}

/* Uniform float in [0, 1). */
static inline float rng_float(rng *r) { return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f); }

/* Uniform direction on the unit sphere, by rejection from the cube. */
static inline vec3 rng_unit_dir(rng *g)
{
    for (;;) {
        vec3 v = v3(2.0f * rng_float(g) - 1.0f, 2.0f * rng_float(g) - 1.0f,
                    2.0f * rng_float(g) - 1.0f);
        float l2 = v3_len2(v);
        if (l2 > 1e-4f && l2 <= 1.0f)
            return v3_scale(v, 1.0f / sqrtf(l2));
    }
}

#endif

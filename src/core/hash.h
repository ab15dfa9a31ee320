/* hash: stateless integer hashing for deterministic "random" numbers. A
 * value drawn from a hash of where it is used (a pixel, a sample index, a
 * light, a stratum) is the same whichever thread computes it and in
 * whatever order, which is how sampling stays bit-identical for any thread
 * count. The mixer is "lowbias32" (C. Wellons, "Prospecting for Hash
 * Functions", 2018): every input bit affects every output bit. */
#ifndef GLINT_CORE_HASH_H
#define GLINT_CORE_HASH_H

#include <stdint.h>

static inline uint32_t hash_u32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/* A new hash from a hash h and one more value v. */
static inline uint32_t hash_add(uint32_t h, uint32_t v)
{
    return hash_u32(h ^ (hash_u32(v) + 0x9e3779b9U + (h << 6) + (h >> 2)));
}

/* The top 24 bits of h as a float in [0, 1). */
static inline float hash_unit(uint32_t h) { return (float)(h >> 8) * (1.0f / 16777216.0f); }

#endif

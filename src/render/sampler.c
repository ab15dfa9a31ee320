#include "sampler.h"

#include "scene/settings.h"

/* Which random number of a sample: each use draws from its own stream. */
enum { DIM_JITTER_X, DIM_JITTER_Y, DIM_LENS_U, DIM_LENS_V, DIM_TIME, DIM_LENS_PERM,
       DIM_TIME_PERM };

/* A 32-bit integer hash with good avalanche (Wellons's "lowbias32",
 * from his hash-prospector search). */
static uint32_t mix(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

static uint32_t hash4(uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    return mix(a + mix(b + mix(c + mix(d + 0x9e3779b9U))));
}

/* A float in [0, 1) from 24 bits of h. */
static float unit(uint32_t h) { return (float)(h >> 8) * (1.0f / 16777216.0f); }

/* A permutation of [0, l) chosen by seed: i is mixed by steps each of
 * which is a bijection of [0, 2^bits) (multiplication by an odd number and
 * xor-shifts, masked), repeated until it lands below l ("cycle walking",
 * as in Kensler 2013). */
static uint32_t permute(uint32_t i, uint32_t l, uint32_t seed)
{
    if (l <= 1)
        return 0;
    uint32_t mask = l - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    do {
        i = ((i ^ seed) * 0x2c1b3c6dU + (seed >> 7)) & mask;
        i ^= (i & mask) >> 3;
        i = (i * (0x297a2d39U | 1U) + mix(seed)) & mask;
        i ^= (i & mask) >> 2;
        i = (i * 0x9e3779b1U) & mask;
        i ^= (i & mask) >> 5;
    } while (i >= l);
    return i;
}

sampler sampler_make(const glint_settings *s, bool lens, bool motion)
{
    int n = settings_grid_side(s->samples);
    return (sampler){s->sampler, n > 0 ? n : 1, lens, motion};
}

int sampler_count(const sampler *s) { return s->n * s->n; }

bool sampler_same_in_every_pixel(const sampler *s)
{
    return s->kind == GLINT_SAMPLER_GRID && !s->lens && !s->motion;
}

pixel_sample sampler_get(const sampler *s, int x, int y, int k)
{
    uint32_t ux = (uint32_t)x, uy = (uint32_t)y, uk = (uint32_t)k;
    int n = s->n;
    float inv_n = 1.0f / (float)n;
    int a = k % n, b = k / n;
    pixel_sample p;
    float jx = 0.5f, jy = 0.5f;
    switch (s->kind) {
    case GLINT_SAMPLER_GRID:
    case GLINT_SAMPLER_ADAPTIVE:
        break;
    case GLINT_SAMPLER_JITTER:
        jx = unit(hash4(ux, uy, uk, DIM_JITTER_X));
        jy = unit(hash4(ux, uy, uk, DIM_JITTER_Y));
        break;
    }
    p.fx = ((float)a + jx) * inv_n;
    p.fy = ((float)b + jy) * inv_n;
    uint32_t count = (uint32_t)(n * n);
    p.lu = p.lv = 0.5f;
    p.time = 0.0f;
    if (s->lens) {
        uint32_t lens = permute(uk, count, hash4(ux, uy, 0, DIM_LENS_PERM));
        p.lu = ((float)(lens % (uint32_t)n) + unit(hash4(ux, uy, uk, DIM_LENS_U))) * inv_n;
        p.lv = ((float)(lens / (uint32_t)n) + unit(hash4(ux, uy, uk, DIM_LENS_V))) * inv_n;
    }
    if (s->motion) {
        uint32_t slot = permute(uk, count, hash4(ux, uy, 0, DIM_TIME_PERM));
        p.time = ((float)slot + unit(hash4(ux, uy, uk, DIM_TIME))) / (float)count;
    }
    /* float rounding must not reach 1 */
    p.fx = p.fx < 1.0f ? p.fx : 0x1.fffffep-1f;
    p.fy = p.fy < 1.0f ? p.fy : 0x1.fffffep-1f;
    p.lu = p.lu < 1.0f ? p.lu : 0x1.fffffep-1f;
    p.lv = p.lv < 1.0f ? p.lv : 0x1.fffffep-1f;
    p.time = p.time < 1.0f ? p.time : 0x1.fffffep-1f;
    return p;
}

pixel_sample sampler_point(uint32_t gx, uint32_t gy, float fx, float fy)
{
    const uint32_t point = 0x80000000U; /* a stream apart from sampler_get's */
    return (pixel_sample){fx, fy, unit(hash4(gx, gy, point, DIM_LENS_U)),
                          unit(hash4(gx, gy, point, DIM_LENS_V)),
                          unit(hash4(gx, gy, point, DIM_TIME))};
}

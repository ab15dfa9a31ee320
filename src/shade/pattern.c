#include "pattern.h"

#include <math.h>
#include <stdint.h>

/* stb_perlin's noise compiled in from its header rather than called in
 * Debian's libstb (built from the same header), which glint does not link
 * and opens only for the BMP, TGA and GIF files stb_image reads
 * (io/legacy.c). The noise is the same to the bit (tests/test_pattern.c
 * holds the two side by side). */
#define STB_PERLIN_IMPLEMENTATION
#include <stb_perlin.h>

/* floor(a) + floor(b) + floor(c) mod 2, in doubles so that large
 * coordinates keep their parity: the last bit of the whole number s
 * below 2^53, 0 from there (every double that large is even), 1 for an
 * infinite or NaN s, as fmod(|s|, 2) < 0.5 decides, without its call. */
static float parity(double a, double b, double c)
{
    double s = fabs(floor(a) + floor(b) + floor(c));
    if (s < 0x1p53)
        return (int64_t)s & 1 ? 1.0f : 0.0f;
    return s == s && s != INFINITY ? 0.0f : 1.0f;
}

float pattern_checker(vec3 q, bool solid)
{
    double e = solid ? (double)PATTERN_EDGE_BIAS : 0.0;
    return parity((double)q.x + e, (double)q.y + e, (double)q.z + e);
}

float pattern_stripes(vec3 q, bool solid)
{
    return parity((double)q.x + (solid ? (double)PATTERN_EDGE_BIAS : 0.0), 0.0, 0.0);
}

float pattern_rings(vec3 q, bool solid)
{
    double r = sqrt((double)q.x * q.x + (double)q.y * q.y);
    return parity(r + (solid ? (double)PATTERN_EDGE_BIAS : 0.0), 0.0, 0.0);
}

float pattern_gradient(vec3 q)
{
    double x = (double)q.x;
    float f = (float)(x - floor(x));
    return f < 1.0f ? f : 0.0f; /* rounding of x just below an integer */
}

/* x brought into [0, 256), the noise's period, so that stb_perlin's
 * conversion to int stays in range and far coordinates keep precision. */
static float wrap256(float x)
{
    if (!isfinite(x))
        return 0.0f;
    double w = (double)x - 256.0 * floor((double)x / 256.0);
    return w < 256.0 ? (float)w : 0.0f;
}

float pattern_perlin(vec3 q)
{
    float n = stb_perlin_noise3(wrap256(q.x), wrap256(q.y), wrap256(q.z), 0, 0, 0);
    return n < -1.0f ? -1.0f : n > 1.0f ? 1.0f : n;
}

float pattern_noise_value(vec3 q) { return 0.5f + 0.5f * pattern_perlin(q); }

float pattern_turbulence(vec3 q, const pattern_noise *pn)
{
    float sum = 0.0f, norm = 0.0f, amp = 1.0f, freq = 1.0f;
    for (int i = 0; i < pn->octaves; i++) {
        sum += fabsf(pattern_perlin(v3_scale(q, freq))) * amp;
        norm += amp;
        amp *= pn->gain;
        freq *= pn->lacunarity;
    }
    float t = norm > 0.0f ? sum / norm : 0.0f;
    return t > 1.0f ? 1.0f : t;
}

float pattern_marble(vec3 q, const pattern_noise *pn)
{
    float t = pn->amount > 0.0f ? pn->amount * pattern_turbulence(q, pn) : 0.0f;
    return 0.5f + 0.5f * sinf((float)M_PI * (q.x + t));
}

float pattern_wood(vec3 q, const pattern_noise *pn)
{
    double r = sqrt((double)q.x * q.x + (double)q.y * q.y);
    if (pn->amount > 0.0f)
        r += (double)(pn->amount * pattern_turbulence(q, pn));
    double f = r - floor(r);
    return (float)(1.0 - fabs(2.0 * f - 1.0));
}

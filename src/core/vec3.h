/* vec3: three floats used for points, directions and RGB colours.
 * Everything here is static inline arithmetic; no function has side effects. */
#ifndef GLINT_CORE_VEC3_H
#define GLINT_CORE_VEC3_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct vec3 {
    float x, y, z;
} vec3;

/* min and max as single instructions (fminf/fmaxf are library calls
 * under strict IEEE rules); with a NaN argument they return b. */
static inline float minf(float a, float b) { return a < b ? a : b; }
static inline float maxf(float a, float b) { return a > b ? a : b; }

/* The float just above x (x itself for +inf and NaN), without a library
 * call: "t < next_up(x)" is "t <= x". */
static inline float next_up(float x)
{
    if (!(x < INFINITY))
        return x;
    if (x == 0.0f)
        return 0x1p-149f;
    union {
        float f;
        int32_t i;
    } u = {x};
    u.i += x > 0.0f ? 1 : -1;
    return u.f;
}

static inline vec3 v3(float x, float y, float z) { return (vec3){x, y, z}; }
static inline vec3 v3s(float s) { return (vec3){s, s, s}; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
/* a + b * s */
static inline vec3 v3_madd(vec3 a, vec3 b, float s)
{
    return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static inline float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float v3_len2(vec3 a) { return v3_dot(a, a); }
static inline float v3_len(vec3 a) { return sqrtf(v3_dot(a, a)); }
static inline vec3 v3_norm(vec3 a)
{
    float l = v3_len(a);
    return l > 0.0f ? v3_scale(a, 1.0f / l) : a;
}
static inline vec3 v3_min(vec3 a, vec3 b)
{
    return v3(minf(a.x, b.x), minf(a.y, b.y), minf(a.z, b.z));
}
static inline vec3 v3_max(vec3 a, vec3 b)
{
    return v3(maxf(a.x, b.x), maxf(a.y, b.y), maxf(a.z, b.z));
}
static inline float v3_max_comp(vec3 a) { return maxf(a.x, maxf(a.y, a.z)); }
static inline float v3_max_abs(vec3 a) { return maxf(fabsf(a.x), maxf(fabsf(a.y), fabsf(a.z))); }
static inline float v3_at(vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline vec3 v3_lerp(vec3 a, vec3 b, float t) { return v3_madd(v3_scale(a, 1.0f - t), b, t); }
static inline bool v3_is_zero(vec3 a) { return a.x == 0.0f && a.y == 0.0f && a.z == 0.0f; }
/* Whether the n floats at f are all finite: none has its exponent's bits
 * all ones (infinite or NaN). One pass without branches, which the
 * compiler keeps in vector registers (loading a scene of thousands of
 * transforms, building one of a million objects, asks this of each). */
static inline bool floats_finite(const float *f, size_t n)
{
    uint32_t bad = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t w;
        memcpy(&w, f + i, sizeof w);
        bad |= (w & 0x7f800000u) == 0x7f800000u;
    }
    return !bad;
}

static inline bool v3_is_finite(vec3 a)
{
    const float f[3] = {a.x, a.y, a.z};
    return floats_finite(f, 3);
}

/* Mirror reflection of incident direction d about unit normal n. */
static inline vec3 v3_reflect(vec3 d, vec3 n) { return v3_madd(d, n, -2.0f * v3_dot(d, n)); }

/* Any unit vector perpendicular to unit vector n (Duff et al. 2017,
 * "Building an Orthonormal Basis, Revisited"). */
static inline void v3_basis(vec3 n, vec3 *t, vec3 *b)
{
    float s = copysignf(1.0f, n.z);
    float a = -1.0f / (s + n.z);
    float c = n.x * n.y * a;
    *t = v3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    *b = v3(c, s + n.y * n.y * a, -n.y);
}

#endif

#include "fog.h"

#include <math.h>

float fog_distance(const fog *f, vec3 o, vec3 d, float t)
{
    float h = f->height_falloff;
    if (h <= 0.0f)
        return t;
    /* In double: exp(-h o.y) can be large below y = 0 and the factor
     * (1 - exp(-x)) / x needs care near x = 0. */
    double base = exp(-(double)h * (double)o.y);
    double k = (double)h * (double)d.y;
    if (isinf(t))
        return k > 0.0 ? (float)(base / k) : INFINITY;
    double x = k * (double)t;
    double g = fabs(x) < 1e-8 ? 1.0 - 0.5 * x : -expm1(-x) / x;
    double dist = base * (double)t * g;
    return isnan(dist) ? INFINITY : (float)dist; /* inf * 0: deep below y = 0 */
}

float fog_transmittance(const fog *f, vec3 o, vec3 d, float t)
{
    switch (f->kind) {
    case FOG_NONE:
        return 1.0f;
    case FOG_EXPONENTIAL: {
        float dist = fog_distance(f, o, d, t);
        return isinf(dist) ? 0.0f : expf(-f->density * dist);
    }
    case FOG_LINEAR: {
        float dist = fog_distance(f, o, d, t);
        if (dist <= f->start)
            return 1.0f;
        if (dist >= f->end)
            return 0.0f;
        return (f->end - dist) / (f->end - f->start);
    }
    }
    return 1.0f;
}

vec3 fog_apply(const fog *f, vec3 o, vec3 d, float t, vec3 c)
{
    if (f->kind == FOG_NONE)
        return c;
    float tr = fog_transmittance(f, o, d, t);
    return v3_madd(v3_scale(f->color, 1.0f - tr), c, tr);
}

/* aabb: axis-aligned bounding box. An empty box has lo > hi. */
#ifndef GLINT_CORE_AABB_H
#define GLINT_CORE_AABB_H

#include <float.h>
#include "vec3.h"

typedef struct aabb {
    vec3 lo, hi;
} aabb;

static inline aabb aabb_empty(void) { return (aabb){v3s(FLT_MAX), v3s(-FLT_MAX)}; }
static inline aabb aabb_point(vec3 p) { return (aabb){p, p}; }
static inline aabb aabb_grow(aabb b, vec3 p) { return (aabb){v3_min(b.lo, p), v3_max(b.hi, p)}; }
static inline aabb aabb_union(aabb a, aabb b) { return (aabb){v3_min(a.lo, b.lo), v3_max(a.hi, b.hi)}; }
static inline vec3 aabb_center(aabb b) { return v3_scale(v3_add(b.lo, b.hi), 0.5f); }
static inline vec3 aabb_extent(aabb b) { return v3_sub(b.hi, b.lo); }
static inline bool aabb_is_empty(aabb b) { return b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z; }
static inline float aabb_area(aabb b)
{
    if (aabb_is_empty(b))
        return 0.0f;
    vec3 e = aabb_extent(b);
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
}

#endif

/* traverse: the ray against a wide BVH (accel/wide.h), four or eight
 * children a node. Generic over what a leaf holds: the caller passes a
 * leaf routine, and because everything here is inlined the compiler
 * builds one specialised copy per caller and per path. A translation unit
 * compiled with -mavx2 (or -mavx512vl) gets the eight-wide box tests; one
 * that defines GLINT_NO_SIMD before its includes gets the scalar four-wide
 * test; every other gets SSE. All of them compute each child's entry
 * distance with the same operations in the same order, so they agree to the
 * bit. */
#ifndef GLINT_ACCEL_TRAVERSE_H
#define GLINT_ACCEL_TRAVERSE_H

#include <math.h>
#include <stdint.h>
#if defined(__SSE2__) && !defined(GLINT_NO_SIMD)
#define GLINT_TRAVERSE_SSE 1
#include <emmintrin.h>
#endif
#if defined(__AVX2__) && !defined(GLINT_NO_SIMD)
#define GLINT_TRAVERSE_AVX2 1
#include <immintrin.h>
#endif
#include "accel/wide.h"
#include "core/ray.h"

/* The slab test rounds (lo - o) * (1 / d) and so can put a box's far
 * distance just before its near one for a ray that passes exactly through
 * an edge or corner of the box, skipping it. Growing the far distances by
 * 1 + 2 gamma(3), gamma(n) = n eps / (1 - n eps) with eps = 2^-24, keeps the
 * test conservative (Ize, "Robust BVH Ray Traversal", JCGT 2013). */
#define WIDE_FAR_SCALE (1.0f + 2.0f * 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f))

/* A box's entry distance (lo - o) * (1 / d) can come out a few units in
 * the last place beyond a hit inside it. Closest-hit walks therefore visit
 * every child entered up to wide_reach(t) of the nearest hit t so far, not
 * only up to t: a hit at exactly t in another child is then always met,
 * and of two hits at the same distance the lower index wins (mesh_trace.h,
 * scene_trace.h) whatever order the walk visits them in, one ray at a
 * time or eight together (mesh_packet.h). */
#define WIDE_TIE_SCALE (1.0f + 0x1p-18f)

static inline float wide_reach(float tmax) { return tmax * WIDE_TIE_SCALE; }

/* A path from the root is at most BVH_MAX_DEPTH long (collapsing never
 * deepens a tree), and a node pushes at most width - 1 entries besides the
 * one it descends to. */
#define WIDE_STACK(w) ((w - 1) * BVH_MAX_DEPTH + (w))

/* A leaf routine tests the leaf's count primitives from first (for the
 * hierarchy as built: prims[first .. first + count); an owner may renumber
 * leaves to point into its own storage): for closest-hit queries it lowers
 * *tmax to each hit it finds and returns true if it found any; for any-hit
 * queries it returns true at the first hit. */
typedef bool (*wide_leaf_fn)(void *ctx, uint32_t first, uint32_t count, float tmin, float *tmax);

/* One entry of the traversal stack: a child to visit and the distance at
 * which the ray enters its box. */
typedef struct wide_entry {
    int32_t child;
    uint32_t count;
    float dist;
} wide_entry;

typedef struct wide_ray {
    vec3 o, inv;
    int nx, ny, nz; /* 1 where the direction is negative: hi is the near plane */
    float tmin;
} wide_ray;

static inline wide_ray wide_ray_make(vec3 o, vec3 d, float tmin)
{
    wide_ray r;
    r.o = o;
    r.inv = v3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
    r.nx = r.inv.x < 0.0f;
    r.ny = r.inv.y < 0.0f;
    r.nz = r.inv.z < 0.0f;
    r.tmin = tmin;
    return r;
}

/* The children of a four-wide node the ray enters before tmax, as a bit
 * mask; tn[k] is where it enters child k. */
__attribute__((always_inline)) static inline int wide_test4(const bvh4_node *n, const wide_ray *r,
                                                            float tmax, float tn[8])
{
#if defined(GLINT_TRAVERSE_SSE)
    const __m128 ox = _mm_set1_ps(r->o.x), oy = _mm_set1_ps(r->o.y), oz = _mm_set1_ps(r->o.z);
    const __m128 ix = _mm_set1_ps(r->inv.x), iy = _mm_set1_ps(r->inv.y), iz = _mm_set1_ps(r->inv.z);
    __m128 t0x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[0 + r->nx]), ox), ix);
    __m128 t1x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[1 - r->nx]), ox), ix);
    __m128 t0y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[2 + r->ny]), oy), iy);
    __m128 t1y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[3 - r->ny]), oy), iy);
    __m128 t0z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[4 + r->nz]), oz), iz);
    __m128 t1z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[5 - r->nz]), oz), iz);
    __m128 vn = _mm_max_ps(_mm_max_ps(t0x, t0y), _mm_max_ps(t0z, _mm_set1_ps(r->tmin)));
    __m128 vf = _mm_min_ps(_mm_min_ps(t1x, t1y), _mm_min_ps(t1z, _mm_set1_ps(INFINITY)));
    vf = _mm_min_ps(_mm_mul_ps(vf, _mm_set1_ps(WIDE_FAR_SCALE)), _mm_set1_ps(tmax));
    _mm_storeu_ps(tn, vn);
    return _mm_movemask_ps(_mm_cmple_ps(vn, vf));
#else
    int mask = 0;
    vec3 o = r->o, inv = r->inv;
    for (int k = 0; k < 4; k++) {
        float a0 = (n->box[0 + r->nx][k] - o.x) * inv.x, a1 = (n->box[1 - r->nx][k] - o.x) * inv.x;
        float b0 = (n->box[2 + r->ny][k] - o.y) * inv.y, b1 = (n->box[3 - r->ny][k] - o.y) * inv.y;
        float c0 = (n->box[4 + r->nz][k] - o.z) * inv.z, c1 = (n->box[5 - r->nz][k] - o.z) * inv.z;
        tn[k] = maxf(maxf(a0, b0), maxf(c0, r->tmin));
        float tf = minf(minf(minf(a1, b1), minf(c1, INFINITY)) * WIDE_FAR_SCALE, tmax);
        mask |= (tn[k] <= tf) << k;
    }
    return mask;
#endif
}

#if defined(GLINT_TRAVERSE_AVX2)
/* The same for an eight-wide node, in one AVX register per plane. With
 * AVX-512 the comparison writes a mask register directly. */
__attribute__((always_inline)) static inline int wide_test8(const bvh8_node *n, const wide_ray *r,
                                                            float tmax, float tn[8])
{
    const __m256 ox = _mm256_set1_ps(r->o.x), oy = _mm256_set1_ps(r->o.y);
    const __m256 oz = _mm256_set1_ps(r->o.z);
    const __m256 ix = _mm256_set1_ps(r->inv.x), iy = _mm256_set1_ps(r->inv.y);
    const __m256 iz = _mm256_set1_ps(r->inv.z);
    __m256 t0x = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n->box[0 + r->nx]), ox), ix);
    __m256 t1x = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n->box[1 - r->nx]), ox), ix);
    __m256 t0y = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n->box[2 + r->ny]), oy), iy);
    __m256 t1y = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n->box[3 - r->ny]), oy), iy);
    __m256 t0z = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n->box[4 + r->nz]), oz), iz);
    __m256 t1z = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n->box[5 - r->nz]), oz), iz);
    __m256 vn = _mm256_max_ps(_mm256_max_ps(t0x, t0y), _mm256_max_ps(t0z, _mm256_set1_ps(r->tmin)));
    __m256 vf = _mm256_min_ps(_mm256_min_ps(t1x, t1y), _mm256_min_ps(t1z, _mm256_set1_ps(INFINITY)));
    vf = _mm256_min_ps(_mm256_mul_ps(vf, _mm256_set1_ps(WIDE_FAR_SCALE)), _mm256_set1_ps(tmax));
    _mm256_storeu_ps(tn, vn);
#if defined(__AVX512VL__)
    return (int)_mm256_cmp_ps_mask(vn, vf, _CMP_LE_OQ);
#else
    return _mm256_movemask_ps(_mm256_cmp_ps(vn, vf, _CMP_LE_OQ));
#endif
}
#endif

/* Where traversal goes from a node whose children in mask are entered at
 * tn: with one child straight on to it, with two on to the nearer with the
 * farther pushed, with more all pushed sorted far to near and the nearest
 * popped (any-hit queries skip the ordering). Ties keep child order, so
 * traversal is the same on every run. Returns false when nothing is
 * entered. */
__attribute__((always_inline)) static inline bool
wide_descend(int mask, const float *tn, const int32_t *child, const uint32_t *count, bool any,
             wide_entry *stack, int *sp, int32_t *cur, uint32_t *cur_count)
{
    if (!mask)
        return false;
    int k0 = __builtin_ctz((unsigned)mask);
    mask &= mask - 1;
    if (!mask) {
        *cur = child[k0];
        *cur_count = count[k0];
        return true;
    }
    int k1 = __builtin_ctz((unsigned)mask);
    mask &= mask - 1;
    if (!mask) {
        int nearer = any || tn[k0] <= tn[k1] ? k0 : k1, farther = k0 + k1 - nearer;
        stack[(*sp)++] = (wide_entry){child[farther], count[farther], tn[farther]};
        *cur = child[nearer];
        *cur_count = count[nearer];
        return true;
    }
    int base = *sp, n = *sp;
    stack[n++] = (wide_entry){child[k0], count[k0], tn[k0]};
    stack[n++] = (wide_entry){child[k1], count[k1], tn[k1]};
    for (; mask; mask &= mask - 1) {
        int k = __builtin_ctz((unsigned)mask);
        stack[n++] = (wide_entry){child[k], count[k], tn[k]};
    }
    if (!any)
        for (int i = base + 1; i < n; i++) {
            wide_entry e = stack[i];
            int j = i;
            for (; j > base && stack[j - 1].dist < e.dist; j--)
                stack[j] = stack[j - 1];
            stack[j] = e;
        }
    *sp = n - 1;
    *cur = stack[n - 1].child;
    *cur_count = stack[n - 1].count;
    return true;
}

/* Tests node i and moves to where wide_descend says. */
__attribute__((always_inline)) static inline bool
wide_visit(const bvhw *b, int width, int32_t i, const wide_ray *r, float tmax, bool any,
           wide_entry *stack, int *sp, int32_t *cur, uint32_t *cur_count)
{
    float tn[8];
#if defined(GLINT_TRAVERSE_AVX2)
    if (width == 8) {
        const bvh8_node *n = &b->n8[i];
        int mask = wide_test8(n, r, tmax, tn);
        /* What the children entered hold is read next: fetch it now (a
         * node's four cache lines, a leaf's first three). */
        for (int m = b->fetch_ahead ? mask : 0; m; m &= m - 1) {
            int32_t c = n->child[__builtin_ctz((unsigned)m)];
            const char *p = c >= 0 ? (const char *)&b->n8[c]
                            : b->leaf_data ? (const char *)b->leaf_data +
                                                 (size_t)(-1 - c) * b->leaf_stride
                                           : NULL;
            if (p) {
                __builtin_prefetch(p);
                __builtin_prefetch(p + 64);
                __builtin_prefetch(p + 128);
                if (c >= 0)
                    __builtin_prefetch(p + 192);
            }
        }
        return wide_descend(mask, tn, n->child, n->count, any, stack, sp, cur, cur_count);
    }
#else
    if (width == 8) /* an eight-wide tree needs a kernel built with AVX2 */
        __builtin_trap();
#endif
    const bvh4_node *n = &b->n4[i];
    return wide_descend(wide_test4(n, r, tmax, tn), tn, n->child, n->count, any, stack, sp, cur,
                        cur_count);
}

/* The ray o + t d against the hierarchy for t in (tmin, *tmax), on a BVH
 * of the given width (a constant, so that each copy holds one layout).
 * With any set, stops at the first leaf that reports a hit. Closest-hit
 * queries visit children near to far and skip entries beyond the reach of
 * the nearest hit (wide_reach) when they come off the stack. */
__attribute__((always_inline)) static inline bool
wide_traverse(const bvhw *b, int width, vec3 o, vec3 d, float tmin, float *tmax, bool any,
              wide_leaf_fn leaf, void *ctx)
{
    if (b->nnodes == 0)
        return false;
    wide_ray r = wide_ray_make(o, d, tmin);
    bool found = false;
    wide_entry stack[WIDE_STACK(8)];
    int sp = 0;
    int32_t cur = 0;
    uint32_t cur_count = 0;
    for (;;) {
        if (cur >= 0) {
            if (wide_visit(b, width, cur, &r, wide_reach(*tmax), any, stack, &sp, &cur,
                           &cur_count))
                continue;
        } else if (leaf(ctx, (uint32_t)(-1 - cur), cur_count, tmin, tmax)) {
            found = true;
            if (any)
                return true;
        }
        do { /* the nearest entry still in front of the nearest hit */
            if (sp == 0)
                return found;
            sp--;
        } while (stack[sp].dist > wide_reach(*tmax));
        cur = stack[sp].child;
        cur_count = stack[sp].count;
    }
}

#endif

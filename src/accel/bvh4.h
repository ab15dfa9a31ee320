/* bvh4: a four-wide BVH made by collapsing a binary one (accel/bvh.h), so
 * that one SIMD box test decides four children at once (Dammertz et al.,
 * "Shallow Bounding Volume Hierarchies for Fast SIMD Ray Tracing of
 * Incoherent Rays", EGSR 2008; Wald et al., "Getting Rid of Packets", IEEE
 * RT 2008). A scalar path does the same work where SSE is missing.
 *
 * Each node keeps its children's boxes as structure-of-arrays. A child is
 * an interior node (child >= 0), a leaf (child < 0: primitives
 * prims[-1 - child .. + count)) or empty (count 0 with an inverted box that
 * no ray can hit). Traversal is generic over what a leaf holds: the caller
 * passes a leaf routine, and because the traversal is static inline the
 * compiler builds one specialised copy per caller. */
#ifndef GLINT_ACCEL_BVH4_H
#define GLINT_ACCEL_BVH4_H

#include <stdint.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "glint.h"
#include "accel/bvh.h"
#include "core/ray.h"

/* The slab test rounds (lo - o) * (1 / d) and so can put a box's far
 * distance just before its near one for a ray that passes exactly through
 * an edge or corner of the box, skipping it. Growing the far distances by
 * 1 + 2 gamma(3), gamma(n) = n eps / (1 - n eps) with eps = 2^-24, keeps the
 * test conservative (Ize, "Robust BVH Ray Traversal", JCGT 2013). */
#define BVH4_FAR_SCALE (1.0f + 2.0f * 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f))

/* A path from the root is at most this long (collapsing never deepens a
 * tree), and a node pushes at most 3 entries besides the one it descends
 * to, so a stack of 3 * BVH_MAX_DEPTH + 4 entries never overflows. */
#define BVH4_STACK (3 * BVH_MAX_DEPTH + 4)

typedef struct bvh4_node {
    float box[6][4];  /* lo x, hi x, lo y, hi y, lo z, hi z; one lane per child */
    int32_t child[4];
    uint32_t count[4];
} __attribute__((aligned(64))) bvh4_node;

typedef struct bvh4 {
    bvh4_node *nodes;
    int nnodes;
    int32_t *prims; /* taken over from the binary BVH */
    int nprims;
    aabb bounds;
} bvh4;

/* Collapses b into out, taking over b's primitive array. b is freed in
 * every case, failure included. */
glint_rc bvh4_from_bvh(bvh4 *out, bvh *b, glint_error *err);
void bvh4_free(bvh4 *b);

/* A leaf routine tests the leaf's count primitives from first (for the
 * hierarchy as built: prims[first .. first + count); an owner may renumber
 * leaves to point into its own storage): for closest-hit queries it lowers
 * *tmax to each hit it finds and returns true if it found any; for any-hit
 * queries it returns true at the first hit. */
typedef bool (*bvh4_leaf_fn)(void *ctx, uint32_t first, uint32_t count, float tmin, float *tmax);

/* One entry of the traversal stack: a child to visit and the distance at
 * which the ray enters its box. */
typedef struct bvh4_entry {
    int32_t child;
    uint32_t count;
    float dist;
} bvh4_entry;

/* The ray o + t d against the hierarchy for t in (tmin, *tmax). With any
 * set, stops at the first leaf that reports a hit. Closest-hit queries
 * visit children near to far: with one child hit the traversal goes on to
 * it directly, with two it pushes the farther, with more it sorts them;
 * any-hit queries skip the ordering. */
__attribute__((always_inline)) static inline bool bvh4_traverse(const bvh4 *b, vec3 o, vec3 d,
                                                                float tmin, float *tmax, bool any,
                                                                bvh4_leaf_fn leaf, void *ctx)
{
    if (b->nnodes == 0)
        return false;
    vec3 inv = v3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
    /* Which of lo/hi is the near plane on each axis. */
    int nx = inv.x < 0.0f, ny = inv.y < 0.0f, nz = inv.z < 0.0f;
    bool found = false;
    bvh4_entry stack[BVH4_STACK];
    int sp = 0;
    int32_t cur = 0;
    uint32_t cur_count = 0;
#if defined(__SSE2__)
    const __m128 ox = _mm_set1_ps(o.x), oy = _mm_set1_ps(o.y), oz = _mm_set1_ps(o.z);
    const __m128 ix = _mm_set1_ps(inv.x), iy = _mm_set1_ps(inv.y), iz = _mm_set1_ps(inv.z);
    const __m128 vtmin = _mm_set1_ps(tmin);
#endif
    for (;;) {
        if (cur < 0) {
            if (leaf(ctx, (uint32_t)(-1 - cur), cur_count, tmin, tmax)) {
                found = true;
                if (any)
                    return true;
            }
        } else {
            const bvh4_node *n = &b->nodes[cur];
            float tn[4];
            int mask = 0;
#if defined(__SSE2__)
            __m128 t0x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[0 + nx]), ox), ix);
            __m128 t1x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[1 - nx]), ox), ix);
            __m128 t0y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[2 + ny]), oy), iy);
            __m128 t1y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[3 - ny]), oy), iy);
            __m128 t0z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[4 + nz]), oz), iz);
            __m128 t1z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[5 - nz]), oz), iz);
            __m128 vn = _mm_max_ps(_mm_max_ps(t0x, t0y), _mm_max_ps(t0z, vtmin));
            __m128 vf = _mm_min_ps(_mm_min_ps(t1x, t1y), _mm_min_ps(t1z, _mm_set1_ps(INFINITY)));
            vf = _mm_min_ps(_mm_mul_ps(vf, _mm_set1_ps(BVH4_FAR_SCALE)), _mm_set1_ps(*tmax));
            mask = _mm_movemask_ps(_mm_cmple_ps(vn, vf));
            _mm_storeu_ps(tn, vn);
#else
            for (int k = 0; k < 4; k++) {
                float a0 = (n->box[0 + nx][k] - o.x) * inv.x, a1 = (n->box[1 - nx][k] - o.x) * inv.x;
                float b0 = (n->box[2 + ny][k] - o.y) * inv.y, b1 = (n->box[3 - ny][k] - o.y) * inv.y;
                float c0 = (n->box[4 + nz][k] - o.z) * inv.z, c1 = (n->box[5 - nz][k] - o.z) * inv.z;
                tn[k] = maxf(maxf(a0, b0), maxf(c0, tmin));
                float tf = minf(minf(minf(a1, b1), minf(c1, INFINITY)) * BVH4_FAR_SCALE, *tmax);
                mask |= (tn[k] <= tf) << k;
            }
#endif
            if (mask) {
                int k0 = __builtin_ctz((unsigned)mask);
                mask &= mask - 1;
                if (!mask) { /* one child: straight on */
                    cur = n->child[k0];
                    cur_count = n->count[k0];
                    continue;
                }
                int k1 = __builtin_ctz((unsigned)mask);
                mask &= mask - 1;
                if (!mask) { /* two: push the farther, go on with the nearer */
                    int nearer = any || tn[k0] <= tn[k1] ? k0 : k1, farther = k0 + k1 - nearer;
                    stack[sp++] = (bvh4_entry){n->child[farther], n->count[farther], tn[farther]};
                    cur = n->child[nearer];
                    cur_count = n->count[nearer];
                    continue;
                }
                /* Three or four: push them sorted far to near, then pop
                 * the nearest. Ties keep child order, so traversal is the
                 * same on every run. */
                int base = sp;
                stack[sp++] = (bvh4_entry){n->child[k0], n->count[k0], tn[k0]};
                stack[sp++] = (bvh4_entry){n->child[k1], n->count[k1], tn[k1]};
                for (; mask; mask &= mask - 1) {
                    int k = __builtin_ctz((unsigned)mask);
                    stack[sp++] = (bvh4_entry){n->child[k], n->count[k], tn[k]};
                }
                if (!any)
                    for (int i = base + 1; i < sp; i++) {
                        bvh4_entry e = stack[i];
                        int j = i;
                        while (j > base && stack[j - 1].dist < e.dist) {
                            stack[j] = stack[j - 1];
                            j--;
                        }
                        stack[j] = e;
                    }
            }
        }
        /* Pop the nearest entry still in front of the nearest hit. */
        do {
            if (sp == 0)
                return found;
            sp--;
        } while (stack[sp].dist > *tmax);
        cur = stack[sp].child;
        cur_count = stack[sp].count;
    }
}

#endif

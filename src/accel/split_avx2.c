/* The AVX2 forms of split.c's binning, partitioning and sweeping loops,
 * for CPUs that have AVX2 (split_ctx.avx2): a primref, and a bin's box,
 * are each one 256-bit register, lo in the lower half and -hi in the
 * upper, so a bin takes in a primitive with one minimum, both sides'
 * centre bounds grow with one minimum and one maximum, and a sweep unites
 * boxes with one minimum and costs eight planes at once. The same
 * operations on the same lanes as split.c's loops, so the tree is the same
 * on either (tests/test_mesh.c, avx2_loops_make_the_same_tree). The
 * Makefile compiles this file with the avx2 flags. */
#include "split.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
#include <immintrin.h>

__attribute__((always_inline)) static inline __m256 ref_load(const primref *r)
{
    return _mm256_loadu_ps(r->lo);
}

/* The centre of a primref, as box4_center computes it. */
__attribute__((always_inline)) static inline __m128 ref_centre(__m256 r)
{
    __m128 lo = _mm256_castps256_ps128(r), nhi = _mm256_extractf128_ps(r, 1);
    return _mm_mul_ps(_mm_sub_ps(lo, nhi), _mm_set1_ps(0.5f));
}

/* A bin takes in r: the minimum with its box, and one more in its count
 * (lane 3 of lo). */
__attribute__((always_inline)) static inline void bin_add(float *bin, __m256 r, __m256 one)
{
    _mm256_store_ps(bin, _mm256_add_ps(_mm256_min_ps(_mm256_load_ps(bin), r), one));
}

/* Ranges of at least this many primitives bin the second of each pair
 * into bins of their own, merged at the end: primitives that come in
 * spatial order (a mesh's triangles) fall into the bins of the one before,
 * and each bin would wait for the last one's store. */
#define BIN_TWO_SETS 256

/* Two primitives at a time: their bins worked out in one 256-bit pass
 * (lower half a's, upper half b's), then each bin takes its primitive. */
void split_bin_avx2(const primref *refs, int lo, int hi, v4 cmin, v4 scale, int nb,
                    box4 (*box)[BINS])
{
    const __m256 one = _mm256_setr_ps(0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 0.0f);
    const __m256 half = _mm256_set1_ps(0.5f), zero = _mm256_setzero_ps();
    const __m128 top = _mm_set1_ps((float)(nb - 1));
    const __m256 cmin2 = _mm256_set_m128(cmin, cmin), scale2 = _mm256_set_m128(scale, scale);
    const __m256 top2 = _mm256_set_m128(top, top);
    float *a0 = (float *)(void *)box[0], *a1 = (float *)(void *)box[1];
    float *a2 = (float *)(void *)box[2];
    float other[3][BINS][8] __attribute__((aligned(32)));
    bool two = hi - lo >= BIN_TWO_SETS;
    if (two) {
        const __m256 empty = _mm256_setr_ps(FLT_MAX, FLT_MAX, FLT_MAX, 0.0f, FLT_MAX, FLT_MAX,
                                            FLT_MAX, FLT_MAX);
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < nb; j++)
                _mm256_store_ps(other[a][j], empty);
    }
    float *b0 = two ? other[0][0] : a0, *b1 = two ? other[1][0] : a1;
    float *b2 = two ? other[2][0] : a2;
    int32_t k[8] __attribute__((aligned(32)));
    int i = lo;
    for (; i + 1 < hi; i += 2) {
        __m256 ra = ref_load(&refs[i]), rb = ref_load(&refs[i + 1]);
        __m256 los = _mm256_permute2f128_ps(ra, rb, 0x20);
        __m256 nhis = _mm256_permute2f128_ps(ra, rb, 0x31);
        __m256 c = _mm256_mul_ps(_mm256_sub_ps(los, nhis), half);
        __m256 f = _mm256_mul_ps(_mm256_sub_ps(c, cmin2), scale2);
        f = _mm256_min_ps(_mm256_max_ps(f, zero), top2); /* max gives 0 for NaN */
        /* eight floats a bin */
        _mm256_store_si256((__m256i *)(void *)k, _mm256_slli_epi32(_mm256_cvttps_epi32(f), 3));
        bin_add(a0 + k[0], ra, one);
        bin_add(a1 + k[1], ra, one);
        bin_add(a2 + k[2], ra, one);
        bin_add(b0 + k[4], rb, one);
        bin_add(b1 + k[5], rb, one);
        bin_add(b2 + k[6], rb, one);
    }
    if (i < hi) {
        __m256 r = ref_load(&refs[i]);
        __m128 f = _mm_mul_ps(_mm_sub_ps(ref_centre(r), cmin), scale);
        f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), top);
        _mm_store_si128((__m128i *)(void *)k, _mm_slli_epi32(_mm_cvttps_epi32(f), 3));
        bin_add(a0 + k[0], r, one);
        bin_add(a1 + k[1], r, one);
        bin_add(a2 + k[2], r, one);
    }
    if (two) /* the minima of both, the counts (lane 3) added */
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < nb; j++) {
                float *p = (float *)(void *)&box[a][j];
                __m256 x = _mm256_load_ps(p), y = _mm256_load_ps(other[a][j]);
                _mm256_store_ps(p, _mm256_blend_ps(_mm256_min_ps(x, y), _mm256_add_ps(x, y), 0x08));
            }
}

/* The areas of eight boxes from their extents (x, y, z, any; of either
 * sign), as split.c's area4 computes each. */
__attribute__((always_inline)) static inline __m256 area8(const __m128 *e)
{
    __m256 t0 = _mm256_set_m128(e[4], e[0]), t1 = _mm256_set_m128(e[5], e[1]);
    __m256 t2 = _mm256_set_m128(e[6], e[2]), t3 = _mm256_set_m128(e[7], e[3]);
    __m256 u0 = _mm256_unpacklo_ps(t0, t1), u1 = _mm256_unpacklo_ps(t2, t3);
    __m256 u2 = _mm256_unpackhi_ps(t0, t1), u3 = _mm256_unpackhi_ps(t2, t3);
    __m256 x = _mm256_shuffle_ps(u0, u1, _MM_SHUFFLE(1, 0, 1, 0));
    __m256 y = _mm256_shuffle_ps(u0, u1, _MM_SHUFFLE(3, 2, 3, 2));
    __m256 z = _mm256_shuffle_ps(u2, u3, _MM_SHUFFLE(1, 0, 1, 0));
    __m256 sum = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(x, y), _mm256_mul_ps(y, z)),
                               _mm256_mul_ps(z, x));
    return _mm256_mul_ps(_mm256_set1_ps(2.0f), sum);
}

/* A box [lo | -hi]'s extents, negated: lo - hi. */
__attribute__((always_inline)) static inline __m128 box_nextent(__m256 b)
{
    return _mm_add_ps(_mm256_extractf128_ps(b, 1), _mm256_castps256_ps128(b));
}

void split_sweep_avx2(const box4 *bins, int nb, int n, float raw[BINS])
{
    int m = nb - 1, m8 = (m + 7) & ~7;
    __m128 below[BINS], above[BINS];
    float count[BINS];
    const __m256 big = _mm256_set1_ps(FLT_MAX);
    const float *bin = (const float *)(const void *)bins;
    __m256 acc = big;
    float cnt = 0.0f;
    for (int k = 0; k < m; k++) {
        __m256 b = _mm256_load_ps(bin + 8 * k);
        acc = _mm256_min_ps(acc, b);
        below[k] = box_nextent(acc);
        cnt += bin[8 * k + 3];
        count[k] = cnt;
    }
    acc = big;
    for (int k = m; k > 0; k--) {
        acc = _mm256_min_ps(acc, _mm256_load_ps(bin + 8 * k));
        above[k - 1] = box_nextent(acc);
    }
    for (int k = m; k < m8; k++) { /* no candidates */
        below[k] = above[k] = _mm_set1_ps(INFINITY);
        count[k] = 0.0f;
    }
    const __m256 inf = _mm256_set1_ps(INFINITY), total = _mm256_set1_ps((float)n);
    for (int k = 0; k < m8; k += 8) {
        __m256 lc = _mm256_loadu_ps(&count[k]), rc = _mm256_sub_ps(total, lc);
        __m256 cost = _mm256_add_ps(_mm256_mul_ps(area8(&below[k]), lc),
                                    _mm256_mul_ps(area8(&above[k]), rc));
        cost = _mm256_blendv_ps(cost, inf, _mm256_cmp_ps(cost, cost, _CMP_UNORD_Q));
        __m256 both = _mm256_cmp_ps(_mm256_min_ps(lc, rc), _mm256_setzero_ps(), _CMP_GT_OQ);
        _mm256_storeu_ps(&raw[k], _mm256_blendv_ps(inf, cost, both));
    }
}

/* Both sides' centre bounds: below's in the lower half of min and max,
 * above's in the upper. */
typedef struct part_acc8 {
    __m256 min, max;
    __m128 split;
    int axis;
} part_acc8;

/* split.c's part_side, both sides at once: the centre, in both halves,
 * plus -0 on its own side and +-inf on the other. */
__attribute__((always_inline)) static inline int part_side8(void *acc, const primref *r)
{
#define I_ INFINITY
    static const float add[2][2][8] __attribute__((aligned(32))) = {
        {{I_, I_, I_, I_, -0.f, -0.f, -0.f, -0.f}, {-I_, -I_, -I_, -I_, -0.f, -0.f, -0.f, -0.f}},
        {{-0.f, -0.f, -0.f, -0.f, I_, I_, I_, I_}, {-0.f, -0.f, -0.f, -0.f, -I_, -I_, -I_, -I_}}};
#undef I_
    part_acc8 *p = acc;
    __m128 c = ref_centre(ref_load(r));
    int below = (_mm_movemask_ps(_mm_cmplt_ps(c, p->split)) >> p->axis) & 1;
    __m256 c2 = _mm256_set_m128(c, c);
    p->min = _mm256_min_ps(_mm256_add_ps(c2, _mm256_load_ps(add[below][0])), p->min);
    p->max = _mm256_max_ps(_mm256_add_ps(c2, _mm256_load_ps(add[below][1])), p->max);
    return below;
}

int split_partition_avx2(split_ctx *b, int lo, int hi, int axis, float plane, cbox *below,
                         cbox *above)
{
    part_acc8 p = {_mm256_set1_ps(FLT_MAX), _mm256_set1_ps(-FLT_MAX), _mm_set1_ps(plane), axis};
    int mid = split_partition_by(b->refs, lo, hi, &p, part_side8);
    *below = (cbox){_mm256_castps256_ps128(p.min), _mm256_castps256_ps128(p.max)};
    *above = (cbox){_mm256_extractf128_ps(p.min, 1), _mm256_extractf128_ps(p.max, 1)};
    return mid;
}
#else
typedef int split_avx2_unused; /* not x86-64: no kernels here */
#endif

/* The AVX2 forms of split.c's binning and partitioning loops, for CPUs
 * that have AVX2 (split_ctx.avx2): a primref, and a bin's box, are each
 * one 256-bit register, lo in the lower half and -hi in the upper, so a
 * bin takes in a primitive with one minimum, and both sides' centre
 * bounds grow with one minimum and one maximum. The same operations on
 * the same lanes as split.c's loops, so the tree is the same on either
 * (tests/test_bvh.c builds with both). The Makefile compiles this file
 * with the avx2 flags. */
#include "split.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
#include <immintrin.h>

static inline __m256 ref_load(const primref *r) { return _mm256_loadu_ps(r->lo); }

/* The centre of a primref, as box4_center computes it. */
static inline __m128 ref_centre(__m256 r)
{
    __m128 lo = _mm256_castps256_ps128(r), nhi = _mm256_extractf128_ps(r, 1);
    return _mm_mul_ps(_mm_sub_ps(lo, nhi), _mm_set1_ps(0.5f));
}

/* A bin takes in r: the minimum with its box, and one more in its count
 * (lane 3 of lo). */
static inline void bin_add(float *bin, __m256 r, __m256 one)
{
    _mm256_store_ps(bin, _mm256_add_ps(_mm256_min_ps(_mm256_load_ps(bin), r), one));
}

void split_bin_avx2(const primref *refs, int lo, int hi, v4 cmin, v4 scale, v4 top,
                    box4 (*box)[BINS])
{
    const __m256 one = _mm256_setr_ps(0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 0.0f);
    float *b0 = (float *)(void *)box[0], *b1 = (float *)(void *)box[1];
    float *b2 = (float *)(void *)box[2];
    for (int i = lo; i < hi; i++) {
        __m256 r = ref_load(&refs[i]);
        __m128 f = _mm_mul_ps(_mm_sub_ps(ref_centre(r), cmin), scale);
        f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), top); /* max gives 0 for NaN */
        __m128i k = _mm_slli_epi32(_mm_cvttps_epi32(f), 3);   /* eight floats a bin */
        bin_add(b0 + _mm_cvtsi128_si32(k), r, one);
        bin_add(b1 + _mm_extract_epi32(k, 1), r, one);
        bin_add(b2 + _mm_extract_epi32(k, 2), r, one);
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
static inline int part_side8(void *acc, const primref *r)
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

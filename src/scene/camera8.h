/* camera8: camera_row8 for a pinhole in eight-wide registers, for the
 * translation units compiled with AVX2 (scene_avx2.c, scene_avx512.c):
 * each lane's direction is the scalar loop's to the bit (the same
 * operations in the same order, none fused), and every field of the
 * packet is written in one 32-byte store, which the packet tests' 32-byte
 * loads then take straight from the store (eight 4-byte stores made each
 * such load wait until they reached the cache). */
#ifndef GLINT_SCENE_CAMERA8_H
#define GLINT_SCENE_CAMERA8_H

#include <immintrin.h>
#include <math.h>
#include "scene/camera.h"

static inline int camera_pinhole8(const camera_frame *f, int x0, int n, float fx, float y,
                                  float time, ray8 *p)
{
    __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    lane = _mm256_andnot_si256(_mm256_cmpgt_epi32(lane, _mm256_set1_epi32(n - 1)), lane);
    __m256 x = _mm256_add_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(x0), lane)),
                             _mm256_set1_ps(fx));
    __m256 yy = _mm256_set1_ps(y);
    const float c[3] = {f->corner.x, f->corner.y, f->corner.z};
    const float dx[3] = {f->dx.x, f->dx.y, f->dx.z}, dy[3] = {f->dy.x, f->dy.y, f->dy.z};
    float *dir[3] = {p->dx, p->dy, p->dz};
    for (int a = 0; a < 3; a++)
        _mm256_storeu_ps(dir[a], _mm256_add_ps(_mm256_add_ps(_mm256_set1_ps(c[a]),
                                                             _mm256_mul_ps(_mm256_set1_ps(dx[a]), x)),
                                               _mm256_mul_ps(_mm256_set1_ps(dy[a]), yy)));
    _mm256_storeu_ps(p->ox, _mm256_set1_ps(f->eye.x));
    _mm256_storeu_ps(p->oy, _mm256_set1_ps(f->eye.y));
    _mm256_storeu_ps(p->oz, _mm256_set1_ps(f->eye.z));
    _mm256_storeu_ps(p->tmin, _mm256_setzero_ps());
    _mm256_storeu_ps(p->tmax, _mm256_set1_ps(INFINITY));
    _mm256_storeu_ps(p->time, _mm256_set1_ps(time));
    return (1 << n) - 1;
}

/* Defines camera_pinhole8_<isa>. */
#define CAMERA8_KERNELS(isa)                                                                   \
    int camera_pinhole8_##isa(const camera_frame *f, int x0, int n, float fx, float y,        \
                              float time, ray8 *p)                                             \
    {                                                                                          \
        return camera_pinhole8(f, x0, n, fx, y, time, p);                                      \
    }

#endif

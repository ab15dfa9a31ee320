/* prepare8_texture: the textures the packet kernels look up themselves
 * (shading.h: shade_flat_texture), at the (u, v) of the lanes' quads: a
 * chequer, and an image on (u, v), each texture_eval's floats lane by
 * lane. For translation units compiled with AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_PREPARE8_TEXTURE_H
#define GLINT_TRACE_PREPARE8_TEXTURE_H

#include "shade/pattern.h"
#include "trace/prepare8_read.h"

/* What prepare8_checker reads of a material's chequer: its scale and
 * offset, and its colours at 0 and at 1 (color_map_eval). */
typedef struct prepare8_chequer {
    float scale[3], offset[3], even[3], odd[3];
} prepare8_chequer;

/* texture_eval of each lane's flat chequer (shading.h: shade_flat_texture)
 * at its quad's (u, v) = (b1, b2), into the lanes of tex whose materials
 * (groups mg) have one; false, tex untouched, where none has.
 * The parity of the squares in whole numbers where the three coordinates
 * are below 2^24 (every float from there up is even), as pattern_checker
 * finds it; otherwise by pattern_checker itself. */
__attribute__((always_inline)) static inline bool
prepare8_checker(const scene *s, const prepare8_groups *mg, __m256 b1, __m256 b2, __m256 tex[3])
{
    prepare8_chequer c[8];
    const char *at[8];
    int textured = 0;
    for (int i = 0; i < mg->n; i++) {
        const material *m = (const material *)(const void *)mg->at[i];
        at[i] = (const char *)&c[i];
        memset(&c[i], 0, sizeof c[i]);
        if (m->texture < 0 || s->textures[m->texture].kind != TEXTURE_CHECKER)
            continue;
        const texture *t = &s->textures[m->texture];
        vec3 e = color_map_eval(&t->pattern.map, 0.0f), f = color_map_eval(&t->pattern.map, 1.0f);
        for (int j = 0; j < 3; j++) {
            c[i].scale[j] = v3_at(t->scale, j), c[i].offset[j] = v3_at(t->offset, j);
            c[i].even[j] = v3_at(e, j), c[i].odd[j] = v3_at(f, j);
        }
        textured |= mg->bits[i];
    }
    if (!textured)
        return false;
    __m256 src[3] = {b1, b2, _mm256_setzero_ps()}, q[3];
    __m256i sum = _mm256_setzero_si256();
    __m256 small = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    for (int j = 0; j < 3; j++) {
        size_t k = (size_t)j * sizeof(float);
        q[j] = _mm256_add_ps(
            _mm256_mul_ps(src[j], prepare8_read(mg, at, offsetof(prepare8_chequer, scale) + k)),
            prepare8_read(mg, at, offsetof(prepare8_chequer, offset) + k));
        sum = _mm256_add_epi32(sum, _mm256_cvttps_epi32(_mm256_floor_ps(q[j])));
        small = _mm256_and_ps(
            small, _mm256_cmp_ps(_mm256_and_ps(q[j], abs), _mm256_set1_ps(0x1p24f), _CMP_LT_OQ));
    }
    __m256 odd = _mm256_castsi256_ps(
        _mm256_cmpeq_epi32(_mm256_and_si256(sum, _mm256_set1_epi32(1)), _mm256_set1_epi32(1)));
    int far = textured & ~_mm256_movemask_ps(small);
    if (far) { /* pattern_checker, lane by lane */
        float qs[3][8];
        int32_t o[8];
        for (int j = 0; j < 3; j++)
            _mm256_storeu_ps(qs[j], q[j]);
        _mm256_storeu_si256((__m256i *)(void *)o, _mm256_castps_si256(odd));
        for (int m = far; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            o[k] = pattern_checker(v3(qs[0][k], qs[1][k], qs[2][k]), false) != 0.0f ? -1 : 0;
        }
        odd = _mm256_castsi256_ps(_mm256_loadu_si256((const __m256i *)(const void *)o));
    }
    __m256 has = packet_lanes(textured);
    for (int j = 0; j < 3; j++) {
        size_t k = (size_t)j * sizeof(float);
        __m256 col =
            _mm256_blendv_ps(prepare8_read(mg, at, offsetof(prepare8_chequer, even) + k),
                             prepare8_read(mg, at, offsetof(prepare8_chequer, odd) + k), odd);
        tex[j] = _mm256_blendv_ps(tex[j], col, has);
    }
    return true;
}

/* wrap_index for texel indices i that lie from -1 to n (those of
 * image_bilinear below, whose coordinates start in [0, 1] when they
 * repeat). */
__attribute__((always_inline)) static inline __m256i prepare8_wrap(__m256i i, int n, texture_wrap w)
{
    __m256i top = _mm256_set1_epi32(n - 1);
    if (w == WRAP_CLAMP)
        return _mm256_min_epi32(_mm256_max_epi32(i, _mm256_setzero_si256()), top);
    __m256i below = _mm256_cmpgt_epi32(_mm256_setzero_si256(), i);
    __m256i above = _mm256_cmpgt_epi32(i, top);
    i = _mm256_add_epi32(i, _mm256_and_si256(below, _mm256_set1_epi32(n)));
    return _mm256_sub_epi32(i, _mm256_and_si256(above, _mm256_set1_epi32(n)));
}

/* The texels (xs[j], ys[j]) of image img for the lanes of `lanes`, their
 * components into c[j], as texture.c's texel reads each (0 in the other
 * lanes). */
static inline void prepare8_texels(const image *img, const float decode[256], int lanes,
                                   const __m256i xs[4], const __m256i ys[4], __m256 c[4][3])
{
    int32_t x[4][8], y[4][8];
    float f[4][3][8] = {{{0}}};
    for (int j = 0; j < 4; j++) {
        _mm256_storeu_si256((__m256i *)(void *)x[j], xs[j]);
        _mm256_storeu_si256((__m256i *)(void *)y[j], ys[j]);
    }
    for (int m = lanes; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        for (int j = 0; j < 4; j++) {
            size_t at = ((size_t)y[j][k] * (size_t)img->width + (size_t)x[j][k]) * 3;
            for (int i = 0; i < 3; i++)
                f[j][i][k] =
                    img->linear ? img->linear[at + (size_t)i] : decode[img->rgb[at + (size_t)i]];
        }
    }
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 3; i++)
            c[j][i] = _mm256_loadu_ps(f[j][i]);
}

/* v3_lerp lane by lane: a (1 - t) + b t. */
__attribute__((always_inline)) static inline void
prepare8_lerp(const __m256 a[3], const __m256 b[3], __m256 t, __m256 out[3])
{
    __m256 s = _mm256_sub_ps(_mm256_set1_ps(1.0f), t);
    for (int i = 0; i < 3; i++)
        out[i] = _mm256_add_ps(_mm256_mul_ps(a[i], s), _mm256_mul_ps(b[i], t));
}

/* texture_eval of image texture t (shade_flat_texture) at the (u, v) =
 * (b1, b2) of the lanes of `lanes`, into those lanes of tex: the
 * coordinates scaled and moved, then image_bilinear's steps. */
static inline void prepare8_image(const scene *s, const float decode[256], const texture *t,
                                  int lanes, __m256 b1, __m256 b2, __m256 tex[3])
{
    const image *img = &s->images[t->image.image];
    const struct image_texture *it = &t->image;
    __m256 u =
        _mm256_add_ps(_mm256_mul_ps(b1, _mm256_set1_ps(t->scale.x)), _mm256_set1_ps(t->offset.x));
    __m256 v =
        _mm256_add_ps(_mm256_mul_ps(b2, _mm256_set1_ps(t->scale.y)), _mm256_set1_ps(t->offset.y));
    if (it->wrap_u == WRAP_REPEAT)
        u = _mm256_sub_ps(u, _mm256_floor_ps(u));
    if (it->wrap_v == WRAP_REPEAT)
        v = _mm256_sub_ps(v, _mm256_floor_ps(v));
    const __m256 half = _mm256_set1_ps(0.5f);
    __m256 x = _mm256_sub_ps(_mm256_mul_ps(u, _mm256_set1_ps((float)img->width)), half);
    __m256 y = _mm256_sub_ps(
        _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f), v), _mm256_set1_ps((float)img->height)),
        half);
    __m256 fx = _mm256_floor_ps(x), fy = _mm256_floor_ps(y);
    __m256 ax = _mm256_sub_ps(x, fx), ay = _mm256_sub_ps(y, fy);
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)),
                 big = _mm256_set1_ps(1e9f);
    __m256 ok = _mm256_and_ps(_mm256_cmp_ps(_mm256_and_ps(fx, abs), big, _CMP_LT_OQ),
                              _mm256_cmp_ps(_mm256_and_ps(fy, abs), big, _CMP_LT_OQ));
    /* the others' texel (0, 0), as image_bilinear returns it */
    __m256i x0 = _mm256_cvttps_epi32(_mm256_and_ps(fx, ok));
    __m256i y0 = _mm256_cvttps_epi32(_mm256_and_ps(fy, ok));
    __m256i one = _mm256_set1_epi32(1), oki = _mm256_castps_si256(ok);
    __m256i xa = _mm256_and_si256(prepare8_wrap(x0, img->width, it->wrap_u), oki);
    __m256i xb =
        _mm256_and_si256(prepare8_wrap(_mm256_add_epi32(x0, one), img->width, it->wrap_u), oki);
    __m256i ya = _mm256_and_si256(prepare8_wrap(y0, img->height, it->wrap_v), oki);
    __m256i yb =
        _mm256_and_si256(prepare8_wrap(_mm256_add_epi32(y0, one), img->height, it->wrap_v), oki);
    __m256 c[4][3], top[3], bot[3], r[3];
    const __m256i xs[4] = {xa, xb, xa, xb}, ys[4] = {ya, ya, yb, yb};
    prepare8_texels(img, decode, lanes, xs, ys, c);
    prepare8_lerp(c[0], c[1], ax, top);
    prepare8_lerp(c[2], c[3], ax, bot);
    prepare8_lerp(top, bot, ay, r);
    __m256 put = _mm256_and_ps(packet_lanes(lanes), ok), first = packet_lanes(lanes);
    for (int i = 0; i < 3; i++)
        tex[i] = _mm256_blendv_ps(tex[i], _mm256_blendv_ps(c[0][i], r[i], put), first);
}

/* The textures of the lanes whose materials (groups mg) have one that the
 * kernels look up, at their quads' (u, v) = (b1, b2), into tex, 1 in the
 * other lanes; false where no lane's material has one. */
__attribute__((always_inline)) static inline bool
prepare8_texture(const scene *s, const float decode[256], const prepare8_groups *mg, __m256 b1,
                 __m256 b2, __m256 tex[3])
{
    for (int i = 0; i < 3; i++)
        tex[i] = _mm256_set1_ps(1.0f);
    bool any = prepare8_checker(s, mg, b1, b2, tex);
    for (int i = 0; i < mg->n; i++) {
        const material *m = (const material *)(const void *)mg->at[i];
        if (m->texture >= 0 && s->textures[m->texture].kind == TEXTURE_IMAGE) {
            prepare8_image(s, decode, &s->textures[m->texture], mg->bits[i], b1, b2, tex);
            any = true;
        }
    }
    return any;
}

#endif

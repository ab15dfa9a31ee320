#include "texture.h"

#include <math.h>

texture texture_image(int img)
{
    return (texture){.kind = TEXTURE_IMAGE, .image = img, .scale_u = 1.0f, .scale_v = 1.0f};
}

texture texture_checker(vec3 even, vec3 odd, float nu, float nv)
{
    return (texture){.kind = TEXTURE_CHECKER, .even = even, .odd = odd, .scale_u = nu,
                     .scale_v = nv};
}

/* Texel index for continuous coordinate x (in texels, centres at i + 0.5). */
static int wrap_index(int i, int n, texture_wrap w)
{
    switch (w) {
    case WRAP_REPEAT:
        i %= n;
        return i < 0 ? i + n : i;
    case WRAP_CLAMP:
        return i < 0 ? 0 : i >= n ? n - 1 : i;
    }
    return 0;
}

static vec3 texel(const image *img, const float decode[256], int x, int y)
{
    if (img->linear) { /* HDR texels are linear already */
        const float *f = img->linear + ((size_t)y * (size_t)img->width + (size_t)x) * 3;
        return v3(f[0], f[1], f[2]);
    }
    const uint8_t *p = img->rgb + ((size_t)y * (size_t)img->width + (size_t)x) * 3;
    return v3(decode[p[0]], decode[p[1]], decode[p[2]]);
}

static vec3 image_bilinear(const texture *t, const image *img, const float decode[256], float u,
                           float v)
{
    float x = u * (float)img->width - 0.5f;
    float y = (1.0f - v) * (float)img->height - 0.5f;
    float fx = floorf(x), fy = floorf(y);
    float ax = x - fx, ay = y - fy;
    if (!(fabsf(fx) < 1e9f && fabsf(fy) < 1e9f))
        return texel(img, decode, 0, 0);
    int x0 = (int)fx, y0 = (int)fy;
    int xa = wrap_index(x0, img->width, t->wrap_u), xb = wrap_index(x0 + 1, img->width, t->wrap_u);
    int ya = wrap_index(y0, img->height, t->wrap_v), yb = wrap_index(y0 + 1, img->height, t->wrap_v);
    vec3 top = v3_lerp(texel(img, decode, xa, ya), texel(img, decode, xb, ya), ax);
    vec3 bot = v3_lerp(texel(img, decode, xa, yb), texel(img, decode, xb, yb), ax);
    return v3_lerp(top, bot, ay);
}

vec3 texture_eval(const texture *t, const image *images, const float decode[256], float u,
                  float v)
{
    u = u * t->scale_u + t->offset_u;
    v = v * t->scale_v + t->offset_v;
    switch (t->kind) {
    case TEXTURE_IMAGE: {
        const image *img = &images[t->image];
        if (t->wrap_u == WRAP_REPEAT)
            u -= floorf(u);
        if (t->wrap_v == WRAP_REPEAT)
            v -= floorf(v);
        return image_bilinear(t, img, decode, u, v);
    }
    case TEXTURE_CHECKER: {
        double s = floor((double)u) + floor((double)v);
        return fmod(fabs(s), 2.0) < 0.5 ? t->even : t->odd;
    }
    }
    return v3s(1.0f);
}

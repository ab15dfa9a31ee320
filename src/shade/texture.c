#include "texture.h"

#include <math.h>

static const color_map black_to_white = {2, {0.0f, 1.0f}, {{0, 0, 0}, {1, 1, 1}}};

texture texture_image(int img)
{
    return (texture){.kind = TEXTURE_IMAGE, .space = SPACE_UV, .scale = v3s(1.0f),
                     .image = {.image = img, .mapping = MAPPING_UV, .axis = 2}};
}

texture texture_checker(vec3 even, vec3 odd, float nu, float nv)
{
    return (texture){.kind = TEXTURE_CHECKER, .space = SPACE_UV, .scale = v3(nu, nv, 1.0f),
                     .pattern = {.map = {2, {0.0f, 1.0f}, {even, odd}},
                                 .noise = {6, 2.0f, 0.5f, 0.0f}}};
}

/* How much turbulence bends marble and wood unless told. */
#define MARBLE_TURBULENCE 5.0f
#define WOOD_TURBULENCE 0.6f

texture texture_pattern(texture_kind kind)
{
    float amount = kind == TEXTURE_MARBLE ? MARBLE_TURBULENCE
                   : kind == TEXTURE_WOOD ? WOOD_TURBULENCE
                                          : 0.0f;
    return (texture){.kind = kind, .space = SPACE_OBJECT, .scale = v3s(1.0f),
                     .pattern = {.map = black_to_white, .noise = {6, 2.0f, 0.5f, amount}}};
}

vec3 color_map_eval(const color_map *m, float x)
{
    if (!(x > m->at[0]))
        return m->color[0];
    for (int i = 1; i < m->n; i++) {
        if (x > m->at[i])
            continue;
        float span = m->at[i] - m->at[i - 1];
        float t = span > 0.0f ? (x - m->at[i - 1]) / span : 1.0f;
        return v3_lerp(m->color[i - 1], m->color[i], t);
    }
    return m->color[m->n - 1];
}

void texture_map(texture_mapping m, int axis, vec3 q, vec3 n, float *u, float *v)
{
    switch (m) {
    case MAPPING_UV:
        *u = q.x;
        *v = q.y;
        return;
    case MAPPING_PLANAR: /* along the axis, seen from its positive side */
        *u = axis == 0 ? 0.5f - q.z : q.x + 0.5f;
        *v = axis == 1 ? 0.5f - q.z : q.y + 0.5f;
        return;
    case MAPPING_SPHERICAL: {
        float r = v3_len(q);
        float s = r > 0.0f ? q.y / r : 0.0f;
        *u = 0.5f + atan2f(q.x, q.z) * (float)(0.5 / M_PI);
        *v = 0.5f + asinf(s < -1.0f ? -1.0f : s > 1.0f ? 1.0f : s) * (float)(1.0 / M_PI);
        return;
    }
    case MAPPING_CYLINDRICAL:
        *u = 0.5f + atan2f(q.x, q.z) * (float)(0.5 / M_PI);
        *v = q.y + 0.5f;
        return;
    case MAPPING_BOX: {
        vec3 a = v3(fabsf(n.x), fabsf(n.y), fabsf(n.z));
        axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
        float side = v3_at(n, axis) < 0.0f ? -1.0f : 1.0f;
        /* Each face seen from outside, upright (the top and bottom with
         * -z and +z up). */
        if (axis == 0) {
            *u = 0.5f - side * q.z;
            *v = q.y + 0.5f;
        } else if (axis == 1) {
            *u = q.x + 0.5f;
            *v = 0.5f - side * q.z;
        } else {
            *u = 0.5f + side * q.x;
            *v = q.y + 0.5f;
        }
        return;
    }
    }
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

static vec3 image_bilinear(const struct image_texture *t, const image *img,
                           const float decode[256], float u, float v)
{
    if (t->wrap_u == WRAP_REPEAT)
        u -= floorf(u);
    if (t->wrap_v == WRAP_REPEAT)
        v -= floorf(v);
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

/* Steps 2 and 3 of texture.h: source point c (normal n) to q'. */
static vec3 texture_coords(const texture *t, vec3 c, vec3 n)
{
    vec3 q = t->has_xform ? mat4_point(&t->xf.inv, c) : c;
    if (t->kind == TEXTURE_IMAGE && t->image.mapping != MAPPING_UV) {
        /* Normals go into texture space through the inverse transpose of
         * inv, which is fwd transposed. */
        mat4 ft = mat4_transpose(&t->xf.fwd);
        vec3 nq = t->has_xform ? mat4_vector(&ft, n) : n;
        float u = 0.0f, v = 0.0f;
        texture_map(t->image.mapping, t->image.axis, q, nq, &u, &v);
        q = v3(u, v, 0.0f);
    }
    return v3_add(v3_mul(q, t->scale), t->offset);
}

/* The texture at q': its colour, and its value in *value. The one switch
 * over the kinds. */
static vec3 lookup(const texture *t, const image *images, const float decode[256], vec3 q,
                   float *value)
{
    const pattern_noise *pn = &t->pattern.noise;
    bool solid = t->space != SPACE_UV;
    float x = 0.0f;
    switch (t->kind) {
    case TEXTURE_IMAGE: {
        vec3 c = image_bilinear(&t->image, &images[t->image.image], decode, q.x, q.y);
        *value = 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
        return c;
    }
    case TEXTURE_CHECKER:
        x = pattern_checker(q, solid);
        break;
    case TEXTURE_STRIPES:
        x = pattern_stripes(q, solid);
        break;
    case TEXTURE_RINGS:
        x = pattern_rings(q, solid);
        break;
    case TEXTURE_GRADIENT:
        x = pattern_gradient(q);
        break;
    case TEXTURE_NOISE:
        x = pattern_noise_value(q);
        break;
    case TEXTURE_TURBULENCE:
        x = pattern_turbulence(q, pn);
        break;
    case TEXTURE_MARBLE:
        x = pattern_marble(q, pn);
        break;
    case TEXTURE_WOOD:
        x = pattern_wood(q, pn);
        break;
    case TEXTURE_KIND_COUNT:
        break;
    }
    *value = x;
    return color_map_eval(&t->pattern.map, x);
}

static vec3 source_point(const texture *t, const texture_point *tp)
{
    return t->space == SPACE_UV ? v3(tp->u, tp->v, 0.0f) : tp->p;
}

vec3 texture_eval(const texture *t, const image *images, const float decode[256],
                  const texture_point *tp)
{
    float value;
    return lookup(t, images, decode, texture_coords(t, source_point(t, tp), tp->n), &value);
}

float texture_value(const texture *t, const image *images, const float decode[256],
                    const texture_point *tp)
{
    float value;
    lookup(t, images, decode, texture_coords(t, source_point(t, tp), tp->n), &value);
    return value;
}

/* The step for differences in source space: 1e-3 of a pattern unit (of
 * an image in (u, v)), from how much the transform and scale magnify. */
static float gradient_step(const texture *t)
{
    float gain = v3_max_abs(t->scale);
    if (t->has_xform) {
        float g = 0.0f;
        for (int i = 0; i < 3; i++)
            g = maxf(g, v3_len(v3(t->xf.inv.m[i][0], t->xf.inv.m[i][1], t->xf.inv.m[i][2])));
        gain *= g;
    }
    return gain > 0.0f && isfinite(gain) ? 1e-3f / gain : 1e-3f;
}

vec3 texture_gradient(const texture *t, const image *images, const float decode[256],
                      const texture_point *tp)
{
    float h = gradient_step(t), g[3];
    for (int i = 0; i < 3; i++) {
        vec3 e = v3(i == 0 ? h : 0.0f, i == 1 ? h : 0.0f, i == 2 ? h : 0.0f);
        float hi, lo;
        lookup(t, images, decode, texture_coords(t, v3_add(tp->p, e), tp->n), &hi);
        lookup(t, images, decode, texture_coords(t, v3_sub(tp->p, e), tp->n), &lo);
        g[i] = (hi - lo) / (2.0f * h);
    }
    return v3(g[0], g[1], g[2]);
}

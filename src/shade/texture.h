/* texture: colour (and a scalar value, for bump mapping) as a function of
 * where a surface point is. A closed enum + union: one image kind and the
 * procedural patterns of pattern.h, dispatched by one switch (texture.c).
 *
 * Where the lookup happens, in three steps:
 *
 * 1. The source point c. In `uv` space it is (u, v, 0), the shape's own
 *    surface coordinates. In `object` space it is the point in the shape's
 *    own coordinates (before its transform) measured from the centre of the
 *    shape's bounds (a plane's point for planes), so a texture moves and
 *    turns with its object and a spherical map is centred on its sphere. In
 *    `world` space it is the world point.
 * 2. The texture's own transform, if any, places the pattern:
 *    q = transform^-1 c. An image in object or world space is then projected
 *    to (u, v, 0) by its mapping:
 *      planar       along an axis: z (u = x + 1/2, v = y + 1/2), y (u = x +
 *                   1/2, v = 1/2 - z) or x (u = 1/2 - z, v = y + 1/2): the
 *                   image's centre at the origin, one image per unit
 *      spherical    longitude and latitude round the origin, as the sphere's
 *                   own (u, v): u = 1/2 + atan2(x, z) / 2 pi,
 *                   v = 1/2 + asin(y / |q|) / pi
 *      cylindrical  u as spherical, v = y + 1/2
 *      box          planar on the face the normal points most along, each
 *                   face seen from outside the right way up
 * 3. Scale and offset, last: q' = q * scale + offset per component. Scale is
 *    a frequency: 2 repeats an image twice per unit of u, or makes a
 *    pattern's cells half as big.
 *
 * Images are sampled bilinearly at (q'.x, q'.y) with v = 0 the bottom row,
 * repeating or clamping per axis; their value is their luminance. Patterns
 * give a value in [0, 1] at q', turned into a colour by the colour map:
 * stops (at_i, color_i) with at ascending, linear between stops, the end
 * colours beyond them. */
#ifndef GLINT_SHADE_TEXTURE_H
#define GLINT_SHADE_TEXTURE_H

#include <stdbool.h>
#include "core/mat4.h"
#include "core/vec3.h"
#include "io/image.h"
#include "shade/pattern.h"

typedef enum texture_kind {
    TEXTURE_IMAGE,
    TEXTURE_CHECKER,
    TEXTURE_STRIPES,
    TEXTURE_RINGS,
    TEXTURE_GRADIENT,
    TEXTURE_NOISE,
    TEXTURE_TURBULENCE,
    TEXTURE_MARBLE,
    TEXTURE_WOOD,
    TEXTURE_KIND_COUNT
} texture_kind;

typedef enum texture_space {
    SPACE_UV,
    SPACE_OBJECT,
    SPACE_WORLD,
} texture_space;

typedef enum texture_mapping {
    MAPPING_UV, /* the surface's (u, v): the only mapping in uv space */
    MAPPING_PLANAR,
    MAPPING_SPHERICAL,
    MAPPING_CYLINDRICAL,
    MAPPING_BOX,
} texture_mapping;

typedef enum texture_wrap {
    WRAP_REPEAT,
    WRAP_CLAMP,
} texture_wrap;

#define COLOR_MAP_MAX 16

typedef struct color_map {
    int n; /* 1 to COLOR_MAP_MAX stops */
    float at[COLOR_MAP_MAX];
    vec3 color[COLOR_MAP_MAX];
} color_map;

struct image_texture {
    int image; /* index into the scene's images */
    texture_mapping mapping;
    int axis; /* planar: 0 x, 1 y, 2 z */
    texture_wrap wrap_u, wrap_v;
};

struct pattern_texture {
    color_map map;
    pattern_noise noise;
};

typedef struct texture {
    texture_kind kind;
    texture_space space;
    vec3 scale, offset; /* in uv space and for images only x and y count */
    bool has_xform;
    xform xf; /* texture -> source space; inv takes c to q */
    union {
        struct image_texture image;
        struct pattern_texture pattern; /* every kind but TEXTURE_IMAGE */
    };
} texture;

/* An image texture on (u, v), scale 1, offset 0, repeating. */
texture texture_image(int image);
/* A chequer with nu x nv squares over the unit (u, v) square, even at 0
 * and odd at 1 in its colour map. */
texture texture_checker(vec3 even, vec3 odd, float nu, float nv);
/* A pattern of kind (not TEXTURE_IMAGE) in object space with a black to
 * white colour map, scale 1 and the default noise parameters (turbulence 5
 * for marble, 0.6 for wood, else 0). */
texture texture_pattern(texture_kind kind);

/* Where a texture is looked up: the point and normal in the texture's
 * source space (object or world, as texture_space says; unused in uv
 * space) and the surface's (u, v). The normal need not be unit. */
typedef struct texture_point {
    vec3 p, n;
    float u, v;
} texture_point;

/* decode maps stored 8-bit image values to the values used in shading. */
vec3 texture_eval(const texture *t, const image *images, const float decode[256],
                  const texture_point *tp);
/* The scalar the texture gives at the point: a pattern's value before the
 * colour map, an image's luminance. */
float texture_value(const texture *t, const image *images, const float decode[256],
                    const texture_point *tp);
/* The gradient of texture_value with respect to the source point, by
 * central differences (for bump mapping; not in uv space). */
vec3 texture_gradient(const texture *t, const image *images, const float decode[256],
                      const texture_point *tp);

/* The colour map at value x. */
vec3 color_map_eval(const color_map *m, float x);

/* (u, v) of texture-space point q with normal n under a mapping other than
 * MAPPING_UV (axis: planar only). */
void texture_map(texture_mapping m, int axis, vec3 q, vec3 n, float *u, float *v);

#endif

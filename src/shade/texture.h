/* texture: colour as a function of surface coordinates (u, v). Image
 * textures sample a picture bilinearly; the chequer alternates two colours.
 * (u, v) first pass through the texture's scale and offset:
 *   u' = u * scale_u + offset_u, v' = v * scale_v + offset_v
 * and each axis then repeats or clamps. v' = 0 is the bottom of an image. */
#ifndef GLINT_SHADE_TEXTURE_H
#define GLINT_SHADE_TEXTURE_H

#include "core/vec3.h"
#include "io/image.h"

typedef enum texture_kind {
    TEXTURE_IMAGE,
    TEXTURE_CHECKER,
} texture_kind;

typedef enum texture_wrap {
    WRAP_REPEAT,
    WRAP_CLAMP,
} texture_wrap;

typedef struct texture {
    texture_kind kind;
    int image;       /* TEXTURE_IMAGE: index into the scene's images */
    vec3 even, odd;  /* TEXTURE_CHECKER: colours of the two kinds of square */
    float scale_u, scale_v, offset_u, offset_v;
    texture_wrap wrap_u, wrap_v;
} texture;

texture texture_image(int image);
/* A chequer with nu x nv squares over the unit (u, v) square. */
texture texture_checker(vec3 even, vec3 odd, float nu, float nv);

/* decode maps stored 8-bit image values to the values used in shading. */
vec3 texture_eval(const texture *t, const image *images, const float decode[256], float u,
                  float v);

#endif

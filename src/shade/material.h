/* material: how a surface answers light, in the Whitted model.
 *
 *   local  = (ambient * scene ambient + sum over lights of diffuse * max(0, n.l)
 *             * light * shadow) * base * (1 - transmit)
 *   + sum over lights of specular * max(0, r.v)^shininess * light * shadow
 *   + emission
 *   + kr * (reflected ray) + kt * tint * (transmitted ray)
 *
 * base = color, times the texture when there is one; n is the shading
 * normal, tilted by the bump pattern when there is one. Only transmission
 * takes light from the local colour; reflection adds on top, as in POV-Ray.
 * The highlight has the light's colour, not the surface's. Surfaces are
 * two-sided: n faces the incoming ray. A light with several samples (an
 * area light) adds each sample's share. kr = reflect and kt = transmit,
 * except that with ior != 1 and fresnel on, Fresnel moves a share of kt to
 * kr (all of it under total internal reflection, fresnel on or off).
 * transmit with ior == 1 is plain transparency: the ray goes on undeviated.
 * With ior != 1 the transmitted ray refracts by Snell's law and the split
 * follows Fresnel (Schlick's approximation). Inside a transmitting object
 * light fades by Beer-Lambert's law, exp(-absorption * distance) per
 * channel, along rays and shadow rays. Shadow rays pass through any
 * transmitting surface, filtered by transmit * tint at each crossing. */
#ifndef GLINT_SHADE_MATERIAL_H
#define GLINT_SHADE_MATERIAL_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>
#include "core/vec3.h"

typedef struct material {
    vec3 color;
    int texture; /* index into the scene's textures, or -1 */
    float ambient, diffuse, specular, shininess;
    float reflect, transmit, ior;
    vec3 tint;
    vec3 absorption; /* per unit length inside; 0: clear */
    vec3 emission;   /* light of its own, added unlit */
    bool fresnel;    /* false: reflect and transmit are used as given */
    int bump;        /* index into the scene's textures (not in uv space), or -1 */
    float bump_strength;
} material;

/* Whether shading this material may read the surface's (u, v) (its
 * texture or its bump pattern, in uv space or not); when not,
 * scene_surface may skip computing them. Whatever reads (u, v) in shading
 * must be named here. */
static inline bool material_uses_uv(const material *m) { return m->texture >= 0 || m->bump >= 0; }

/* The highlight's max(0, r.v)^shininess for r.v = x > 0. A whole
 * shininess from 1 to 2^16 (as scenes give it) by repeated squaring, one
 * product per bit of n: within n ulps of x^n relative to it, and without
 * powf's call, which cost the built-in scene 2-5% of its time; any other
 * by powf. Below 2^e, x^n is below 2^(e n), and from 2^-152 down powf
 * gives +0 (half the least subnormal is 2^-150); so does this, without
 * powf's slowest calls, those that underflow. The light kernels
 * (trace/light8.h) take the same steps eight lanes at once. */
static inline float material_highlight(float x, float n)
{
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    float e = (float)((int)(bits >> 23 & 0xffu) - 126); /* x < 2^e */
    if (e * n <= -152.0f)
        return 0.0f;
    if (n >= 1.0f && n <= 65536.0f && n == (float)(int)n) {
        float r = 1.0f, b = x;
        for (int k = (int)n;; b *= b) {
            if (k & 1)
                r *= b;
            if (!(k >>= 1))
                return r;
        }
    }
    return powf(x, n);
}

/* Matte white: ambient 1, diffuse 1, specular 0, no reflection or
 * transmission, no absorption or emission, Fresnel on, no bump. */
material material_default(void);

/* Whether the material absorbs (some absorption component is > 0). */
static inline bool material_absorbs(const material *m)
{
    return m->absorption.x > 0.0f || m->absorption.y > 0.0f || m->absorption.z > 0.0f;
}

#endif

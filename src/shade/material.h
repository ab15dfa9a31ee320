/* material: how a surface answers light, in the Whitted model.
 *
 *   local  = (ambient * scene ambient + sum over lights of diffuse * max(0, n.l)
 *             * light * shadow) * base * (1 - transmit, at least 0)
 *   + sum over lights of specular * max(0, r.v)^shininess * light * shadow
 *   + reflect * (reflected ray) + transmit * tint * (transmitted ray)
 *
 * Reflection adds on top of the local colour (as in POV-Ray); transmission
 * takes its share from it. base = color, times the texture when there is
 * one. transmit with ior == 1 is plain transparency: the ray goes on
 * undeviated. With ior != 1 the
 * transmitted ray refracts by Snell's law and the split between reflection
 * and transmission follows Fresnel (Schlick's approximation); under total
 * internal reflection all of it reflects. Shadow rays pass through any
 * transmitting surface, filtered by transmit * tint at each crossing. */
#ifndef GLINT_SHADE_MATERIAL_H
#define GLINT_SHADE_MATERIAL_H

#include "core/vec3.h"

typedef struct material {
    vec3 color;
    int texture; /* index into the scene's textures, or -1 */
    float ambient, diffuse, specular, shininess;
    float reflect, transmit, ior;
    vec3 tint;
} material;

/* Matte white: ambient 1, diffuse 1, specular 0, no reflection or transmission. */
material material_default(void);

#endif

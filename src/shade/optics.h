/* optics: directions of reflected and refracted rays, and the Fresnel
 * reflectance that splits light between them. All directions are unit. */
#ifndef GLINT_SHADE_OPTICS_H
#define GLINT_SHADE_OPTICS_H

#include <math.h>
#include <stdbool.h>
#include "core/vec3.h"

/* Refraction of unit incident direction d at unit normal n facing against
 * d (d.n < 0), eta = n_incident / n_transmitted (Snell's law in vector form,
 * Glassner, "An Introduction to Ray Tracing", 1989, ch. 4). Returns false
 * under total internal reflection. */
static inline bool optics_refract(vec3 d, vec3 n, float eta, vec3 *out)
{
    float cosi = -v3_dot(d, n);
    float k = 1.0f - eta * eta * (1.0f - cosi * cosi);
    if (k < 0.0f)
        return false;
    *out = v3_madd(v3_scale(d, eta), n, eta * cosi - sqrtf(k));
    return true;
}

/* Schlick's approximation of Fresnel reflectance ("An Inexpensive BRDF
 * Model for Physically-based Rendering", 1994), for the cosine on the side
 * of the denser medium's lower cosine: cos_i if entering, cos_t if leaving. */
static inline float optics_schlick(float cosine, float n1, float n2)
{
    float r0 = (n1 - n2) / (n1 + n2);
    r0 *= r0;
    float m = 1.0f - cosine;
    float m2 = m * m;
    return r0 + (1.0f - r0) * m2 * m2 * m;
}

#endif

/* fog: light scattered and absorbed by the air along every camera,
 * reflected and refracted ray (not shadow rays), the background included.
 * A segment of length t from o along unit direction d keeps a fraction T of
 * what lies at its end and takes 1 - T of the fog's colour:
 *
 *   seen = T * c + (1 - T) * fog.color
 *
 * T comes from the fog's distance D along the segment. Without height
 * fall-off D = t. With height_falloff h > 0 the air thins upwards as
 * exp(-h y) (ground fog, as thick as given at y = 0), and D is the
 * integral of exp(-h y) along the segment:
 *
 *   D = exp(-h o.y) * t * (1 - exp(-h d.y t)) / (h d.y t)
 *
 * (the last factor is 1 when d.y = 0), so a ray climbing out of the fog
 * meets only a finite amount of it even when it never hits anything.
 *
 *   exponential  T = exp(-density D)
 *   linear       T = (end - D) / (end - start), clamped to [0, 1]: clear up
 *                to start, opaque from end
 *   none         T = 1 */
#ifndef GLINT_SHADE_FOG_H
#define GLINT_SHADE_FOG_H

#include "core/vec3.h"

typedef enum fog_kind {
    FOG_NONE,
    FOG_EXPONENTIAL,
    FOG_LINEAR,
} fog_kind;

typedef struct fog {
    fog_kind kind;
    vec3 color;
    float density;        /* exponential: per unit length, > 0 */
    float start, end;     /* linear: 0 <= start < end */
    float height_falloff; /* >= 0; 0: the same at every height */
} fog;

/* The fog's distance D along the segment from o, unit direction d, length t
 * (INFINITY for a ray that hits nothing). */
float fog_distance(const fog *f, vec3 o, vec3 d, float t);

/* The fraction T of light that crosses the segment. */
float fog_transmittance(const fog *f, vec3 o, vec3 d, float t);

/* What is seen of colour c at the end of the segment. */
vec3 fog_apply(const fog *f, vec3 o, vec3 d, float t, vec3 c);

#endif

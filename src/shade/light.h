/* light: point lights (position and colour; the colour carries intensity).
 * No falloff with distance, as in the classic Whitted model. */
#ifndef GLINT_SHADE_LIGHT_H
#define GLINT_SHADE_LIGHT_H

#include "core/vec3.h"

typedef enum light_kind {
    LIGHT_POINT,
} light_kind;

typedef struct light {
    light_kind kind;
    vec3 position;
    vec3 color;
} light;

#endif

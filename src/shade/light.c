#include "light.h"

#include <math.h>

light light_point(vec3 position, vec3 color, vec3 attenuation)
{
    return (light){.kind = LIGHT_POINT, .color = color, .point = {position, attenuation}};
}

light light_directional(vec3 direction, vec3 color)
{
    return (light){.kind = LIGHT_DIRECTIONAL, .color = color,
                   .directional = {v3_norm(direction)}};
}

light light_spot(vec3 position, vec3 look_at, float inner_deg, float outer_deg, vec3 color,
                 vec3 attenuation)
{
    const double rad = M_PI / 180.0;
    return (light){.kind = LIGHT_SPOT, .color = color,
                   .spot = {position, v3_norm(v3_sub(look_at, position)),
                            (float)cos(inner_deg * rad), (float)cos(outer_deg * rad),
                            attenuation}};
}

light light_area(vec3 position, vec3 edge_u, vec3 edge_v, int n, vec3 color, vec3 attenuation)
{
    vec3 corner = v3_sub(position, v3_scale(v3_add(edge_u, edge_v), 0.5f));
    return (light){.kind = LIGHT_AREA, .color = color,
                   .area = {corner, edge_u, edge_v, n, attenuation}};
}

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
                   .spot = {position, look_at, v3_norm(v3_sub(look_at, position)),
                            (float)cos(inner_deg * rad), (float)cos(outer_deg * rad),
                            attenuation}};
}

light light_area(vec3 position, vec3 edge_u, vec3 edge_v, int n, vec3 color, vec3 attenuation)
{
    vec3 corner = v3_sub(position, v3_scale(v3_add(edge_u, edge_v), 0.5f));
    return (light){.kind = LIGHT_AREA, .color = color,
                   .area = {position, corner, edge_u, edge_v, n, attenuation}};
}

/* d normalised, or keep when d has no length. */
static vec3 unit_or(vec3 d, vec3 keep) { return v3_len2(d) > 0.0f ? v3_norm(d) : keep; }

void light_refresh(light *l)
{
    switch (l->kind) {
    case LIGHT_POINT:
        return;
    case LIGHT_DIRECTIONAL:
        l->directional.direction = unit_or(l->directional.direction, v3(0.0f, -1.0f, 0.0f));
        return;
    case LIGHT_SPOT:
        l->spot.axis = unit_or(v3_sub(l->spot.look_at, l->spot.position), l->spot.axis);
        return;
    case LIGHT_AREA: {
        struct area_light *a = &l->area;
        a->corner = v3_sub(a->position, v3_scale(v3_add(a->edge_u, a->edge_v), 0.5f));
        return;
    }
    case LIGHT_KIND_COUNT:
        return;
    }
}

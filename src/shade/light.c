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

float light_attenuation(vec3 att, float d)
{
    float k = att.x + d * (att.y + d * att.z);
    return k > 0.0f ? 1.0f / k : 0.0f;
}

float light_spot_factor(const struct spot_light *s, float cos_a)
{
    if (cos_a >= s->cos_inner)
        return 1.0f;
    if (cos_a <= s->cos_outer)
        return 0.0f;
    float t = (cos_a - s->cos_outer) / (s->cos_inner - s->cos_outer);
    return t * t * (3.0f - 2.0f * t);
}

int light_sample_count(const light *l)
{
    switch (l->kind) {
    case LIGHT_POINT:
    case LIGHT_DIRECTIONAL:
    case LIGHT_SPOT:
        return 1;
    case LIGHT_AREA:
        return l->area.n * l->area.n;
    case LIGHT_KIND_COUNT:
        break;
    }
    return 0;
}

/* Towards a point light source at pos, attenuated. */
static light_ray toward(vec3 p, vec3 pos, vec3 color, vec3 att)
{
    vec3 d = v3_sub(pos, p);
    float dist = v3_len(d);
    light_ray r = {v3_scale(d, dist > 0.0f ? 1.0f / dist : 0.0f), dist, pos, color};
    if (!(att.x == 1.0f && att.y == 0.0f && att.z == 0.0f))
        r.color = v3_scale(color, light_attenuation(att, dist));
    return r;
}

light_ray light_sample(const light *l, vec3 p, int k, float u1, float u2)
{
    switch (l->kind) {
    case LIGHT_POINT:
        return toward(p, l->point.position, l->color, l->point.attenuation);
    case LIGHT_DIRECTIONAL:
        return (light_ray){v3_neg(l->directional.direction), INFINITY, p, l->color};
    case LIGHT_SPOT: {
        const struct spot_light *s = &l->spot;
        light_ray r = toward(p, s->position, l->color, s->attenuation);
        float f = light_spot_factor(s, -v3_dot(r.dir, s->axis));
        r.color = v3_scale(r.color, f);
        return r;
    }
    case LIGHT_AREA: {
        const struct area_light *a = &l->area;
        float inv = 1.0f / (float)a->n;
        float su = ((float)(k % a->n) + u1) * inv, sv = ((float)(k / a->n) + u2) * inv;
        vec3 pos = v3_madd(v3_madd(a->corner, a->edge_u, su), a->edge_v, sv);
        return toward(p, pos, v3_scale(l->color, inv * inv), a->attenuation);
    }
    case LIGHT_KIND_COUNT:
        break;
    }
    return (light_ray){v3s(0.0f), 0.0f, p, v3s(0.0f)};
}

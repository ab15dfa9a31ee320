/* The lights: section: point, directional, spot and area lights
 * (src/shade/light.h). */
#include "loader.h"

#include <math.h>
#include <stddef.h>

/* In light_kind order. */
static const char *const light_types[] = {"point", "directional", "spot", "area", NULL};
_Static_assert(sizeof light_types / sizeof *light_types == LIGHT_KIND_COUNT + 1,
               "light_types names every light_kind, in order");

static const char *const *const light_keys[LIGHT_KIND_COUNT] = {
    [LIGHT_POINT] = (const char *const[]){"type", "position", "color", "attenuation", NULL},
    [LIGHT_DIRECTIONAL] = (const char *const[]){"type", "direction", "color", NULL},
    [LIGHT_SPOT] = (const char *const[]){"type", "position", "look_at", "inner_angle",
                                         "outer_angle", "color", "attenuation", NULL},
    [LIGHT_AREA] = (const char *const[]){"type", "position", "edge_u", "edge_v", "samples",
                                         "color", "attenuation", NULL},
};

/* [c, l, q], none below 0, not all 0: intensity / (c + l d + q d^2). */
static glint_rc read_attenuation(loader *L, uint32_t map, vec3 *out)
{
    *out = v3(1.0f, 0.0f, 0.0f);
    uint32_t v = load_get(L, map, "attenuation");
    if (v == YDOC_NONE)
        return GLINT_OK;
    float f[3];
    glint_rc rc = load_numbers(L, v, "attenuation", "[constant, linear, quadratic]", 3, f);
    char buf[SHOWN];
    for (int i = 0; rc == GLINT_OK && i < 3; i++)
        if (!(f[i] >= 0.0f)) {
            uint32_t c = ydoc_item(load_doc(L), load_node(L, v), (uint32_t)i);
            rc = load_fail(L, c, "attenuation terms must be >= 0 (got %s)", load_shown(L, c, buf));
        }
    if (rc == GLINT_OK && f[0] == 0.0f && f[1] == 0.0f && f[2] == 0.0f)
        rc = load_fail(L, v, "attenuation must not be [0, 0, 0] (use [1, 0, 0] for none)");
    if (rc == GLINT_OK)
        *out = v3(f[0], f[1], f[2]);
    return rc;
}

/* An optional angle in degrees, 0 to 179.9. */
static glint_rc read_angle(loader *L, uint32_t map, const char *key, float *out)
{
    uint32_t v = load_get(L, map, key);
    if (v == YDOC_NONE)
        return GLINT_OK;
    glint_rc rc = load_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out >= 0.0f && *out < 180.0f))
        rc = load_fail(L, v, "%s must be at least 0 and below 180 degrees (got %s)", key,
                       load_shown(L, v, buf));
    return rc;
}

/* Where a light's value lives, in floats from the start of a light, for
 * the animation channels that key it (light_refresh derives the rest). */
#define LIGHT_OFFSET(field) ((int)(offsetof(light, field) / sizeof(float)))

/* A required vector that may be keyed: its value at the start in *out. */
static glint_rc keyed_vec3(loader *L, uint32_t map, const char *key, const char *what,
                           load_value_fn read, int offset, vec3 *out)
{
    uint32_t v;
    glint_rc rc = load_need(L, map, key, what, &v);
    if (rc == GLINT_OK)
        rc = load_anim_value(L, v, key, 3, read, &out->x, offset, -INFINITY, INFINITY);
    return rc;
}

static glint_rc read_spot(loader *L, uint32_t map, vec3 color, light *out)
{
    vec3 pos, at, att;
    float inner = 20.0f, outer = 30.0f;
    glint_rc rc = keyed_vec3(L, map, "position", "spot light", load_read_vec3,
                             LIGHT_OFFSET(spot.position), &pos);
    if (rc == GLINT_OK)
        rc = keyed_vec3(L, map, "look_at", "spot light", load_read_vec3,
                        LIGHT_OFFSET(spot.look_at), &at);
    if (rc == GLINT_OK && v3_is_zero(v3_sub(at, pos)))
        rc = load_fail(L, load_get(L, map, "look_at"), "look_at must differ from position");
    if (rc == GLINT_OK)
        rc = read_angle(L, map, "inner_angle", &inner);
    if (rc == GLINT_OK)
        rc = read_angle(L, map, "outer_angle", &outer);
    if (rc == GLINT_OK && !(outer > inner)) {
        uint32_t v = load_get(L, map, "outer_angle");
        rc = load_fail(L, v != YDOC_NONE ? v : map,
                       "outer_angle (%g) must be greater than inner_angle (%g)", (double)outer,
                       (double)inner);
    }
    if (rc == GLINT_OK)
        rc = read_attenuation(L, map, &att);
    if (rc == GLINT_OK)
        *out = light_spot(pos, at, inner, outer, color, att);
    return rc;
}

static glint_rc read_area(loader *L, uint32_t map, vec3 color, light *out)
{
    vec3 pos, eu, ev, att;
    int n = 4;
    uint32_t v;
    glint_rc rc = keyed_vec3(L, map, "position", "area light", load_read_vec3,
                             LIGHT_OFFSET(area.position), &pos);
    if (rc == GLINT_OK)
        rc = keyed_vec3(L, map, "edge_u", "area light", load_read_nonzero_vec3,
                        LIGHT_OFFSET(area.edge_u), &eu);
    if (rc == GLINT_OK)
        rc = keyed_vec3(L, map, "edge_v", "area light", load_read_nonzero_vec3,
                        LIGHT_OFFSET(area.edge_v), &ev);
    v = load_get(L, map, "edge_v");
    if (rc == GLINT_OK && !(v3_len2(v3_cross(eu, ev)) > 0.0f))
        rc = load_fail(L, v, "edge_v must not be parallel to edge_u");
    if (rc == GLINT_OK && (v = load_get(L, map, "samples")) != YDOC_NONE)
        rc = load_int(L, v, "samples", 1, LIGHT_MAX_AREA_SAMPLES, &n);
    if (rc == GLINT_OK)
        rc = read_attenuation(L, map, &att);
    if (rc == GLINT_OK)
        *out = light_area(pos, eu, ev, n, color, att);
    return rc;
}

/* The keys of one kind. */
static glint_rc read_light(loader *L, uint32_t map, light_kind kind, vec3 color, light *out)
{
    vec3 a, att;
    glint_rc rc = GLINT_OK;
    switch (kind) {
    case LIGHT_POINT:
        rc = keyed_vec3(L, map, "position", "point light", load_read_vec3,
                        LIGHT_OFFSET(point.position), &a);
        if (rc == GLINT_OK)
            rc = read_attenuation(L, map, &att);
        if (rc == GLINT_OK)
            *out = light_point(a, color, att);
        return rc;
    case LIGHT_DIRECTIONAL:
        rc = keyed_vec3(L, map, "direction", "directional light", load_read_nonzero_vec3,
                        LIGHT_OFFSET(directional.direction), &a);
        if (rc == GLINT_OK)
            *out = light_directional(a, color);
        return rc;
    case LIGHT_SPOT:
        return read_spot(L, map, color, out);
    case LIGHT_AREA:
        return read_area(L, map, color, out);
    case LIGHT_KIND_COUNT:
        break;
    }
    return rc;
}

glint_rc load_light(loader *L, uint32_t map)
{
    if (load_node(L, map)->kind != YNODE_MAP)
        return load_expected(L, map, "a mapping", "lights");
    uint32_t v;
    int type;
    glint_rc rc = load_need(L, map, "type", "light", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "light type", light_types, &type);
    if (rc != GLINT_OK)
        return rc;
    rc = load_check_keys_in(L, map, light_keys[type], light_types[type], " light");
    vec3 color = v3s(1.0f);
    if (rc == GLINT_OK && (v = load_get(L, map, "color")) != YDOC_NONE)
        rc = load_anim_value(L, v, "color", 3, load_read_color, &color.x,
                             (int)(offsetof(light, color) / sizeof(float)), 0.0f, INFINITY);
    light l;
    if (rc == GLINT_OK)
        rc = read_light(L, map, (light_kind)type, color, &l);
    if (rc != GLINT_OK)
        return rc;
    int index = scene_add_light(L->s, &l);
    return index < 0 ? err_nomem(L->err) : load_anim_bind(L, ANIM_LIGHT, index);
}

/* The fog: section (src/shade/fog.h). The first file to set it wins, as
 * for the other scene-wide settings. */
#include "loader.h"

/* In fog_kind order, after FOG_NONE. */
static const char *const fog_types[] = {"exponential", "linear", NULL};
static const char *const fog_keys[] = {"type", "color", "density", "start", "end",
                                       "height_falloff", NULL};
static const char *const exponential_keys[] = {"type", "color", "density", "height_falloff",
                                               NULL};
static const char *const linear_keys[] = {"type", "color", "start", "end", "height_falloff",
                                          NULL};

glint_rc load_fog(loader *L, uint32_t map)
{
    uint32_t v;
    int type;
    glint_rc rc = load_want_map(L, map, "fog");
    if (rc == GLINT_OK)
        rc = load_check_keys(L, map, fog_keys, "in fog");
    if (rc == GLINT_OK)
        rc = load_need(L, map, "type", "fog", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "fog type", fog_types, &type);
    if (rc == GLINT_OK)
        rc = load_check_keys(L, map, type == 0 ? exponential_keys : linear_keys,
                             type == 0 ? "in exponential fog" : "in linear fog");
    fog f = {type == 0 ? FOG_EXPONENTIAL : FOG_LINEAR, v3s(0.5f), 0.0f, 0.0f, 0.0f, 0.0f};
    if (rc == GLINT_OK && (v = load_get(L, map, "color")) != YDOC_NONE)
        rc = load_color(L, v, "color", &f.color);
    if (rc == GLINT_OK && type == 0)
        rc = load_need_positive(L, map, "density", "exponential fog", &f.density);
    if (rc == GLINT_OK && type == 1 && (v = load_get(L, map, "start")) != YDOC_NONE)
        rc = load_nonneg(L, v, "start", &f.start);
    if (rc == GLINT_OK && type == 1)
        rc = load_need_positive(L, map, "end", "linear fog", &f.end);
    if (rc == GLINT_OK && type == 1 && !(f.end > f.start))
        rc = load_fail(L, load_get(L, map, "end"), "end (%g) must be greater than start (%g)",
                       (double)f.end, (double)f.start);
    if (rc == GLINT_OK && (v = load_get(L, map, "height_falloff")) != YDOC_NONE)
        rc = load_nonneg(L, v, "height_falloff", &f.height_falloff);
    if (rc == GLINT_OK && load_claim(L, SET_FOG))
        L->fog = f;
    return rc;
}

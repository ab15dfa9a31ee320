/* The image: and camera: sections. The first file to set a value wins
 * (includers are read before what they include). */
#include "loader.h"
#include "scene/settings.h"

static const char *const image_keys[] = {"width",      "height",   "samples",     "depth",
                                         "background", "transfer", "adc_bailout", NULL};
static const char *const transfers[] = {"none", "srgb", NULL};

glint_rc load_image_settings(loader *L, uint32_t map)
{
    glint_rc rc = load_want_map(L, map, "image");
    if (rc == GLINT_OK)
        rc = load_check_keys(L, map, image_keys, "in image");
    glint_settings *st = &L->settings;
    uint32_t v;
    int x;
    vec3 c;
    char buf[SHOWN];
    if (rc == GLINT_OK && (v = load_get(L, map, "width")) != YDOC_NONE) {
        rc = load_int(L, v, "width", 1, SETTINGS_MAX_SIDE, &x);
        if (rc == GLINT_OK && load_claim(L, SET_WIDTH))
            st->width = x;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "height")) != YDOC_NONE) {
        rc = load_int(L, v, "height", 1, SETTINGS_MAX_SIDE, &x);
        if (rc == GLINT_OK && load_claim(L, SET_HEIGHT))
            st->height = x;
    }
    if (rc == GLINT_OK && L->size_file < 0 &&
        (load_get(L, map, "width") != YDOC_NONE || load_get(L, map, "height") != YDOC_NONE)) {
        L->size_file = L->cur;
        L->size_node = map;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "samples")) != YDOC_NONE) {
        rc = load_int(L, v, "samples", 1, SETTINGS_MAX_SAMPLES, &x);
        if (rc == GLINT_OK && settings_grid_side(x) < 0)
            rc = load_fail(L, v, "samples must be a perfect square (1, 4, 9, 16, ...) (got %s)",
                      load_shown(L, v, buf));
        if (rc == GLINT_OK && load_claim(L, SET_SAMPLES))
            st->samples = x;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "depth")) != YDOC_NONE) {
        rc = load_int(L, v, "depth", 0, SETTINGS_MAX_DEPTH, &x);
        if (rc == GLINT_OK && load_claim(L, SET_DEPTH))
            st->max_depth = x;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "background")) != YDOC_NONE) {
        rc = load_color(L, v, "background", &c);
        if (rc == GLINT_OK && load_claim(L, SET_BACKGROUND))
            L->background = c;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "transfer")) != YDOC_NONE) {
        rc = load_enum(L, v, "transfer", "transfer", transfers, &x);
        if (rc == GLINT_OK && load_claim(L, SET_TRANSFER))
            st->transfer = x == 0 ? GLINT_TRANSFER_NONE : GLINT_TRANSFER_SRGB;
    }
    float f;
    if (rc == GLINT_OK && (v = load_get(L, map, "adc_bailout")) != YDOC_NONE) {
        rc = load_unit(L, v, "adc_bailout", &f);
        if (rc == GLINT_OK && load_claim(L, SET_ADC_BAILOUT))
            st->adc_bailout = f;
    }
    return rc;
}

static const char *const camera_keys[] = {"eye", "look_at", "up", "fov", NULL};

glint_rc load_camera(loader *L, uint32_t map)
{
    glint_rc rc = load_want_map(L, map, "camera");
    if (rc == GLINT_OK)
        rc = load_check_keys(L, map, camera_keys, "in camera");
    if (rc != GLINT_OK)
        return rc;
    if (L->camera_file < 0) {
        L->camera_file = L->cur;
        L->camera_node = map;
    }
    camera *cam = &L->camera;
    uint32_t v;
    vec3 p;
    float f;
    char buf[SHOWN];
    if ((v = load_get(L, map, "eye")) != YDOC_NONE) {
        rc = load_vec3(L, v, "eye", &p);
        if (rc == GLINT_OK && load_claim(L, SET_EYE))
            cam->eye = p;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "look_at")) != YDOC_NONE) {
        rc = load_vec3(L, v, "look_at", &p);
        if (rc == GLINT_OK && load_claim(L, SET_LOOK_AT))
            cam->target = p;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "up")) != YDOC_NONE) {
        rc = load_nonzero_vec3(L, v, "up", &p);
        if (rc == GLINT_OK && load_claim(L, SET_UP))
            cam->up = p;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "fov")) != YDOC_NONE) {
        rc = load_number(L, v, "fov", &f);
        if (rc == GLINT_OK && !(f > 0.0f && f < 180.0f))
            rc = load_fail(L, v, "fov must be > 0 and < 180 degrees (got %s)", load_shown(L, v, buf));
        if (rc == GLINT_OK && load_claim(L, SET_FOV))
            cam->hfov = f;
    }
    return rc;
}


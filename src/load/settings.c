/* The image: and camera: sections. The first file to set a value wins
 * (includers are read before what they include). */
#include "loader.h"

#include <math.h>
#include <stddef.h>

#include "scene/settings.h"

static const char *const image_keys[] = {"width",      "height",   "samples",     "depth",
                                         "background", "transfer", "adc_bailout", "sampler",
                                         "threshold",  "max_depth", "alpha",      NULL};
static const char *const transfers[] = {"none", "srgb", NULL};
static const char *const samplers[] = {"grid", "jitter", "adaptive", NULL}; /* glint_sampler order */

/* image: sampler, threshold, max_depth, alpha. */
static glint_rc load_sampling(loader *L, uint32_t map)
{
    glint_settings *st = &L->settings;
    glint_rc rc = GLINT_OK;
    uint32_t v;
    int x;
    float f;
    bool b;
    if ((v = load_get(L, map, "sampler")) != YDOC_NONE) {
        rc = load_enum(L, v, "sampler", "sampler", samplers, &x);
        if (rc == GLINT_OK && load_claim(L, SET_SAMPLER))
            st->sampler = (glint_sampler)x;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "threshold")) != YDOC_NONE) {
        rc = load_unit(L, v, "threshold", &f);
        if (rc == GLINT_OK && load_claim(L, SET_THRESHOLD))
            st->threshold = (double)f;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "max_depth")) != YDOC_NONE) {
        rc = load_int(L, v, "max_depth", 0, SETTINGS_MAX_ADAPTIVE_DEPTH, &x);
        if (rc == GLINT_OK && load_claim(L, SET_ADAPTIVE_DEPTH))
            st->adaptive_depth = x;
    }
    if (rc == GLINT_OK && (v = load_get(L, map, "alpha")) != YDOC_NONE) {
        rc = load_bool(L, v, "alpha", &b);
        if (rc == GLINT_OK && load_claim(L, SET_ALPHA))
            st->alpha = b;
    }
    return rc;
}

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
    if (rc == GLINT_OK)
        rc = load_sampling(L, map);
    return rc;
}

static const char *const camera_keys[] = {"eye",      "look_at",        "up",    "fov",
                                          "aperture", "focus_distance", "width", "shutter",
                                          "projection", NULL};
static const char *const projections[] = {"perspective", "orthographic", "equirectangular",
                                          "fisheye", NULL}; /* camera_projection order */

#define CAMERA_AT(field) ((int)(offsetof(camera, field) / sizeof(float)))

/* A field of the camera that may be keyed. */
typedef struct camera_field {
    const char *key;
    unsigned bit;
    int dim, offset;
    load_value_fn read;
    float lo, hi; /* keyed values are held in this range */
} camera_field;

/* fov: checked against the widest range here (fisheye's), against the
 * projection's at the end. */
static glint_rc read_fov(loader *L, uint32_t v, const char *key, float *out)
{
    char buf[SHOWN];
    glint_rc rc = load_number(L, v, key, out);
    if (rc == GLINT_OK && !(*out > 0.0f && *out <= 360.0f))
        rc = load_fail(L, v, "fov must be > 0 and < 180 degrees (up to 360 for a fisheye) "
                             "(got %s)", load_shown(L, v, buf));
    return rc;
}

static glint_rc read_shutter(loader *L, uint32_t v, const char *key, float *out)
{
    return load_unit(L, v, key, out);
}

static const camera_field camera_fields[] = {
    {"eye", SET_EYE, 3, CAMERA_AT(eye), load_read_vec3, -INFINITY, INFINITY},
    {"look_at", SET_LOOK_AT, 3, CAMERA_AT(target), load_read_vec3, -INFINITY, INFINITY},
    {"up", SET_UP, 3, CAMERA_AT(up), load_read_nonzero_vec3, -INFINITY, INFINITY},
    {"fov", SET_FOV, 1, CAMERA_AT(hfov), read_fov, 1e-3f, 360.0f},
    {"aperture", SET_APERTURE, 1, CAMERA_AT(aperture), load_read_nonneg, 0.0f, INFINITY},
    {"focus_distance", SET_FOCUS, 1, CAMERA_AT(focus_distance), load_read_positive, 1e-6f,
     INFINITY},
    {"width", SET_VIEW_WIDTH, 1, CAMERA_AT(width), load_read_positive, 1e-6f, INFINITY},
    {"shutter", SET_SHUTTER, 1, CAMERA_AT(shutter), read_shutter, 0.0f, 1.0f},
};

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
    for (size_t i = 0; rc == GLINT_OK && i < sizeof camera_fields / sizeof *camera_fields; i++) {
        const camera_field *f = &camera_fields[i];
        if ((v = load_get(L, map, f->key)) == YDOC_NONE)
            continue;
        float val[3];
        bool shutter = f->bit == SET_SHUTTER;
        rc = shutter && load_is_keyed(L, v)
                 ? load_fail(L, v, "shutter cannot be keyed")
                 : load_anim_value(L, v, f->key, f->dim, f->read, val, f->offset, f->lo, f->hi);
        if (rc != GLINT_OK)
            break;
        if (!load_claim(L, f->bit)) {
            load_anim_drop(L);
            continue;
        }
        for (int c = 0; c < f->dim; c++)
            ((float *)cam)[f->offset + c] = val[c];
        if (f->bit == SET_VIEW_WIDTH)
            L->width_node = v;
        if (f->bit == SET_FOV) {
            L->fov_file = L->cur;
            L->fov_node = v;
        }
        rc = load_anim_bind(L, ANIM_CAMERA, 0);
    }
    int x;
    if (rc == GLINT_OK && (v = load_get(L, map, "projection")) != YDOC_NONE) {
        rc = load_enum(L, v, "projection", "projection", projections, &x);
        if (rc == GLINT_OK && load_claim(L, SET_PROJECTION))
            cam->projection = (camera_projection)x;
    }
    return rc;
}

static const char *const animation_keys[] = {"frames", "fps", "start", "end", NULL};

/* animation: {frames: N, fps: F} or {start: S, end: E, fps: F}; the frames
 * then cover [start, end), one every 1 / fps seconds. */
glint_rc load_animation(loader *L, uint32_t map)
{
    glint_rc rc = load_want_map(L, map, "animation");
    if (rc == GLINT_OK)
        rc = load_check_keys(L, map, animation_keys, "in animation");
    if (rc != GLINT_OK)
        return rc;
    uint32_t frames = load_get(L, map, "frames"), end = load_get(L, map, "end"), v;
    if (rc == GLINT_OK && frames != YDOC_NONE && end != YDOC_NONE)
        rc = load_fail(L, end, "animation takes frames or end, not both");
    if (rc == GLINT_OK && frames == YDOC_NONE && end == YDOC_NONE)
        rc = load_fail(L, map, "animation needs frames (a count) or end (seconds)");
    int n = 1;
    float fps = 24.0f, start = 0.0f, stop;
    if (rc == GLINT_OK && frames != YDOC_NONE)
        rc = load_int(L, frames, "frames", 1, LOAD_MAX_FRAMES, &n);
    if (rc == GLINT_OK && (v = load_get(L, map, "fps")) != YDOC_NONE)
        rc = load_positive(L, v, "fps", &fps);
    if (rc == GLINT_OK && (v = load_get(L, map, "start")) != YDOC_NONE)
        rc = load_number(L, v, "start", &start);
    if (rc == GLINT_OK && end != YDOC_NONE) {
        rc = load_number(L, end, "end", &stop);
        double count = rc == GLINT_OK ? floor((double)(stop - start) * fps + 0.5) : 0.0;
        if (rc == GLINT_OK && !(count >= 1.0 && count <= LOAD_MAX_FRAMES))
            rc = load_fail(L, end, "animation from %g to %g s at %g fps has %.0f frames "
                                   "(1 to %d)", (double)start, (double)stop, (double)fps,
                           count, LOAD_MAX_FRAMES);
        n = (int)count;
    }
    if (rc == GLINT_OK && load_claim(L, SET_ANIMATION)) {
        L->s->anim.frames = n;
        L->s->anim.fps = fps;
        L->s->anim.start = start;
    }
    return rc;
}

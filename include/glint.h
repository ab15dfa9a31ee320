/* glint: a Whitted-style ray tracer, as a library.
 *
 * The flow is: get a scene (built in, or loaded from a file), read its
 * settings, change any you like, render into a float RGB film, write the film
 * to an image file. Every call that can fail returns a glint_rc and fills a
 * glint_error with a one-line message; the library never prints and never
 * exits. All functions are safe to call from any thread on distinct objects. */
#ifndef GLINT_GLINT_H
#define GLINT_GLINT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GLINT_VERSION "0.1.0"

typedef enum glint_rc {
    GLINT_OK = 0,
    GLINT_ERR_NOMEM, /* out of memory */
    GLINT_ERR_IO,    /* a file could not be read or written */
    GLINT_ERR_INPUT, /* bad input: scene, mesh, texture or settings */
    GLINT_ERR_CANCELLED,
} glint_rc;

typedef struct glint_error {
    glint_rc code;
    char msg[1024];
} glint_error;

/* Process exit code for a result: 0 ok, 2 bad input, 1 anything else. */
int glint_exit_code(glint_rc rc);

/* How linear film values become 8-bit pixel values. */
typedef enum glint_transfer {
    GLINT_TRANSFER_NONE, /* value * 255, clamped: colours are display values */
    GLINT_TRANSFER_SRGB, /* the sRGB curve (IEC 61966-2-1): colours are linear */
} glint_transfer;

typedef struct glint_settings {
    int width, height;     /* pixels */
    int samples;           /* per pixel; a perfect square (N*N regular grid) */
    int max_depth;         /* reflection/refraction recursion limit */
    int threads;           /* 0: one per core */
    glint_transfer transfer;
} glint_settings;

typedef struct glint_film {
    int width, height;
    float *rgb; /* width*height*3 floats, row 0 at the top, linear values */
} glint_film;

typedef struct glint_stats {
    uint64_t primary_rays, secondary_rays, shadow_rays;
    double seconds; /* wall time of the render */
} glint_stats;

typedef struct glint_callbacks {
    /* Called after each finished tile (from the worker thread that rendered
     * it; calls are serialised). done/total count tiles. */
    void (*tile_done)(void *user, const glint_film *film, int x0, int y0, int x1, int y1,
                      int done, int total);
    void *user;
    /* When non-null and set non-zero by another thread, the render stops
     * early and returns GLINT_ERR_CANCELLED. */
    const volatile int *cancel;
} glint_callbacks;

typedef struct glint_scene glint_scene;

/* The assignment's nine-object scene. */
glint_rc glint_scene_builtin(glint_scene **out, glint_error *err);
/* A scene file (YAML, docs/scene-format.md); paths in it are relative to
 * its folder. Errors name the file, line and column. */
glint_rc glint_scene_load(const char *path, glint_scene **out, glint_error *err);
void glint_scene_free(glint_scene *scene);

/* The scene's own image settings. */
void glint_scene_settings(const glint_scene *scene, glint_settings *out);
/* Checks settings for a render: sizes, sample counts, memory limits. */
glint_rc glint_settings_check(const glint_settings *s, glint_error *err);

/* Renders the scene into *film (allocated here; free with glint_film_free).
 * callbacks and stats may be NULL. */
glint_rc glint_render(const glint_scene *scene, const glint_settings *settings,
                      const glint_callbacks *callbacks, glint_film *film, glint_stats *stats,
                      glint_error *err);
void glint_film_free(glint_film *film);

/* Render threads used when settings.threads is 0: one per core. */
int glint_default_threads(void);

/* Image file formats for glint_film_write. */
typedef enum glint_format {
    GLINT_FORMAT_AUTO, /* from the file name's extension; PNG for "-" */
    GLINT_FORMAT_PNG,  /* .png: 8 or 16 bits, RGB or RGBA */
    GLINT_FORMAT_PPM,  /* .ppm: binary PPM, 8 or 16 bits */
    GLINT_FORMAT_JPEG, /* .jpg, .jpeg: 8 bits, lossy */
    GLINT_FORMAT_HDR,  /* .hdr: Radiance RGBE, linear */
    GLINT_FORMAT_PFM,  /* .pfm: 32-bit float, linear */
    GLINT_FORMAT_EXR,  /* .exr: OpenEXR half (16) or float (32), RGB or RGBA, linear */
} glint_format;

/* How glint_film_write writes. Zero-initialised options are the defaults. */
typedef struct glint_write_options {
    glint_format format;     /* GLINT_FORMAT_AUTO: from the extension */
    glint_transfer transfer; /* 8- and 16-bit formats: how film values become pixels */
    int quality;             /* JPEG, 1..100; 0: 90 */
    int bits;                /* per channel; 0: the format's default (PNG, PPM 8; EXR 16);
                                PNG and PPM take 8 or 16, EXR 16 or 32, PFM 32, JPEG 8 */
    const float *alpha;      /* NULL, or width*height coverage values in [0, 1] (linear):
                                PNG and EXR get an alpha channel; other formats ignore it */
} glint_write_options;

/* Writes the film to path ("-": standard output). Float formats (.hdr,
 * .pfm, .exr) take the linear film as it is; the others quantise it through
 * the transfer function. The file is encoded in memory first, then written
 * beside the target and renamed into place, so it appears complete or not at
 * all (details: README.md, "Output files"). opts may be NULL (defaults). */
glint_rc glint_film_write(const glint_film *film, const char *path,
                          const glint_write_options *opts, glint_error *err);

/* Checks, before a render, that glint_film_write(path, opts) can work: a
 * known format and bit depth for it, not a directory or a read-only file, an
 * existing folder where a file can be created. Errors are GLINT_ERR_INPUT. */
glint_rc glint_output_check(const char *path, const glint_write_options *opts, glint_error *err);

/* A format from its name or extension ("png", "jpg", "exr"...). */
glint_rc glint_format_parse(const char *name, glint_format *out, glint_error *err);

#ifdef __cplusplus
}
#endif

#endif

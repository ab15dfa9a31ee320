/* glint: a Whitted-style ray tracer, as a library.
 *
 * Flow. Get a scene: glint_scene_builtin, glint_scene_load (a YAML file), or
 * glint_scene_new followed by glint_scene_add_* and glint_scene_build. Read
 * its settings and camera, change any you like (on the scene, or per render),
 * render into a float RGB film (the whole image, a region of it, or a list of
 * tiles), then write the film to an image file.
 *
 * Errors. Every call that can fail returns a glint_rc and, when err is not
 * NULL, fills *err with a one-line message. Every function checks its
 * arguments: a NULL pointer or a value out of range is GLINT_ERR_INPUT, with
 * a message naming the function and the argument. The library never prints
 * and never exits.
 *
 * Ownership. A scene belongs to the caller from the call that made it until
 * glint_scene_free. A film's pixels belong to the caller after glint_render
 * or glint_film_alloc, until glint_film_free. Everything passed in by
 * pointer (settings, camera, materials, shapes, transform steps, paths) is
 * copied before the call returns; the library keeps no pointer to it. Files
 * a call names (a scene, a texture image, a mesh) are read during the call.
 *
 * Threads. Functions may be called from any thread. Calls on distinct
 * scenes and films never interfere. Several renders of one scene may run at
 * once (rendering only reads the scene), but nothing may change a scene
 * (add, set, build, free) while another call uses it. Loading scenes with
 * meshes from several threads is safe: mesh imports are serialised inside.
 *
 * Compatibility. Structures may gain fields in later versions: start from
 * what the library fills in (glint_scene_settings, glint_scene_camera,
 * glint_material_default, glint_texture_default, glint_light_default,
 * glint_fog_default) rather than from a structure written out by hand, and
 * zero-initialise the rest. */
#ifndef GLINT_GLINT_H
#define GLINT_GLINT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Symbols the shared library exports; everything else in it is hidden. */
#if defined(__GNUC__)
#define GLINT_API __attribute__((visibility("default")))
#else
#define GLINT_API
#endif

#define GLINT_VERSION "0.1.0"

/* The version of the library linked, which may differ from the header's
 * GLINT_VERSION when the shared library was replaced. */
GLINT_API const char *glint_version(void);

/* ---- errors -------------------------------------------------------------- */

typedef enum glint_rc {
    GLINT_OK = 0,
    GLINT_ERR_NOMEM, /* out of memory */
    GLINT_ERR_IO,    /* a file could not be read or written */
    GLINT_ERR_INPUT, /* bad input: arguments, scene, mesh, texture or settings */
    GLINT_ERR_CANCELLED,
} glint_rc;

typedef struct glint_error {
    glint_rc code;
    char msg[1024];
} glint_error;

/* Process exit code for a result: 0 ok, 2 bad input, 1 anything else. */
GLINT_API int glint_exit_code(glint_rc rc);

/* ---- settings ------------------------------------------------------------ */

/* How linear film values become 8-bit pixel values. */
typedef enum glint_transfer {
    GLINT_TRANSFER_NONE, /* value * 255, clamped: colours are display values */
    GLINT_TRANSFER_SRGB, /* the sRGB curve (IEC 61966-2-1): colours are linear */
} glint_transfer;

/* Where in a pixel its samples go (docs/scene-format.md, image.sampler). */
typedef enum glint_sampler {
    GLINT_SAMPLER_GRID,     /* N x N regular grid, at the centres of N x N cells */
    GLINT_SAMPLER_JITTER,   /* one sample in each of the N x N cells, placed by a hash of
                               the pixel and the sample: the same for any thread count */
    GLINT_SAMPLER_ADAPTIVE, /* corners (shared with neighbours) and centre; a cell whose
                               samples differ by more than threshold splits in four, down
                               to adaptive_depth; samples is not used */
} glint_sampler;

typedef struct glint_settings {
    int width, height;     /* pixels, 1 to 32768 each, at most 2^27 in all */
    int samples;           /* per pixel, 1 to 1024; a perfect square (N*N grid) */
    int max_depth;         /* reflection/refraction recursion limit, 0 to 64 */
    int threads;           /* 0: one per core; at most 1024 */
    glint_transfer transfer;
    /* Adaptive depth control (Hall and Greenberg 1983): a reflected or
     * transmitted ray whose share of the pixel falls below this is not
     * traced. 0 to 1; 0 never prunes (the tree of rays then grows as
     * 2^depth through glass). A scene's default is 1/255. */
    double adc_bailout;
    glint_sampler sampler;
    double threshold;      /* ADAPTIVE: largest difference of display values (0 to 1)
                              left unsplit; 0 splits every cell */
    int adaptive_depth;    /* ADAPTIVE: most times a cell splits, 0 to 5 (4^5 cells) */
    int alpha;             /* non-zero: the film gets coverage (alpha), the share of a
                              pixel's camera rays that hit something */
} glint_settings;

/* Checks settings for a render: sizes, sample counts, memory limits. */
GLINT_API glint_rc glint_settings_check(const glint_settings *s, glint_error *err);

/* Threads used when a thread count is 0: one per core this process may
 * run on (its CPU affinity, which taskset, mpirun and srun set). */
GLINT_API int glint_default_threads(void);

/* Memory kept for a load and the render after it. A program that loads a
 * scene and then renders it can have the library keep one block of at
 * least `bytes` mapped pages (six times a YAML scene file's size holds its
 * parse tree): the parse tree of the next scene file loaded takes it while
 * the scene loads, and the film made after it (of 1 MiB or more) then
 * takes the same pages, touched already, instead of fresh ones (which a
 * virtual machine may first have to get from its host); a film freed
 * leaves its block for the next. The block stays mapped until the process
 * ends. Returns it, whose pages the caller may map ahead while the scene
 * loads (from any thread, with madvise MADV_POPULATE_WRITE, which leaves
 * what they hold; never write to it, unmap it or use the address after
 * the load), or NULL when it cannot be made or was made already. Films
 * are freed with glint_film_free, as always: never with free(). Advice
 * only: every result is the same with it or without. */
GLINT_API void *glint_memory_spare(size_t bytes);

/* ---- scenes -------------------------------------------------------------- */

typedef struct glint_scene glint_scene;

/* The assignment's nine-object scene, built. */
GLINT_API glint_rc glint_scene_builtin(glint_scene **out, glint_error *err);
/* A scene file (YAML, docs/scene-format.md), built; paths in it are
 * relative to its folder. Errors name the file, line and column. The scene
 * and the files it names must be regular files (a FIFO, a device or a
 * folder is refused before anything is read); "-" and "/dev/stdin" read
 * standard input to its end, with paths relative to the current folder. */
GLINT_API glint_rc glint_scene_load(const char *path, glint_scene **out, glint_error *err);

/* How a scene is loaded; all zero (or a NULL pointer) is the default. */
typedef struct glint_load_options {
    int threads; /* 0 to 1024 (0: glint_default_threads): the threads that decode
                    the scene's textures and build its trees, its meshes' and
                    its own, then and at every later build (glint_scene_set_threads) */
} glint_load_options;

/* glint_scene_builtin and glint_scene_load with options. */
GLINT_API glint_rc glint_scene_builtin_with(const glint_load_options *options,
                                            glint_scene **out, glint_error *err);
GLINT_API glint_rc glint_scene_load_with(const char *path, const glint_load_options *options,
                                         glint_scene **out, glint_error *err);
/* Frees the scene and everything in it; NULL is fine. */
GLINT_API void glint_scene_free(glint_scene *scene);
/* What the user should know about a scene that loaded: lines such as
 * "model.ply: 12 of 5000 triangles dropped (12 of zero area)", each ending
 * in a newline; "" when there are none (or scene is NULL). Valid until the
 * scene is freed or changed. */
GLINT_API const char *glint_scene_warnings(const glint_scene *scene);

/* The settings a render uses when given none: the scene's own. */
GLINT_API glint_rc glint_scene_settings(const glint_scene *scene, glint_settings *out,
                                        glint_error *err);
/* Checks (as glint_settings_check) and stores them. */
GLINT_API glint_rc glint_scene_set_settings(glint_scene *scene, const glint_settings *s,
                                            glint_error *err);

/* What a scene holds, for reports such as glint --stats. */
typedef struct glint_scene_info {
    int objects, lights, materials, textures, meshes;
    uint64_t triangles;   /* placed: a mesh's triangles once per object placing it,
                             and each triangle object */
    double build_seconds; /* wall time of the scene's last build (bounds, BVH) */
} glint_scene_info;

GLINT_API glint_rc glint_scene_describe(const glint_scene *scene, glint_scene_info *out,
                                        glint_error *err);

/* The files on disk a loaded scene was read from: the scene file, the files
 * it includes, texture images and meshes, each once, as the loader opened
 * them (relative to the working folder when the scene's path was). A
 * watcher re-loads when one changes. None for the built-in scene. */
GLINT_API int glint_scene_source_count(const glint_scene *scene);
/* Source i (0 <= i < count), owned by the scene; NULL when out of range. */
GLINT_API const char *glint_scene_source(const glint_scene *scene, int i);

/* What a scene holds, so that a front end can say when something is
 * missing (no lights: only the ambient term shows; no objects: only the
 * background). Meshes count the files, objects their instances. */
typedef struct glint_scene_counts {
    int objects, lights, materials, textures, meshes;
} glint_scene_counts;
GLINT_API glint_rc glint_scene_count(const glint_scene *scene, glint_scene_counts *out,
                                     glint_error *err);

/* ---- camera -------------------------------------------------------------- */

typedef enum glint_projection {
    GLINT_PROJECTION_PERSPECTIVE,     /* a pinhole (or thin lens, with an aperture) */
    GLINT_PROJECTION_ORTHOGRAPHIC,    /* parallel rays from a window width wide */
    GLINT_PROJECTION_EQUIRECTANGULAR, /* the whole sphere: 360 degrees across, 180 down */
    GLINT_PROJECTION_FISHEYE,         /* equidistant: angle from the axis grows with the
                                         distance from the centre; fov across the width */
} glint_projection;

/* Pixels are square: the vertical field of view follows from fov and the
 * image's aspect ratio. */
typedef struct glint_camera {
    double eye[3];
    double look_at[3];          /* not equal to eye */
    double up[3];               /* not zero, not parallel to look_at - eye */
    double fov;                 /* horizontal field of view, degrees: perspective (0, 180),
                                   fisheye (0, 360]; unused by the other two */
    double aperture;            /* lens diameter (thin lens), >= 0; 0 is a pinhole */
    double focus_distance;      /* > 0, or 0: the distance from eye to look_at */
    glint_projection projection;
    double width;               /* orthographic: width of the view, > 0 */
    double shutter;             /* share of a frame the shutter is open, 0 to 1: motion
                                   blur of animated scenes; 0 none */
} glint_camera;

GLINT_API glint_rc glint_scene_camera(const glint_scene *scene, glint_camera *out,
                                      glint_error *err);
/* Refuses (GLINT_ERR_INPUT) a camera out of the ranges above or with a
 * value that is not finite, and leaves the scene's camera as it was. */
GLINT_API glint_rc glint_scene_set_camera(glint_scene *scene, const glint_camera *cam,
                                          glint_error *err);

/* ---- animation -------------------------------------------------------------
 * A scene file's animation: block and keyed values (docs/scene-format.md)
 * make the camera, lights, material colours and transforms functions of
 * time. A scene is at one time at once: loading leaves it at frame 1. */

typedef struct glint_animation {
    int frames;   /* 1 for a still scene */
    double fps;   /* frames per second (24 unless the scene says) */
    double start; /* seconds: frame 1's time; frame k's is start + (k - 1) / fps */
} glint_animation;

GLINT_API glint_rc glint_scene_animation(const glint_scene *scene, glint_animation *out,
                                         glint_error *err);
/* Moves the scene to time seconds: animated values take their values then,
 * and with camera.shutter > 0 the shutter stays open until seconds +
 * shutter / fps, moving objects and the camera blurring over that interval.
 * Rebuilds the scene (as glint_scene_build). Changes the scene: no render
 * may run at the same time. A camera set by glint_scene_set_camera keeps
 * its values only until an animated camera is moved in time. */
GLINT_API glint_rc glint_scene_set_time(glint_scene *scene, double seconds, glint_error *err);
/* glint_scene_set_time at frame's time; frame from 1 to the frame count. */
GLINT_API glint_rc glint_scene_set_frame(glint_scene *scene, int frame, glint_error *err);

/* ---- building a scene in code --------------------------------------------
 * Every shape, texture, material, light and setting of the scene format
 * (docs/scene-format.md) can be built here; the same scene as a YAML file
 * renders to the same image when it gives the same numbers. Keyed values
 * (animation) are the scene format's alone: a scene built in code is
 * still, and an embedder animates it by changing it between renders.
 * Adds return the new element's index in *index (may be NULL where no
 * index is needed). Colours are display values unless the render's
 * transfer is sRGB; every number must be finite. */

/* An empty scene: no objects or lights, the default camera (eye at the
 * origin looking down -z, fov 90) and settings (500x500, 1 sample, depth 5),
 * black background, ambient 0.2. */
GLINT_API glint_rc glint_scene_new(glint_scene **out, glint_error *err);

GLINT_API glint_rc glint_scene_set_background(glint_scene *scene, const double rgb[3],
                                              glint_error *err);
/* Ambient light, scaled by each material's ambient; colour components >= 0. */
GLINT_API glint_rc glint_scene_set_ambient(glint_scene *scene, const double rgb[3],
                                           glint_error *err);

/* The procedural patterns (src/shade/pattern.h gives each formula) give a
 * value that the colour map turns into a colour. */
typedef enum glint_texture_kind {
    GLINT_TEXTURE_IMAGE,      /* a picture read from file */
    GLINT_TEXTURE_CHECKER,    /* a chequer of even and odd (or of colors' stops 0 and 1) */
    GLINT_TEXTURE_STRIPES,    /* slabs of width 1 across x */
    GLINT_TEXTURE_RINGS,      /* tubes round the z axis (circles on (u, v)) */
    GLINT_TEXTURE_GRADIENT,   /* a ramp from 0 to 1 along x, repeating */
    GLINT_TEXTURE_NOISE,      /* Perlin noise */
    GLINT_TEXTURE_TURBULENCE, /* a fractal sum of noise (octaves, lacunarity, gain) */
    GLINT_TEXTURE_MARBLE,     /* veins across x bent by turbulence */
    GLINT_TEXTURE_WOOD,       /* rings round the z axis bent by turbulence */
} glint_texture_kind;

/* Where a texture is looked up (the scene format's space:). */
typedef enum glint_texture_space {
    GLINT_SPACE_UV,     /* the surface's (u, v) */
    GLINT_SPACE_OBJECT, /* the point in the object's own coordinates, from its bounds' centre */
    GLINT_SPACE_WORLD,  /* the point in the world */
} glint_texture_space;

/* How an image in space OBJECT or WORLD finds its (u, v) (mapping:). */
typedef enum glint_mapping {
    GLINT_MAPPING_UV,          /* the surface's (u, v): only in space UV */
    GLINT_MAPPING_PLANAR,      /* along axis, one image per unit, centred at the origin */
    GLINT_MAPPING_SPHERICAL,   /* longitude and latitude round the origin */
    GLINT_MAPPING_CYLINDRICAL, /* longitude round the y axis, height along it */
    GLINT_MAPPING_BOX,         /* planar on the face the normal points most along */
} glint_mapping;

/* A colour map's stop: the colour at pattern value at. */
typedef struct glint_color_stop {
    double at;
    double color[3]; /* components >= 0 */
} glint_color_stop;

#define GLINT_COLOR_MAP_MAX 16

typedef enum glint_wrap {
    GLINT_WRAP_REPEAT,
    GLINT_WRAP_CLAMP,
} glint_wrap;

struct glint_step;

/* Colour as a function of where a surface point is, as in the scene
 * format: on (u, v), u' = u * scale[0] + offset[0], v' = v * scale[1] +
 * offset[1] before lookup; in space, the point goes through the inverse of
 * the texture's transform (steps), then (an image) its mapping, then scale
 * and offset per component (z: scale_z, offset_z). The fields from space on
 * came later; zero in them keeps the earlier meaning for images and
 * chequers on (u, v). */
typedef struct glint_texture {
    glint_texture_kind kind;
    const char *file;       /* IMAGE: PNG, JPEG, ... (read by the add); v = 0 is its bottom row */
    glint_wrap wrap[2];     /* IMAGE: along u and v */
    double even[3], odd[3]; /* CHECKER: colours of the two kinds of square, components >= 0 */
    double scale[2];        /* not 0; a chequer has scale[0] x scale[1] squares on the unit square */
    double offset[2];
    glint_texture_space space; /* images: UV with mapping UV, OBJECT or WORLD with any other;
                                  patterns: any (the default is OBJECT, UV for the chequer) */
    glint_mapping mapping;     /* IMAGE only */
    int axis;                  /* IMAGE with MAPPING_PLANAR: 0 x, 1 y, 2 z */
    double scale_z, offset_z;  /* patterns in space: the third components (scale_z not 0) */
    /* Patterns: the colour map, 1 to GLINT_COLOR_MAP_MAX stops with at
     * ascending; 0 stops: the kind's own (the chequer's even and odd,
     * black at 0 to white at 1 for the others). */
    int ncolors;
    glint_color_stop colors[GLINT_COLOR_MAP_MAX];
    int octaves;        /* TURBULENCE, MARBLE, WOOD: 1 to 16 */
    double lacunarity;  /* TURBULENCE, MARBLE, WOOD: > 0, frequency ratio of octaves */
    double gain;        /* TURBULENCE, MARBLE, WOOD: > 0, amplitude ratio of octaves */
    double turbulence;  /* MARBLE, WOOD: >= 0, how much turbulence bends them */
    const struct glint_step *steps; /* the texture's transform, as an object's, placing it
                                       in its space; NULL: none */
    int nsteps;
} glint_texture;

/* The scene format's defaults for a kind: no file, repeat, even 1, odd 0,
 * scale 1, offset 0, space UV for images and chequers and OBJECT for the
 * other patterns, mapping UV, axis z, the kind's own colours, 6 octaves,
 * lacunarity 2, gain 0.5, turbulence 5 for marble, 0.6 for wood, no
 * transform. */
GLINT_API glint_texture glint_texture_default(glint_texture_kind kind);
/* Reads an image texture's file now: a file that cannot be read or decoded
 * is GLINT_ERR_INPUT naming it. */
GLINT_API glint_rc glint_scene_add_texture(glint_scene *scene, const glint_texture *t,
                                           int *index, glint_error *err);

/* The Whitted material of docs/scene-format.md and src/shade/material.h. */
typedef struct glint_material {
    double color[3];    /* base colour, components >= 0 */
    double ambient;     /* >= 0: share of the scene's ambient light */
    double diffuse;     /* >= 0: Lambert term */
    double specular;    /* >= 0: Phong highlight strength */
    double shininess;   /* >= 0: Phong exponent */
    double reflect;     /* 0 to 1: mirror reflection */
    double transmit;    /* 0 to 1: light passed through */
    double ior;         /* > 0: 1 is plain transparency, otherwise refraction */
    double tint[3];     /* filters transmitted light and shadows, components >= 0 */
    int texture;        /* -1: none; else an index from glint_scene_add_texture,
                           whose colour multiplies color */
    double absorption[3]; /* per unit length inside (Beer-Lambert), components >= 0 */
    double emission[3];   /* light of its own, added unlit; components >= 0 */
    int fresnel_off;      /* nonzero: reflect and transmit as given at any angle (the
                             scene format's fresnel: false) */
    int bump;             /* nonzero: the normal leans with bump_texture's gradient (bump:) */
    int bump_texture;     /* with bump: an index from glint_scene_add_texture, a texture
                             in space OBJECT or WORLD */
    double bump_strength; /* with bump: how far the normal leans, finite; 1 as given */
} glint_material;

/* Matte white: colour 1, ambient 1, diffuse 1, specular 0, shininess 50,
 * reflect 0, transmit 0, ior 1, tint 1, no texture, no absorption or
 * emission, Fresnel on, no bump (strength 1) (the scene format's
 * defaults). */
GLINT_API glint_material glint_material_default(void);
GLINT_API glint_rc glint_scene_add_material(glint_scene *scene, const glint_material *m,
                                            int *index, glint_error *err);

/* The lights of the scene format (docs/scene-format.md), with the fields
 * each kind reads. */
typedef enum glint_light_kind {
    GLINT_LIGHT_POINT,       /* position, color, attenuation */
    GLINT_LIGHT_DIRECTIONAL, /* direction, color */
    GLINT_LIGHT_SPOT,        /* position, look_at, inner_angle, outer_angle, color,
                                attenuation */
    GLINT_LIGHT_AREA,        /* position (the centre), edge_u, edge_v, samples, color,
                                attenuation */
} glint_light_kind;

typedef struct glint_light {
    glint_light_kind kind;
    double position[3];
    double color[3]; /* carries the intensity; components >= 0, may exceed 1 */
    /* c, l, q: intensity / (c + l d + q d^2) at distance d; each >= 0.
     * {1, 0, 0} (and all zero, so that a light set up without it keeps its
     * meaning) is no falloff. */
    double attenuation[3];
    double direction[3];  /* DIRECTIONAL: the way the light travels, not zero */
    double look_at[3];    /* SPOT: the cone's axis runs from position to here */
    double inner_angle;   /* SPOT: degrees of full intensity, 0 to < 180 */
    double outer_angle;   /* SPOT: degrees where it reaches zero, > inner, < 180 */
    double edge_u[3], edge_v[3]; /* AREA: the rectangle's edges, not zero or parallel */
    int samples;          /* AREA: N for N x N samples, 1 to 64 */
} glint_light;

/* The scene format's defaults for a kind: colour 1, no falloff, spot
 * angles 20 and 30, 4 x 4 area samples; positions, directions and edges
 * zero. */
GLINT_API glint_light glint_light_default(glint_light_kind kind);

GLINT_API glint_rc glint_scene_add_light(glint_scene *scene, const glint_light *l, int *index,
                                         glint_error *err);

typedef enum glint_shape_kind {
    GLINT_SHAPE_SPHERE,
    GLINT_SHAPE_PLANE,
    GLINT_SHAPE_QUAD,
    GLINT_SHAPE_BOX,
    GLINT_SHAPE_CYLINDER,
    GLINT_SHAPE_TRIANGLE,
    GLINT_SHAPE_MESH,
    GLINT_SHAPE_CONE,
    GLINT_SHAPE_DISK,
    GLINT_SHAPE_TORUS,
    GLINT_SHAPE_POLYHEDRON,
    GLINT_SHAPE_CSG,
} glint_shape_kind;

/* The shapes, in their own coordinates, with the rules of the scene format.
 * A triangle's (u, v) are (0, 0), (1, 0), (0, 1) at p0, p1, p2 unless it has
 * its own. */
typedef struct glint_sphere { double center[3], radius; } glint_sphere;          /* radius > 0 */
typedef struct glint_plane { double point[3], normal[3]; } glint_plane;          /* normal not 0 */
typedef struct glint_quad { double origin[3], edge_u[3], edge_v[3]; } glint_quad; /* edges not parallel */
typedef struct glint_box { double min[3], max[3]; } glint_box; /* max > min on every axis */
typedef struct glint_cylinder {
    double base[3]; /* centre of the bottom; the axis is +y */
    double radius, height; /* > 0 */
    int capped;            /* non-zero: closed ends */
} glint_cylinder;
typedef struct glint_triangle {
    double p0[3], p1[3], p2[3]; /* not on one line */
    int has_uv;                 /* non-zero: uv holds the (u, v) of p0, p1 and p2 */
    double uv[3][2];
} glint_triangle;
typedef struct glint_mesh { int index; } glint_mesh; /* from glint_scene_add_mesh */
typedef struct glint_cone {
    double base[3];    /* centre of the bottom; the axis is +y */
    double radius;     /* at the base, > 0 */
    double top_radius; /* at base + height, >= 0; 0 is pointed */
    double height;     /* > 0 */
    int capped;        /* non-zero: closed ends */
} glint_cone;
typedef struct glint_disk {
    double center[3], normal[3]; /* normal not 0 */
    double radius;               /* > 0 */
    double inner_radius;         /* 0 <= inner_radius < radius: an annulus when > 0 */
} glint_disk;
typedef struct glint_torus {
    double center[3];    /* round the +y axis through center */
    double major_radius; /* > 0: of the circle the tube follows, in the xz plane */
    double minor_radius; /* > 0: of the tube */
} glint_torus;

/* A closed solid of flat faces: a preset, or vertices and faces. */
typedef enum glint_polyhedron_preset {
    GLINT_POLYHEDRON_FACES, /* not a preset: vertices and faces */
    GLINT_POLYHEDRON_TETRAHEDRON,
    GLINT_POLYHEDRON_CUBE,
    GLINT_POLYHEDRON_OCTAHEDRON,
    GLINT_POLYHEDRON_DODECAHEDRON,
    GLINT_POLYHEDRON_ICOSAHEDRON,
} glint_polyhedron_preset;
typedef struct glint_polyhedron {
    glint_polyhedron_preset preset;
    double center[3];  /* a preset's centre */
    double radius;     /* a preset's circumradius, > 0 */
    /* GLINT_POLYHEDRON_FACES: at least 4 vertices and 4 faces; face i has
     * face_sizes[i] (>= 3) vertex indices, listed one face after another in
     * indices, counter-clockwise seen from outside. The solid must be
     * closed, each face planar (to 0.1% of its size), simple and with area,
     * each edge shared by two faces running along it opposite ways. */
    const double (*vertices)[3];
    int nvertices;
    const int *indices;
    const int *face_sizes;
    int nfaces;
} glint_polyhedron;

/* Constructive solid geometry: op applied to the operands (difference: the
 * first minus all the others). Each operand is an object: a closed solid
 * (sphere, box, capped cylinder or cone, torus, polyhedron, closed mesh)
 * or another csg, with its own transform, applied before the enclosing
 * csg's, and its own material, or -1: the nearest enclosing csg's (the
 * object's material), else for a mesh the file's own. */
typedef enum glint_csg_op {
    GLINT_CSG_UNION,
    GLINT_CSG_INTERSECTION,
    GLINT_CSG_DIFFERENCE,
} glint_csg_op;
struct glint_object;
typedef struct glint_csg {
    glint_csg_op op;
    const struct glint_object *operands; /* at least 2; at most 256 solids in all */
    int noperands;
} glint_csg;

typedef struct glint_shape {
    glint_shape_kind kind;
    union {
        glint_sphere sphere;
        glint_plane plane;
        glint_quad quad;
        glint_box box;
        glint_cylinder cylinder;
        glint_triangle triangle;
        glint_mesh mesh;
        glint_cone cone;
        glint_disk disk;
        glint_torus torus;
        glint_polyhedron polyhedron;
        glint_csg csg;
    };
} glint_shape;

/* One step of a transform, as in the scene format's transform list. */
typedef enum glint_step_kind {
    GLINT_STEP_TRANSLATE, /* v[0..2]: the offset */
    GLINT_STEP_ROTATE,    /* v[0..2]: axis (not zero), v[3]: degrees, right-handed */
    GLINT_STEP_SCALE,     /* v[0..2]: factors, none 0 */
    GLINT_STEP_SHEAR,     /* v[0..5]: xy, xz, yx, yz, zx, zy (x' = x + xy*y + xz*z, ...) */
    GLINT_STEP_MATRIX,    /* v[0..11]: 3 rows of 4, row-major, acting on column vectors */
} glint_step_kind;

typedef struct glint_step {
    glint_step_kind kind;
    double v[12];
} glint_step;

/* Reads a triangle mesh file (OBJ, PLY, STL, OFF, glTF, or any format
 * assimp reads) with its own materials, for objects to place: each object
 * with a GLINT_SHAPE_MESH shape is an instance sharing its triangles. */
GLINT_API glint_rc glint_scene_add_mesh(glint_scene *scene, const char *path, int *index,
                                        glint_error *err);
/* The same with the scene format's smooth_angle: vertex normals are shared
 * across edges whose faces meet at less than this many degrees (0 to 180;
 * 0 is faceted). glint_scene_add_mesh uses the format's default. */
GLINT_API glint_rc glint_scene_add_mesh_smoothed(glint_scene *scene, const char *path,
                                                 double smooth_angle, int *index,
                                                 glint_error *err);

typedef struct glint_object {
    glint_shape shape;
    int material;            /* an index from glint_scene_add_material; for a
                                mesh, -1: the file's own materials; for a csg,
                                -1: each operand's own */
    const glint_step *steps; /* the transform, first step applied first; NULL: none */
    int nsteps;
} glint_object;

/* Refuses a shape out of its rules, a material index not added yet, or a
 * transform that is not invertible; messages name the csg operand by its
 * path (operands[1].operands[0]). */
GLINT_API glint_rc glint_scene_add_object(glint_scene *scene, const glint_object *obj,
                                          int *index, glint_error *err);

/* Fog along camera, reflected and refracted rays (src/shade/fog.h). */
typedef enum glint_fog_kind {
    GLINT_FOG_NONE,
    GLINT_FOG_EXPONENTIAL, /* keeps exp(-density d) of what lies at distance d */
    GLINT_FOG_LINEAR,      /* clear up to start, opaque from end */
} glint_fog_kind;
typedef struct glint_fog {
    glint_fog_kind kind;
    double color[3];       /* components >= 0 */
    double density;        /* EXPONENTIAL: > 0 */
    double start, end;     /* LINEAR: 0 <= start < end */
    double height_falloff; /* >= 0: the air thins upwards as exp(-height_falloff y); 0 none */
} glint_fog;

/* The scene format's defaults for a kind: colour 0.5, start 0, no height
 * fall-off; density and end 0, which the kind must be given. */
GLINT_API glint_fog glint_fog_default(glint_fog_kind kind);
/* Replaces the scene's fog (GLINT_FOG_NONE: none). */
GLINT_API glint_rc glint_scene_set_fog(glint_scene *scene, const glint_fog *fog,
                                       glint_error *err);

/* Prepares the scene for rendering (bounds, the BVH). Call after the last
 * add; a scene with objects added since its last build refuses to render. */
GLINT_API glint_rc glint_scene_build(glint_scene *scene, glint_error *err);
/* The threads the scene's later builds (glint_scene_build, the rebuilds of
 * glint_scene_set_time) and mesh imports (glint_scene_add_mesh) run on: 0
 * to 1024, 0 for glint_default_threads (a new scene's setting). Renders
 * take theirs from glint_settings. */
GLINT_API glint_rc glint_scene_set_threads(glint_scene *scene, int threads, glint_error *err);

/* ---- rendering ----------------------------------------------------------- */

typedef struct glint_film {
    int width, height;
    float *rgb;   /* width*height*3 floats, row 0 at the top, linear values */
    float *alpha; /* NULL, or width*height coverage values in [0, 1]: glint_render
                     fills it when settings.alpha is set; a region or tile render
                     fills it when the caller allocated it */
} glint_film;

/* A rectangle of pixels: x0 <= x < x1, y0 <= y < y1, (0, 0) the top left. */
typedef struct glint_rect {
    int x0, y0, x1, y1;
} glint_rect;

typedef struct glint_stats {
    uint64_t primary_rays, secondary_rays, shadow_rays; /* primary: camera rays, one per
                                                            pixel sample */
    double seconds; /* wall time of the render */
} glint_stats;

/* Where a render is, passed to the progress callback. */
typedef struct glint_progress {
    double percent;          /* 0 to 100; exactly 100 when the last pixel is done */
    uint64_t samples_done;   /* pixel samples finished so far (adaptive sampler: pixels,
                                as its sample count is known only at the end) */
    uint64_t samples_total;  /* pixel samples this render traces (adaptive: pixels) */
    uint64_t rays;           /* rays of every kind traced so far */
    double seconds;          /* since the render started */
} glint_progress;

/* Every member may be NULL. The callbacks run on render threads. tile_done
 * and progress are serialised (never two at once, one render's calls in the
 * order their counts grow) and are called after each finished tile,
 * tile_done first; they should return quickly, as the render waits. */
typedef struct glint_callbacks {
    void *user; /* passed to every callback */
    /* A tile finished: pixels [x0, x1) x [y0, y1) of the image are final in
     * film (at their image position, or offset by the region's origin when
     * the film is region-sized: see glint_render_region). */
    void (*tile_done)(void *user, const glint_film *film, int x0, int y0, int x1, int y1);
    void (*progress)(void *user, const glint_progress *p);
    /* Polled before each tile by every render thread, possibly at once from
     * several: non-zero stops the render, which then returns
     * GLINT_ERR_CANCELLED. Tiles in flight finish first, so cancellation
     * takes effect within one tile's time. Read an atomic flag here. */
    int (*cancelled)(void *user);
} glint_callbacks;

/* Renders the whole image into *film (allocated here; free it with
 * glint_film_free). settings NULL: the scene's own. callbacks and stats may
 * be NULL. On any error, cancellation included, the film is left empty. */
GLINT_API glint_rc glint_render(const glint_scene *scene, const glint_settings *settings,
                                const glint_callbacks *callbacks, glint_film *film,
                                glint_stats *stats, glint_error *err);

/* Allocates a film of width x height pixels, all zero. */
GLINT_API glint_rc glint_film_alloc(glint_film *film, int width, int height, glint_error *err);
/* Frees a film's pixels and empties it; NULL and an empty film are fine. */
GLINT_API void glint_film_free(glint_film *film);

/* Renders the pixels of region into film, which the caller allocated
 * either at the image's size (settings width x height: pixels land at their
 * image position) or at the region's size (pixel (x0, y0) lands at the
 * film's top left). Pixels outside the region are not touched, and a pixel's
 * value does not depend on the region it was rendered in, so regions
 * rendered apart (by threads, processes or machines) assemble into the
 * byte-identical image. On cancellation the film keeps every tile reported
 * done. */
GLINT_API glint_rc glint_render_region(const glint_scene *scene, const glint_settings *settings,
                                       const glint_rect *region,
                                       const glint_callbacks *callbacks, glint_film *film,
                                       glint_stats *stats, glint_error *err);

/* The image's tile grid: square tiles (16 pixels a side; the last row and
 * column may be cut short), numbered row by row from the top left. A whole
 * render on one thread renders them in this order; on several, the tiles
 * (of the image, the region or the list, in that order) are cut into one
 * run of consecutive tiles a thread, each thread renders its own run in
 * order, and one whose run is done takes the last tile left of the
 * longest other run. */
GLINT_API glint_rc glint_tile_count(const glint_settings *settings, int *count,
                                    glint_error *err);
GLINT_API glint_rc glint_tile_rect(const glint_settings *settings, int tile, glint_rect *out,
                                   glint_error *err);

/* Renders the listed tiles (each index once, any order) into a film the
 * caller allocated either at the image's size or at the size of the
 * smallest rectangle holding every listed tile (its top-left pixel at the
 * film's top left: a batch of neighbouring tiles needs no image-sized film),
 * as glint_render_region does for a region. */
GLINT_API glint_rc glint_render_tiles(const glint_scene *scene, const glint_settings *settings,
                                      const int *tiles, int ntiles,
                                      const glint_callbacks *callbacks, glint_film *film,
                                      glint_stats *stats, glint_error *err);

/* ---- progressive rendering -------------------------------------------------
 * An image rendered in passes that converge to exactly glint_render's film:
 * a first pass of 1 sample per pixel, later passes adding the rest of each
 * pixel's samples in the batch order. The accumulating film keeps, per
 * pixel, the sum of the samples so far, counted per tile. */

typedef struct glint_accum {
    int width, height;
    int ntiles;        /* the image's tile grid (glint_tile_count) */
    int *tile_samples; /* per tile: samples per pixel summed so far */
    float *sum;        /* width*height*3: per pixel, the sum of those samples */
    float *cover;      /* width*height: per pixel, the sum of their coverage (alpha) */
    int *tile_div;     /* per tile: what sum is divided by (tile_samples, or 1 once
                          the adaptive sampler's final pass left exact values) */
} glint_accum;

/* An accumulating film of width x height with no sample in it. */
GLINT_API glint_rc glint_accum_alloc(glint_accum *a, int width, int height, glint_error *err);
/* Frees it and empties it; NULL is fine. */
GLINT_API void glint_accum_free(glint_accum *a);
/* Forgets every sample (after the camera or the scene changed). */
GLINT_API void glint_accum_clear(glint_accum *a);

/* Brings every tile of the accumulating film (of the settings' size) up to
 * upto samples per pixel (1 to settings.samples), tracing only the samples
 * each lacks. Tiles are handed out and reported as in glint_render
 * (tile_done's film is NULL: resolve to see the pixels); a cancelled pass
 * leaves every tile whole, either as it was or brought up to upto. */
GLINT_API glint_rc glint_render_pass(const glint_scene *scene, const glint_settings *settings,
                                     int upto, const glint_callbacks *callbacks, glint_accum *a,
                                     glint_stats *stats, glint_error *err);
/* Writes the mean of each pixel's samples into film (image-sized,
 * allocated by the caller), for the pixels of rect (NULL: all); pixels of
 * tiles with no sample are not touched. Once every tile has
 * settings.samples, film is byte-identical to glint_render's. *min_samples
 * (may be NULL) is the fewest samples per pixel of any tile. */
GLINT_API glint_rc glint_accum_resolve(const glint_accum *a, const glint_rect *rect,
                                       glint_film *film, int *min_samples, glint_error *err);

/* The 8-bit RGB pixels glint_film_write puts in an 8-bit file, for the
 * pixels of rect (NULL: all): dst holds film.width * film.height * 3 bytes,
 * row 0 at the top, and only rect's are written. For showing a film. */
GLINT_API glint_rc glint_film_quantize(const glint_film *film, const glint_rect *rect,
                                       glint_transfer transfer, uint8_t *dst, glint_error *err);

/* ---- resume files ----------------------------------------------------------
 * An interrupted render kept on disk, to be finished later into the
 * byte-identical image. The record is tile by tile (the grid of
 * glint_tile_count): which tiles are final, and their pixels, with the
 * settings and a fingerprint of the scene and settings so that a render of
 * anything else refuses it. The format is described in src/render/resume.h;
 * files are written atomically. */

typedef struct glint_resume {
    glint_settings settings; /* of the render (threads is kept but never compared) */
    uint64_t fingerprint;    /* glint_fingerprint of the scene and settings */
    int ntiles;              /* the image's tile count */
    unsigned char *done;     /* ntiles flags: non-zero, tile i is final in film */
    glint_film film;         /* image-sized; final tiles hold their pixels */
    char *note;              /* the caller's bytes, kept verbatim (NUL-terminated; may be NULL) */
    size_t note_len;
} glint_resume;

/* A 64-bit hash of everything in a built scene a pixel depends on (camera,
 * shapes, transforms, materials, textures with their pixels, lights, meshes)
 * and of the settings but the thread count. */
GLINT_API glint_rc glint_fingerprint(const glint_scene *scene, const glint_settings *settings,
                                     uint64_t *out, glint_error *err);

/* A record with no tile final, for this scene and settings (NULL: the
 * scene's). Free it with glint_resume_free. */
GLINT_API glint_rc glint_resume_init(glint_resume *r, const glint_scene *scene,
                                     const glint_settings *settings, glint_error *err);
/* Frees what the record holds and empties it; NULL is fine. */
GLINT_API void glint_resume_free(glint_resume *r);
/* Replaces the note with a copy of len bytes (at most 1 MiB). */
GLINT_API glint_rc glint_resume_set_note(glint_resume *r, const void *data, size_t len,
                                         glint_error *err);
/* Writes the record to path (atomically: the file is whole or not changed). */
GLINT_API glint_rc glint_resume_write(const glint_resume *r, const char *path, glint_error *err);
/* Reads a record written by glint_resume_write. A file that is not one, is
 * cut short or damaged is GLINT_ERR_INPUT naming it. */
GLINT_API glint_rc glint_resume_read(const char *path, glint_resume *out, glint_error *err);
/* GLINT_OK when the record belongs to a render of this scene with these
 * settings (NULL: the scene's); otherwise GLINT_ERR_INPUT naming the first
 * difference (size, samples, depth, transfer, or the scene and camera). */
GLINT_API glint_rc glint_resume_check(const glint_resume *r, const glint_scene *scene,
                                      const glint_settings *settings, glint_error *err);
/* Renders the tiles not yet final into r->film, marking each final as it
 * is finished (before callbacks->tile_done sees it). Progress counts the
 * whole image, tiles final before the call included. Checks the record
 * first (glint_resume_check). On cancellation r holds exactly the tiles
 * whose pixels are in its film, ready for glint_resume_write; when every
 * tile is final, r->film is the image glint_render makes. */
GLINT_API glint_rc glint_resume_render(const glint_scene *scene, const glint_settings *settings,
                                       const glint_callbacks *callbacks, glint_resume *r,
                                       glint_stats *stats, glint_error *err);
/* Tiles final in the record. */
GLINT_API int glint_resume_done(const glint_resume *r);

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
    const float *alpha;      /* NULL (the film's own alpha, if it has one), or width*height
                                coverage values in [0, 1] (linear): PNG and EXR get an
                                alpha channel; other formats ignore it */
    int threads;             /* PNG: threads that compress it, 0 to 1024 (0: one per
                                core); the file is the same for any number */
} glint_write_options;

/* Writes the film to path ("-": standard output). Float formats (.hdr,
 * .pfm, .exr) take the linear film as it is; the others quantise it through
 * the transfer function. The file is encoded in memory first, then written
 * beside the target and renamed into place, so it appears complete or not at
 * all (details: README.md, "Output files"). opts may be NULL (defaults). */
GLINT_API glint_rc glint_film_write(const glint_film *film, const char *path,
                                    const glint_write_options *opts, glint_error *err);

/* Checks, before a render, that glint_film_write(path, opts) can work: a
 * known format and bit depth for it, not a directory or a read-only file, an
 * existing folder where a file can be created. Errors are GLINT_ERR_INPUT. */
GLINT_API glint_rc glint_output_check(const char *path, const glint_write_options *opts, glint_error *err);

/* A format from its name or extension ("png", "jpg", "exr"...). */
GLINT_API glint_rc glint_format_parse(const char *name, glint_format *out, glint_error *err);

/* ---- frame sequences -----------------------------------------------------
 * The pieces every front end that renders an animation shares (the command
 * line, the MPI driver): which frames to render, what each is called, and
 * whether a frame is already done. Frames are numbered from 1. */

/* Parses a frame list against an animation of frames frames: "A:B" (A to B,
 * both included) or "N" (one frame), with 1 <= A <= B <= frames. */
GLINT_API glint_rc glint_frames_parse(const char *spec, int frames, int *first, int *last,
                                      glint_error *err);

/* The output name of frame number frame (>= 0) for pattern. A printf-style
 * field in the pattern takes the number: %d, %Nd or %0Nd (N from 1 to 9);
 * "%%" is a literal %. Without a field, "-%04d" goes before the extension
 * (out.png: out-0001.png; out: out-0001). Refuses (GLINT_ERR_INPUT) a
 * pattern with two fields or another % conversion, "-" (standard output),
 * and a result that does not fit in size bytes. */
GLINT_API glint_rc glint_frame_path(const char *pattern, int frame, char *out, size_t size,
                                    glint_error *err);

/* Whether path is a complete image: a regular file that decodes whole in
 * its format (any format glint writes), of width x height pixels (0 for
 * either: any). Files are written to a temporary name and renamed into
 * place, so a frame interrupted mid-write is absent, not half there; this
 * also catches a file cut short by other means. 1 yes, 0 no. */
GLINT_API int glint_output_complete(const char *path, int width, int height);

#ifdef __cplusplus
}
#endif

#endif

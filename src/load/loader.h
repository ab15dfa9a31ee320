/* loader: what the parts of the scene-file front end share. A load runs in
 * two passes. The first walks the scene file, then each of its includes in
 * turn (depth first), adding lights, textures, images, materials,
 * transforms and objects to the scene as it meets them; names used before
 * they are known are noted as references. The second (load.c) resolves
 * those references, checks the settings as a whole and builds the scene.
 * Every tree stays alive until the end so that late errors can still point
 * at the node they are about.
 *
 * One file per part of the format: keys.c (reading keys and values, with
 * the messages), keyed.c (keyed values, which animate what they are read
 * into), paths.c (paths and files named in a scene), settings.c (image,
 * camera, animation and fog), lights.c, textures.c, materials.c,
 * transform.c, objects.c (shapes, meshes, objects), load.c (files,
 * includes, the second pass). Each section builds the scene only through
 * scene_add_* and the scene's setters.
 *
 * Internal to src/load: nothing here is part of the public API. */
#ifndef GLINT_LOAD_LOADER_H
#define GLINT_LOAD_LOADER_H

#include <stdbool.h>
#include <stdint.h>

#include "core/error.h"
#include "load/load.h"
#include "load/names.h"
#include "load/yaml_doc.h"
#include "scene/scene.h"

/* Room for a user string in a message, escaped (ydoc_show). */
#define SHOWN (YDOC_SHOW_MAX * 4 + 8)

typedef struct lfile {
    char *name; /* shown in messages */
    char *key;  /* tidied path, for finding include cycles */
    char *dir;  /* folder that relative paths resolve against; "" for none */
    char *data; /* the text while it is parsed, when the loader read it */
    ydoc *doc;
} lfile;

/* A name used by a material (for a texture) or an object (for a material),
 * to be resolved once every file has been read. */
typedef struct ref {
    int index; /* the material or object; for a csg's operand, the scene's csg */
    int leaf;  /* the csg's operand; 0 otherwise */
    int file;
    uint32_t node; /* the name */
} ref;

/* Where a texture or material name was defined, and what it names. */
typedef struct def {
    int file;
    uint32_t node;
    int index;
} def;

/* Settings a file may set; the first file to set one wins (includers are
 * read before what they include). */
enum {
    SET_WIDTH = 1 << 0,
    SET_HEIGHT = 1 << 1,
    SET_SAMPLES = 1 << 2,
    SET_DEPTH = 1 << 3,
    SET_BACKGROUND = 1 << 4,
    SET_TRANSFER = 1 << 5,
    SET_EYE = 1 << 6,
    SET_LOOK_AT = 1 << 7,
    SET_UP = 1 << 8,
    SET_FOV = 1 << 9,
    SET_AMBIENT = 1 << 10,
    SET_ADC_BAILOUT = 1 << 11,
    SET_FOG = 1 << 12,
    SET_SAMPLER = 1 << 13,
    SET_THRESHOLD = 1 << 14,
    SET_ADAPTIVE_DEPTH = 1 << 15,
    SET_ALPHA = 1 << 16,
    SET_PROJECTION = 1 << 17,
    SET_APERTURE = 1 << 18,
    SET_FOCUS = 1 << 19,
    SET_VIEW_WIDTH = 1 << 20,
    SET_SHUTTER = 1 << 21,
    SET_ANIMATION = 1 << 22,
};

/* A texture file read in the first pass, its image decoded at the end of
 * it (load_decode_images), into the scene's image `index`. */
typedef struct image_job {
    char *data, *shown; /* the file's bytes; its name in messages */
    size_t size;
    int file;      /* where the texture names it */
    uint32_t node;
    int index;
    image img;
    glint_rc rc;
    glint_error err;
} image_job;

typedef struct loader {
    scene *s;
    scene_reader reader;
    void *user;
    glint_error *err;
    lfile *files;
    int nfiles, cap_files;
    int cur; /* the file being read */
    /* The include chain: files open inside one another, and in each the
     * include entry being followed. */
    int chain[LOAD_MAX_INCLUDE_DEPTH];
    uint32_t via[LOAD_MAX_INCLUDE_DEPTH];
    int depth;
    names texture_names, material_names; /* name -> index into defs */
    def *defs;
    int ndefs, cap_defs;
    names images; /* resolved path -> index into the scene's images */
    names meshes; /* resolved path -> index into the scene's meshes */
    ref *texture_refs, *material_refs, *csg_refs, *bump_refs;
    int ntexture_refs, cap_texture_refs, nmaterial_refs, cap_material_refs;
    int ncsg_refs, cap_csg_refs;
    int nbump_refs, cap_bump_refs;
    int default_material; /* -1 until an object needs it */
    unsigned set;
    /* Scene-wide values, handed to the scene once every file is read. */
    glint_settings settings;
    camera camera;
    vec3 background, ambient;
    fog fog;
    int size_file, camera_file; /* where the image size and camera were set; -1: nowhere */
    uint32_t size_node, camera_node;
    uint32_t width_node;  /* the camera's width, or YDOC_NONE (checked at the end) */
    int fov_file;         /* where the camera's fov was set (checked at the end) */
    uint32_t fov_node;
    anim_channel *pending; /* keyed values read, waiting for what they animate */
    int npending, cap_pending;
    /* Room for a transform's steps and their channels as they are read,
     * kept from one transform to the next (transform.c). */
    anim_step *step_room;
    int cap_step_room;
    anim_channel *channel_room;
    int cap_channel_room;
    image_job *image_jobs; /* texture files waiting to be decoded */
    int nimage_jobs, cap_image_jobs;
} loader;


/* ---- messages (keys.c) ------------------------------------------------ */

/* Fails with "FILE:LINE:COL: message" at node at of file. */
glint_rc load_fail_in(loader *L, int file, uint32_t at, const char *fmt, ...) GLINT_PRINTF(4, 5);
/* The same in the file being read. */
glint_rc load_fail(loader *L, uint32_t at, const char *fmt, ...) GLINT_PRINTF(3, 4);
const ydoc *load_doc(const loader *L);
const ynode *load_node(const loader *L, uint32_t i);
/* A scalar's text made printable, into buf (SHOWN bytes). */
const char *load_shown(const loader *L, uint32_t i, char *buf);
/* "expected WHAT for 'KEY', got ..." at v. */
glint_rc load_expected(loader *L, uint32_t v, const char *what, const char *key);

/* ---- keys of a mapping (keys.c) --------------------------------------- */

/* Refuses the first key of map that is not in valid (a NULL-terminated
 * list); where says where the mapping is ("in sphere", "at the top level"). */
glint_rc load_check_keys(loader *L, uint32_t map, const char *const *valid, const char *where);
/* The same in a mapping of a type, "in NAME" then tail (" light", or ""):
 * the words are joined only for a message, not for every object. */
glint_rc load_check_keys_in(loader *L, uint32_t map, const char *const *valid, const char *name,
                            const char *tail);
/* The value under key, or YDOC_NONE. */
uint32_t load_get(const loader *L, uint32_t map, const char *key);
/* The value under key, which must be there; what names the mapping. */
glint_rc load_need(loader *L, uint32_t map, const char *key, const char *what, uint32_t *v);
glint_rc load_want_map(loader *L, uint32_t v, const char *key);
/* Each item of the sequence v through item; key names the list. */
glint_rc load_list(loader *L, uint32_t v, const char *key, glint_rc (*item)(loader *, uint32_t));
/* Whether this file may set the setting (a SET_* bit): no file read before
 * it did. */
bool load_claim(loader *L, unsigned bit);
/* Notes a name to resolve after every file is read. */
glint_rc load_add_ref(loader *L, ref **refs, int *n, int *cap, int index, uint32_t name);

/* ---- values (keys.c); key names the value in messages ------------------ */

glint_rc load_number(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_positive(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_nonneg(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_unit(loader *L, uint32_t v, const char *key, float *out); /* [0, 1] */
glint_rc load_nonzero(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_int(loader *L, uint32_t v, const char *key, int lo, int hi, int *out);
glint_rc load_bool(loader *L, uint32_t v, const char *key, bool *out);
/* n numbers in a sequence; what describes it ("[x, y, z]"). */
glint_rc load_numbers(loader *L, uint32_t v, const char *key, const char *what, int n,
                      float *out);
glint_rc load_vec3(loader *L, uint32_t v, const char *key, vec3 *out);
glint_rc load_nonzero_vec3(loader *L, uint32_t v, const char *key, vec3 *out);
/* A colour: a number (grey) or [r, g, b], no component below 0. */
glint_rc load_color(loader *L, uint32_t v, const char *key, vec3 *out);
/* A string out of valid (NULL-terminated); *out its index; what names the
 * kind of thing ("object type"). */
glint_rc load_enum(loader *L, uint32_t v, const char *key, const char *what,
                   const char *const *valid, int *out);
/* A name (of a material or texture): a non-empty string or a number. */
glint_rc load_name(loader *L, uint32_t v, const char *what);
/* A path written in the file: a non-empty string without NUL bytes. */
glint_rc load_path_key(loader *L, uint32_t v, const char *key);
/* Required fields of a mapping. */
glint_rc load_need_vec3(loader *L, uint32_t map, const char *key, const char *what, vec3 *out);
glint_rc load_need_positive(loader *L, uint32_t map, const char *key, const char *what,
                            float *out);

/* ---- keyed values (keyed.c) ------------------------------------------- */

/* Reads one plain value of key at v into out (as many floats as it has). */
typedef glint_rc (*load_value_fn)(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_read_number(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_read_nonneg(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_read_positive(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_read_vec3(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_read_nonzero_vec3(loader *L, uint32_t v, const char *key, float *out);
glint_rc load_read_color(loader *L, uint32_t v, const char *key, float *out);

/* Whether v is a keyed value: a mapping with 'keys'. */
bool load_is_keyed(const loader *L, uint32_t v);
/* A value that may be keyed ({keys: [[t, v], ...], interpolation: ...}).
 * Plain, it is read into out (dim floats). Keyed, each key's value is read
 * by read, the track joins the scene, out gets the first key's value, and
 * a channel writing dim floats at offset (in floats into the animated
 * structure), clamped to [lo, hi], waits for load_anim_bind. */
glint_rc load_anim_value(loader *L, uint32_t v, const char *key, int dim, load_value_fn read,
                         float *out, int offset, float lo, float hi);
/* Aims the waiting channels at (target, index) and adds them. */
glint_rc load_anim_bind(loader *L, anim_target target, int index);
/* Forgets the waiting channels (a value another file already set). */
void load_anim_drop(loader *L);

/* ---- paths and files (paths.c) ---------------------------------------- */

/* dir joined to rel (unless rel is absolute or dir is empty), tidied
 * ("a/./b/../c" is "a/c"); NULL when out of memory. */
char *path_join(const char *dir, const char *rel);
/* The folder part of a path: "a/b.yaml" -> "a", "b.yaml" -> "", "/b" -> "/". */
char *path_dir(const char *path);
/* A copy with control bytes escaped as \xNN, so that messages naming it
 * stay on one line; NULL when out of memory. */
char *path_printable(const char *path);
/* "cannot read KIND 'written' (resolved): reason", or the size-limit
 * message when reason is NULL. */
glint_rc load_cannot_read(loader *L, uint32_t at, const char *kind, const char *written,
                          const char *resolved, const char *reason);
/* Reads a file named in the scene through the reader. written is the path
 * as written, resolved the path the reader gets; kind says what the file is
 * for ("include", "texture"). */
glint_rc load_named_file(loader *L, uint32_t at, const char *written, const char *resolved,
                         const char *kind, char **data, size_t *size);

/* ---- sections: each reads one part of the format into the scene -------- */

glint_rc load_image_settings(loader *L, uint32_t map); /* settings.c: image: */
glint_rc load_camera(loader *L, uint32_t map);         /* settings.c: camera: */
glint_rc load_animation(loader *L, uint32_t map);      /* settings.c: animation: */
glint_rc load_light(loader *L, uint32_t map);          /* lights.c: one item of lights: */
/* textures.c and materials.c: a texture or material mapping, added;
 * *index gets it. */
glint_rc load_texture(loader *L, uint32_t map, int *index);
/* textures.c: the texture files the first pass read, decoded at once, one
 * thread per file (up to one per core), into their scene images. rc is the
 * first pass's result: a file that does not decode was met before whatever
 * ended the pass, so its error is the one reported. Frees the jobs. */
glint_rc load_decode_images(loader *L, glint_rc rc);
glint_rc load_material(loader *L, uint32_t map, int *index);
/* settings.c: fog: at the top level. */
glint_rc load_fog(loader *L, uint32_t map);
/* materials.c: textures: or materials: at the top level. */
glint_rc load_named(loader *L, uint32_t map, bool textures);
/* transform.c: a list of steps; *index the scene's xform or -1 for none. */
glint_rc load_transform(loader *L, uint32_t list, int *index);
/* The same as a value: *any says whether there were steps. */
glint_rc load_xform(loader *L, uint32_t list, xform *out, bool *any);
glint_rc load_object(loader *L, uint32_t map); /* objects.c: one item of objects: */

/* ---- parts of objects, shared by objects.c, polyhedron.c and csg.c ------ */

/* The format's name for a shape kind. */
const char *load_type_name(shape_kind kind);
/* An object mapping's type, its keys checked; list names where it is. */
glint_rc load_object_type(loader *L, uint32_t map, const char *list, int *type);
/* The shape of an object of the given kind (not a csg). */
glint_rc load_object_shape(loader *L, uint32_t map, shape_kind kind, shape *out);
/* The object's material: an index, or a name to resolve (*name, with
 * *index -1); without one, the default material, or -1 for a mesh. */
glint_rc load_object_material(loader *L, uint32_t map, bool is_mesh, int *index, uint32_t *name);
glint_rc load_polyhedron(loader *L, uint32_t map, shape *out); /* polyhedron.c */
glint_rc load_csg(loader *L, uint32_t map); /* csg.c: a csg object, added to the scene */

#endif

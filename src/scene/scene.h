/* scene: everything a render reads, in flat arrays owned here. Objects name
 * their material, materials their texture, textures their image, all by
 * index; an object's transform is an index into xforms or -1 for none.
 *
 * Invariants once scene_build has run: every index is in range, every
 * transform is invertible, and bounds[] holds each object's world bounds. */
#ifndef GLINT_SCENE_SCENE_H
#define GLINT_SCENE_SCENE_H

#include <stdbool.h>
#include "glint.h"
#include "accel/wide.h"
#include "core/mat4.h"
#include "geom/csg.h"
#include "geom/mesh.h"
#include "geom/polyhedron.h"
#include "geom/shape.h"
#include "io/image.h"
#include "scene/anim.h"
#include "scene/camera.h"
#include "shade/fog.h"
#include "shade/light.h"
#include "shade/material.h"
#include "shade/texture.h"

typedef struct object {
    shape shape;
    int material;   /* -1: a mesh's own per-triangle materials, or a csg's per operand */
    int xform;      /* -1: the shape is in world space */
    bool transmits; /* some material it uses has transmit > 0 (by scene_build) */
    vec3 origin;    /* of object-space textures, in the shape's space (by scene_build) */
    int motion;     /* the anim motion driving its transform, or -1 (by scene_build) */
    bool moving;    /* moves while the shutter is open: its transform is the motion's
                       at each ray's time, not xforms[xform] (by scene_build) */
} object;

#define SCENE_FEW_CROSSED 8

/* A file the scene was read from, and when the front end read its bytes
 * itself (scene_source_read), their fingerprint (fingerprint_file_bytes):
 * what was rendered, which scene_fingerprint then need not read again. */
typedef struct scene_source {
    char *path;
    uint64_t bytes;
    bool read;
} scene_source;

struct glint_scene {
    object *objects;
    int nobjects, cap_objects;
    aabb *bounds; /* world bounds per object, by scene_build */
    size_t cap_bounds; /* room in bounds and unbounded */
    xform *xforms;
    int nxforms, cap_xforms;
    material *materials;
    int nmaterials, cap_materials;
    texture *textures;
    int ntextures, cap_textures;
    image *images;
    int nimages, cap_images;
    light *lights;
    int nlights, cap_lights;
    mesh **meshes;
    int nmeshes, cap_meshes;
    polyhedron **polyhedra;
    int npolyhedra, cap_polyhedra;
    csg **csgs;
    int ncsgs, cap_csgs;

    camera camera;
    vec3 background;
    vec3 ambient; /* ambient light, scaled by each material's ambient */
    fog fog;
    glint_settings settings;
    bvhw bvh;        /* over the objects with finite bounds, by scene_build */
    int32_t *unbounded; /* the others (planes), tested by every ray */
    int nunbounded;
    char *warnings; /* lines for the user from building the scene, or NULL */
    bool built;
    bool any_transmit; /* some material has transmit > 0 (by scene_build) */
    bool any_reflect;  /* some material has reflect > 0 (by scene_build) */
    bool any_absorb;   /* some material absorbs, transmitting or not: an opaque part of a
                          transmitting csg or mesh is crossed too (by scene_build) */
    /* The objects that transmit, in order, when there are at most
     * SCENE_FEW_CROSSED; ncrossed -1 when there are more (by scene_build). */
    int32_t crossed[SCENE_FEW_CROSSED];
    int ncrossed;
    bool flat;         /* the BVH is one leaf or empty: rays test objects in turn */
    double build_seconds; /* wall time of the last scene_build */
    int threads; /* for scene_build, mesh imports and texture decoding: 0 one per CPU (cpus.h) */
    scene_source *sources; /* files the scene was read from, each once (front ends add them) */
    int nsources, cap_sources;

    anim anim;             /* tracks, channels and motions; frames and fps */
    float time;            /* seconds: when the shutter opens (scene_set_time) */
    float shutter_seconds; /* how long it stays open: camera.shutter / fps */
    bool camera_moves;     /* the camera changes while the shutter is open */
};

typedef struct glint_scene scene;

/* A scene with the default camera and settings and nothing in it. */
scene *scene_new(void);
void scene_free(scene *s);

/* Each add returns the new element's index, or -1 when out of memory. */
int scene_add_material(scene *s, const material *m);
int scene_add_texture(scene *s, const texture *t);
int scene_add_image(scene *s, image *img); /* takes ownership of img's pixels */
/* Puts img (its pixels owned from now on) in image i, added empty before. */
void scene_set_image(scene *s, int i, image *img);
int scene_add_light(scene *s, const light *l);
int scene_add_xform(scene *s, const xform *x);
int scene_add_object(scene *s, const shape *sh, int material, int xform);
/* Room for n more objects and n more transforms, asked by a front end that
 * knows how many are coming: grown by doubling, a scene of thousands of
 * objects copied each array several times over, and every copy touched
 * fresh pages. A hint only: false when memory is short, and the adds then
 * grow the arrays as they would have. */
bool scene_reserve_objects(scene *s, int n);
/* Takes ownership of m (allocated with malloc, initialised by mesh_init). */
int scene_add_mesh(scene *s, mesh *m);
/* Appends lines (each ending in '\n'; "" adds nothing) to the scene's
 * warnings; false when out of memory. */
bool scene_add_warnings(scene *s, const char *lines);
/* The warnings so far, "" when none. */
const char *scene_warnings(const scene *s);
/* The same for a polyhedron (by polyhedron_init or _preset) and a csg (by
 * csg_finish); objects place them with shape_polyhedron and shape_csg. */
int scene_add_polyhedron(scene *s, polyhedron *p);
int scene_add_csg(scene *s, csg *c);

/* The scene-wide values a front end sets; each marks the scene unbuilt. */
void scene_set_camera(scene *s, const camera *c);
void scene_set_settings(scene *s, const glint_settings *st);
void scene_set_background(scene *s, vec3 color);
void scene_set_ambient(scene *s, vec3 color);
void scene_set_fog(scene *s, const fog *f);
/* Names resolved after their users were added: a material's texture and an
 * object's material (indices as returned by the adds). */
void scene_set_material_texture(scene *s, int mat, int tex);
void scene_set_material_bump(scene *s, int mat, int tex);
void scene_set_object_material(scene *s, int obj, int mat);
/* The material of operand leaf of the scene's csg number c. */
void scene_set_csg_material(scene *s, int c, int leaf, int mat);

camera scene_camera(const scene *s);
glint_settings scene_settings(const scene *s);
vec3 scene_background(const scene *s);
vec3 scene_ambient(const scene *s);
fog scene_fog(const scene *s);
int scene_object_count(const scene *s);
int scene_material_count(const scene *s);
int scene_texture_count(const scene *s);
int scene_mesh_count(const scene *s);
const struct mesh *scene_mesh(const scene *s, int index);

/* Records a file the scene was read from (a scene file, an include, a
 * texture, a mesh), once however often it is added: its index, or -1 when
 * out of memory. */
int scene_add_source(scene *s, const char *path);
/* The bytes source i was read as (the last read, when it was read more
 * than once). A source without them is read again by scene_fingerprint. */
void scene_source_read(scene *s, int i, const void *data, size_t n);

/* Checks indices and computes derived data; call after the last add. A
 * moving object's bounds hold it over the whole shutter interval. */
glint_rc scene_build(scene *s, glint_error *err);

/* Sets the scene to time t (seconds): the camera, lights, materials and
 * transforms take their animated values at t, the shutter interval becomes
 * [t, t + camera.shutter / fps], and the scene is built again. Errors: a
 * transform that is not invertible at t. */
glint_rc scene_set_time(scene *s, float t, glint_error *err);
/* After scene_set_camera: the shutter interval follows the camera's
 * shutter, and a built scene whose objects start or stop moving is built
 * again. */
glint_rc scene_camera_changed(scene *s, glint_error *err);
/* The camera at time t (its animated values evaluated at t). */
camera scene_camera_at(const scene *s, float t);
/* Bounds of object i over the shutter interval (scene_build's rule). */
aabb scene_object_bounds(const scene *s, int i);
/* The same for object o, whose shape's own bounds (shape_bounds) are b. */
aabb scene_object_bounds_of(const scene *s, const object *o, aabb b);
/* For scene_build: *of, the motion driving each transform or -1 (NULL
 * when there are no motions); false when memory runs out. Free *of. */
bool scene_motions_of(const scene *s, int **of);
/* Which motion drives o's transform (of: from scene_motions_of), and
 * whether o moves while the shutter is open. */
static inline void scene_link_motion(const scene *s, const int *of, object *o)
{
    o->motion = of && o->xform >= 0 && o->xform < s->nxforms ? of[o->xform] : -1;
    o->moving = o->motion >= 0 && s->shutter_seconds > 0.0f;
}
/* A moving object's transform at time t (object -> world, with inverse). */
xform scene_object_xform_at(const scene *s, const object *o, float t);

typedef struct scene_hit {
    shape_hit h;
    int object;
} scene_hit;

/* Nearest hit along r within (tmin, tmax); tmax is not changed. */
bool scene_intersect(const scene *s, const ray *r, scene_hit *hit);
/* The nearest hits of the rays of active (bit k: ray k of r) at once,
 * each as scene_intersect finds it: returns the rays that hit, with
 * hit[k] for each. Coherent rays (a camera's through neighbouring pixels)
 * in a flat scene share the walks of its meshes' hierarchies. */
int scene_intersect8(const scene *s, const ray8 *r, int active, scene_hit *hit);
/* scene_intersect8 for rays that spread (reflected and refracted ones,
 * for which walks shared by eight cost more than they save): together in
 * a flat scene or a tree of one node, where the eight share one box test
 * and the sphere, quad, plane and torus tests, but one by one in a scene
 * with meshes or a deeper tree. The same hits. */
int scene_intersect8_spread(const scene *s, const ray8 *r, int active, scene_hit *hit);
/* The objects of the scene's tree (those with bounds) that a ray from o
 * with a direction anywhere in [dlo, dhi] (component by component) may
 * meet at t >= 0, into list (room for cap), in the tree's order: their
 * count, or -1 when there are more than cap, or the scene's path takes no
 * packets (scene_cone.c). *reach (reach not NULL) gets a box that holds
 * every point where those rays may meet them, or an infinite one where
 * they may meet an unbounded object. A tile's camera rays from a pinhole
 * ask it once for the tile. */
int scene_cone_objects(const scene *s, vec3 o, vec3 dlo, vec3 dhi, int32_t *list, int cap,
                       aabb *reach);
/* The objects of the scene's tree that a shadow ray may meet on its way
 * from a point of box `from` (scene_cone_objects's reach) to a point light
 * at light_at, into list (room for cap), in the tree's order: their
 * count; 0 for an empty box; -1 when there are more than cap, the box is
 * infinite or the scene's path takes no packets. */
int scene_shadow_cone_objects(const scene *s, aabb from, vec3 light_at, int32_t *list, int cap);
/* scene_shadow8 for shadow rays of a bundle that list
 * (scene_shadow_cone_objects) was made for: the unbounded objects and the
 * n of list, without a walk; the same answers. */
bool scene_shadow8_among(const scene *s, const ray8 *r, int active, const int32_t *list, int n,
                         int *blocked, int *crosses);
/* scene_intersect8 for rays of a bundle that list (scene_cone_objects) was
 * made for: the unbounded objects and the n of list, without a walk. The
 * same hits. */
int scene_intersect8_among(const scene *s, const ray8 *r, int active, const int32_t *list,
                           int n, scene_hit *hit);
/* Whether scene_intersect8 walks the scene's rays together (a flat scene
 * holding a mesh that does not move, on an eight-wide path); otherwise it
 * only takes them one at a time. */
bool scene_packets_pay(const scene *s);
/* Shadow rays of active (bit k: ray k of r) at once: sets *blocked to
 * the rays an opaque object blocks, where scene_shadow returns true, and
 * *crosses to those of the others that meet a transmitting object, whose
 * light scene_shadow's crossings then filter (scene_shadow_unblocked8),
 * or may meet one: a sphere, quad or plane says so for eight rays in one
 * test, any other transmitting shape is left to the crossings' search,
 * which finds none for a ray that misses it. The rest reach their end
 * unfiltered. Coherent rays (towards one light from neighbouring points)
 * share the walk of the scene's tree. False when the rays cannot go
 * together (the scene's path is not eight-wide, or their directions
 * differ in sign): then ask scene_shadow ray by ray. */
bool scene_shadow8(const scene *s, const ray8 *r, int active, int *blocked, int *crosses);
/* Whether an opaque object (transmit == 0) blocks r within (tmin, tmax). */
bool scene_occluded_opaque(const scene *s, const ray *r);

/* A shadow ray's crossings of transmitting objects, nearest first. */
#define SCENE_SHADOW_MAX 64
typedef struct scene_crossings {
    int n;
    scene_hit hit[SCENE_SHADOW_MAX];
} scene_crossings;

/* A shadow ray in one walk through the scene: true when an opaque object
 * blocks r within (tmin, tmax), or when it crosses transmitting objects
 * more than SCENE_SHADOW_MAX times (full shadow); otherwise out holds every
 * place where r crosses a transmitting object's surface, by t (ties by
 * object). After each crossing of an object the next is sought
 * ray_epsilon beyond it (core/ray.h). */
bool scene_shadow(const scene *s, const ray *r, scene_crossings *out);
/* scene_shadow for the shadow rays of lanes (bit k: ray k of r), which no
 * opaque object blocks (as scene_shadow8 found them), at once: the same
 * crossings into out[k], and the rays for which it returns true. Where the
 * scene's transmitting objects are few only they are asked, a sphere for
 * the eight rays in one test on the eight-wide paths. */
int scene_shadow_unblocked8(const scene *s, const ray8 *r, int lanes, scene_crossings out[8]);
/* The commonest case of scene_shadow_unblocked8, where the transmitting
 * objects are few unturned spheres tested eight rays at once: for each ray
 * of lanes that crosses one of them only, that object in obj[k] and its
 * crossings (1 or 2) in count[k]; count[k] 0 for a ray that crosses none.
 * Returns the rays that cross more than one, or all of lanes where the
 * transmitting objects are not such spheres: scene_shadow_unblocked8's. */
int scene_shadow_one_crossed8(const scene *s, const ray8 *r, int lanes, int32_t obj[8],
                              int count[8]);

/* Surface at a hit, in world space, normals unit and outward; (u, v) may
 * be left 0 where the hit's material does not use them (material_uses_uv).
 * scene_surface.h has it inline for the shading of every hit. */
void scene_surface(const scene *s, const ray *r, const scene_hit *hit, surface *out);

/* World point p and normal n of a surface of object i in the object's
 * texture space: the shape's own coordinates measured from the object's
 * origin (texture.h, step 1). The normal is not normalised. */
void scene_object_point(const scene *s, int i, vec3 p, vec3 n, vec3 *po, vec3 *no);

/* The material at a hit. */
static inline const material *scene_hit_material(const scene *s, const scene_hit *hit)
{
    const object *o = &s->objects[hit->object];
    int m = o->material >= 0 ? o->material : shape_hit_material(&o->shape, &hit->h);
    return &s->materials[m];
}

#endif

#include "scene.h"

#include <math.h>
#include <stdlib.h>

#include "core/array.h"
#include "core/error.h"

scene *scene_new(void)
{
    scene *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->camera = (camera){v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 90.0f};
    s->background = v3s(0.0f);
    s->ambient = v3s(0.2f);
    s->settings = (glint_settings){.width = 500, .height = 500, .samples = 1, .max_depth = 5,
                                   .threads = 0, .transfer = GLINT_TRANSFER_NONE};
    return s;
}

void scene_free(scene *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->nimages; i++)
        image_free(&s->images[i]);
    free(s->objects);
    free(s->bounds);
    free(s->xforms);
    free(s->materials);
    free(s->textures);
    free(s->images);
    free(s->lights);
    free(s);
}

void glint_scene_free(glint_scene *s) { scene_free(s); }

void glint_scene_settings(const glint_scene *s, glint_settings *out) { *out = s->settings; }

#define PUSH(arr, n, cap, value)                                                            \
    do {                                                                                    \
        int i_ = array_push((void **)&(arr), &(n), &(cap), sizeof *(arr));                  \
        if (i_ >= 0)                                                                        \
            (arr)[i_] = (value);                                                            \
        return i_;                                                                          \
    } while (0)

int scene_add_material(scene *s, const material *m) { PUSH(s->materials, s->nmaterials, s->cap_materials, *m); }
int scene_add_texture(scene *s, const texture *t) { PUSH(s->textures, s->ntextures, s->cap_textures, *t); }
int scene_add_light(scene *s, const light *l) { PUSH(s->lights, s->nlights, s->cap_lights, *l); }
int scene_add_xform(scene *s, const xform *x) { PUSH(s->xforms, s->nxforms, s->cap_xforms, *x); }

int scene_add_image(scene *s, image *img)
{
    int i = array_push((void **)&s->images, &s->nimages, &s->cap_images, sizeof *s->images);
    if (i >= 0) {
        s->images[i] = *img;
        img->rgb = NULL;
    }
    return i;
}

int scene_add_object(scene *s, const shape *sh, int mat, int xf)
{
    object o = {*sh, mat, xf};
    s->built = false;
    PUSH(s->objects, s->nobjects, s->cap_objects, o);
}

static aabb xform_bounds(const xform *x, aabb b)
{
    if (aabb_is_empty(b))
        return b;
    aabb r = aabb_empty();
    for (int i = 0; i < 8; i++) {
        vec3 c = v3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
        r = aabb_grow(r, mat4_point(&x->fwd, c));
    }
    return r;
}

glint_rc scene_build(scene *s, glint_error *err)
{
    for (int i = 0; i < s->ntextures; i++)
        if (s->textures[i].kind == TEXTURE_IMAGE &&
            (s->textures[i].image < 0 || s->textures[i].image >= s->nimages))
            return err_set(err, GLINT_ERR_INPUT, "texture %d refers to a missing image", i);
    for (int i = 0; i < s->nmaterials; i++)
        if (s->materials[i].texture >= s->ntextures)
            return err_set(err, GLINT_ERR_INPUT, "material %d refers to a missing texture", i);
    free(s->bounds);
    s->bounds = malloc(sizeof *s->bounds * (size_t)(s->nobjects ? s->nobjects : 1));
    if (!s->bounds)
        return err_nomem(err);
    for (int i = 0; i < s->nobjects; i++) {
        const object *o = &s->objects[i];
        if (o->material < 0 || o->material >= s->nmaterials)
            return err_set(err, GLINT_ERR_INPUT, "object %d refers to a missing material", i);
        if (o->xform >= s->nxforms)
            return err_set(err, GLINT_ERR_INPUT, "object %d refers to a missing transform", i);
        aabb b = shape_bounds(&o->shape);
        s->bounds[i] = o->xform >= 0 ? xform_bounds(&s->xforms[o->xform], b) : b;
    }
    s->any_transmit = false;
    for (int i = 0; i < s->nmaterials; i++)
        s->any_transmit = s->any_transmit || s->materials[i].transmit > 0.0f;
    s->built = true;
    return GLINT_OK;
}

/* The ray in the object's own space; t values carry over unchanged because
 * the direction is transformed without renormalising. */
static inline ray object_ray(const scene *s, const object *o, const ray *r)
{
    if (o->xform < 0)
        return *r;
    const xform *x = &s->xforms[o->xform];
    return (ray){mat4_point(&x->inv, r->o), mat4_vector(&x->inv, r->d), r->tmin, r->tmax};
}

static inline vec3 inverse_dir(vec3 d)
{
    return v3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
}

/* Bounds of unbounded shapes (planes) are empty; those are always tested. */
static inline bool may_hit(const scene *s, int i, const ray *r, vec3 inv_d)
{
    aabb b = s->bounds[i];
    return aabb_is_empty(b) || aabb_hit(b, r->o, inv_d, r->tmin, r->tmax);
}

bool scene_intersect(const scene *s, const ray *r, scene_hit *hit)
{
    ray cur = *r;
    bool found = false;
    vec3 inv_d = inverse_dir(r->d);
    for (int i = 0; i < s->nobjects; i++) {
        const object *o = &s->objects[i];
        if (!may_hit(s, i, &cur, inv_d))
            continue;
        ray lr = object_ray(s, o, &cur);
        if (shape_intersect(&o->shape, &lr, &hit->h)) {
            cur.tmax = hit->h.t;
            hit->object = i;
            found = true;
        }
    }
    return found;
}

bool scene_occluded_opaque(const scene *s, const ray *r)
{
    vec3 inv_d = inverse_dir(r->d);
    for (int i = 0; i < s->nobjects; i++) {
        const object *o = &s->objects[i];
        if (s->materials[o->material].transmit > 0.0f || !may_hit(s, i, r, inv_d))
            continue;
        ray lr = object_ray(s, o, r);
        if (shape_occluded(&o->shape, &lr))
            return true;
    }
    return false;
}

void scene_surface(const scene *s, const ray *r, const scene_hit *hit, surface *out)
{
    const object *o = &s->objects[hit->object];
    if (o->xform < 0) {
        shape_surface(&o->shape, r, &hit->h, out);
        return;
    }
    const xform *x = &s->xforms[o->xform];
    ray lr = object_ray(s, o, r);
    shape_surface(&o->shape, &lr, &hit->h, out);
    out->p = ray_at(r, hit->h.t);
    out->n = v3_norm(xform_normal(x, out->n));
}

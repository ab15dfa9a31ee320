/* Time in the scene: setting it (the animated values of the camera,
 * lights, materials and transforms), the camera at a ray's time, moving
 * objects' transforms, and bounds that hold a moving object over the whole
 * shutter interval. */
#include "scene.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#include "core/error.h"

/* Intervals the shutter time is cut into to bound a moving object. */
#define MOTION_BOUND_STEPS 32

xform scene_object_xform_at(const scene *s, const object *o, float t)
{
    xform x;
    if (!anim_motion_xform(&s->anim, o->motion, t, &x))
        return s->xforms[o->xform]; /* not invertible at t: the one at the frame's time */
    return x;
}

/* A moving object's shape is inside the box of its transformed bounding
 * box's corners at every time. Between two sampled times a corner moves
 * along a path no longer than about the chord between them (the steps are
 * short against any turn), so it stays within that chord's length of one
 * end: the union of the sampled boxes grown by the longest chord holds the
 * object at every time of the interval. */
static aabb moving_bounds(const scene *s, const object *o, aabb b)
{
    if (aabb_is_unbounded(b))
        return b;
    aabb r = aabb_empty();
    vec3 prev[8];
    float grow = 0.0f;
    for (int k = 0; k <= MOTION_BOUND_STEPS; k++) {
        float t = s->time + s->shutter_seconds * (float)k / MOTION_BOUND_STEPS;
        xform x = scene_object_xform_at(s, o, t);
        for (int i = 0; i < 8; i++) {
            vec3 c = v3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y,
                        i & 4 ? b.hi.z : b.lo.z);
            vec3 p = mat4_point(&x.fwd, c);
            if (k > 0)
                grow = fmaxf(grow, v3_len(v3_sub(p, prev[i])));
            prev[i] = p;
            r = aabb_grow(r, p);
        }
    }
    r.lo = v3_sub(r.lo, v3s(grow));
    r.hi = v3_add(r.hi, v3s(grow));
    return r;
}

aabb scene_object_bounds(const scene *s, int i)
{
    return scene_object_bounds_of(s, &s->objects[i], shape_bounds(&s->objects[i].shape));
}

aabb scene_object_bounds_of(const scene *s, const object *o, aabb b)
{
    if (o->moving)
        return moving_bounds(s, o, b);
    return o->xform >= 0 ? shape_bounds_mapped(&o->shape, &s->xforms[o->xform].fwd) : b;
}

bool scene_motions_of(const scene *s, int **of)
{
    *of = NULL;
    if (s->anim.nmotions == 0)
        return true;
    *of = malloc(sizeof **of * (size_t)(s->nxforms ? s->nxforms : 1));
    if (!*of)
        return false;
    for (int i = 0; i < s->nxforms; i++)
        (*of)[i] = -1;
    for (int m = 0; m < s->anim.nmotions; m++)
        if (s->anim.motions[m].xform >= 0 && s->anim.motions[m].xform < s->nxforms)
            (*of)[s->anim.motions[m].xform] = m;
    return true;
}

camera scene_camera_at(const scene *s, float t)
{
    camera c = s->camera;
    anim_apply(&s->anim, ANIM_CAMERA, 0, (float *)&c, t);
    return c;
}

/* The shutter interval from the camera's shutter and the frame rate. */
static void shutter_interval(scene *s)
{
    s->shutter_seconds = s->camera.shutter > 0.0f ? s->camera.shutter / s->anim.fps : 0.0f;
    s->camera_moves = s->shutter_seconds > 0.0f && anim_drives(&s->anim, ANIM_CAMERA);
}

glint_rc scene_camera_changed(scene *s, glint_error *err)
{
    float before = s->shutter_seconds;
    shutter_interval(s);
    if (s->shutter_seconds == before || s->anim.nmotions == 0 || !s->built)
        return GLINT_OK;
    return scene_build(s, err); /* objects start or stop moving */
}

glint_rc scene_set_time(scene *s, float t, glint_error *err)
{
    const anim *a = &s->anim;
    s->time = t;
    s->camera = scene_camera_at(s, t);
    shutter_interval(s);
    for (int i = 0; i < a->nchannels; i++) {
        const anim_channel *c = &a->channels[i];
        if (c->target == ANIM_LIGHT && c->index < s->nlights)
            anim_apply_channel(a, c, (float *)&s->lights[c->index], t);
        else if (c->target == ANIM_MATERIAL && c->index < s->nmaterials)
            anim_apply_channel(a, c, (float *)&s->materials[c->index], t);
    }
    for (int i = 0; i < s->nlights; i++)
        light_refresh(&s->lights[i]);
    for (int m = 0; m < a->nmotions; m++) {
        int xf = a->motions[m].xform;
        if (xf < 0 || xf >= s->nxforms)
            continue;
        if (!anim_motion_xform(a, m, t, &s->xforms[xf]))
            return err_set(err, GLINT_ERR_INPUT,
                           "an animated transform is not invertible at time %g s", (double)t);
    }
    return scene_build(s, err);
}

/* transform: lists of steps (translate, rotate, scale, shear, matrix),
 * composed first applied first, into one affine xform per object. */
#include "loader.h"

#include <math.h>
#include <stdio.h>

#include "core/array.h"

/* ---- transforms ------------------------------------------------------- */

/* In step_kind order. */
static const char *const transform_keys[] = {"translate", "rotate_x", "rotate_y", "rotate_z",
                                             "rotate",    "scale",    "shear",    "matrix",
                                             NULL};

typedef enum step_kind {
    STEP_TRANSLATE,
    STEP_ROTATE_X,
    STEP_ROTATE_Y,
    STEP_ROTATE_Z,
    STEP_ROTATE,
    STEP_SCALE,
    STEP_SHEAR,
    STEP_MATRIX,
    STEP_COUNT
} step_kind;
_Static_assert(sizeof transform_keys / sizeof *transform_keys == STEP_COUNT + 1,
               "transform_keys names every step_kind, in order");
static const char *const rotate_keys[] = {"axis", "angle", NULL};
static const char *const shear_keys[] = {"xy", "xz", "yx", "yz", "zx", "zy", NULL};

/* A number (uniform) or [sx, sy, sz], no factor 0, as three floats. */
static glint_rc read_scale(loader *L, uint32_t v, const char *key, float *f)
{
    glint_rc rc;
    if (load_node(L, v)->kind == YNODE_NUMBER) {
        rc = load_nonzero(L, v, key, &f[0]);
        f[1] = f[2] = f[0];
    } else if (load_node(L, v)->kind == YNODE_SEQ) {
        rc = load_numbers(L, v, key, "a number or [sx, sy, sz]", 3, f);
        for (int i = 0; rc == GLINT_OK && i < 3; i++)
            rc = load_nonzero(L, ydoc_item(load_doc(L), load_node(L, v), (uint32_t)i), key, &f[i]);
    } else {
        rc = load_expected(L, v, "a number or [sx, sy, sz]", key);
    }
    return rc;
}

/* {axis: [x, y, z], angle: degrees}; either may be keyed. */
static glint_rc step_rotate(loader *L, uint32_t v, const char *key, anim_step *out)
{
    uint32_t axis, angle;
    glint_rc rc = load_want_map(L, v, key);
    if (rc == GLINT_OK)
        rc = load_check_keys(L, v, rotate_keys, "in rotate");
    if (rc == GLINT_OK)
        rc = load_need(L, v, "axis", "rotate", &axis);
    if (rc == GLINT_OK)
        rc = load_need(L, v, "angle", "rotate", &angle);
    if (rc == GLINT_OK)
        rc = load_anim_value(L, axis, "axis", 3, load_read_nonzero_vec3, out->v, 0, -INFINITY,
                             INFINITY);
    if (rc == GLINT_OK)
        rc = load_anim_value(L, angle, "angle", 1, load_read_number, &out->v[3], 3, -INFINITY,
                             INFINITY);
    out->kind = ANIM_STEP_ROTATE;
    return rc;
}

/* {xy: k, ...}: the first axis moves by k times the second; each may be
 * keyed. */
static glint_rc step_shear(loader *L, uint32_t v, const char *key, anim_step *out)
{
    glint_rc rc = load_want_map(L, v, key);
    if (rc == GLINT_OK)
        rc = load_check_keys(L, v, shear_keys, "in shear");
    out->kind = ANIM_STEP_SHEAR;
    for (int i = 0; rc == GLINT_OK && i < 6; i++) {
        uint32_t c = load_get(L, v, shear_keys[i]);
        if (c != YDOC_NONE)
            rc = load_anim_value(L, c, shear_keys[i], 1, load_read_number, &out->v[i], i,
                                 -INFINITY, INFINITY);
    }
    return rc;
}

/* 12 numbers (three rows) or 16 with the affine last row. */
static glint_rc step_matrix(loader *L, uint32_t v, const char *key, anim_step *out)
{
    const ynode *s = load_node(L, v);
    float f[16];
    glint_rc rc = GLINT_OK;
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, "12 or 16 numbers", key);
    if (s->count != 12 && s->count != 16)
        return load_fail(L, v, "expected 12 or 16 numbers for 'matrix', got %u", s->count);
    for (uint32_t i = 0; rc == GLINT_OK && i < s->count; i++)
        rc = load_number(L, ydoc_item(load_doc(L), s, i), key, &f[i]);
    if (rc != GLINT_OK)
        return rc;
    if (s->count == 16 && !(f[12] == 0.0f && f[13] == 0.0f && f[14] == 0.0f && f[15] == 1.0f))
        return load_fail(L, ydoc_item(load_doc(L), s, 12),
                         "the last row of a 16-number matrix must be 0, 0, 0, 1 (transforms "
                         "are affine)");
    mat4 mm = mat4_identity();
    for (int i = 0; i < 12; i++)
        mm.m[i / 4][i % 4] = f[i];
    out->kind = ANIM_STEP_FIXED;
    if (!xform_from_matrix(&mm, &out->fixed))
        return load_fail(L, v, "matrix is not invertible");
    return GLINT_OK;
}

/* The value of one step of kind (keyed values at their first key). */
static glint_rc step_value(loader *L, step_kind kind, uint32_t v, anim_step *out)
{
    const char *key = transform_keys[kind];
    *out = (anim_step){.kind = ANIM_STEP_TRANSLATE};
    switch (kind) {
    case STEP_TRANSLATE:
        return load_anim_value(L, v, key, 3, load_read_vec3, out->v, 0, -INFINITY, INFINITY);
    case STEP_ROTATE_X:
    case STEP_ROTATE_Y:
    case STEP_ROTATE_Z:
        out->kind = ANIM_STEP_ROTATE;
        out->v[0] = kind == STEP_ROTATE_X;
        out->v[1] = kind == STEP_ROTATE_Y;
        out->v[2] = kind == STEP_ROTATE_Z;
        return load_anim_value(L, v, key, 1, load_read_number, &out->v[3], 3, -INFINITY,
                               INFINITY);
    case STEP_ROTATE:
        return step_rotate(L, v, key, out);
    case STEP_SCALE:
        out->kind = ANIM_STEP_SCALE;
        return load_anim_value(L, v, key, 3, read_scale, out->v, 0, -INFINITY, INFINITY);
    case STEP_SHEAR:
        return step_shear(L, v, key, out);
    case STEP_MATRIX:
        return step_matrix(L, v, key, out);
    case STEP_COUNT:
        break;
    }
    return GLINT_OK;
}

/* A transform's steps as read, for a motion when some are keyed. */
typedef struct step_list {
    anim_step *steps;
    int n, cap;
    anim_channel *channels; /* index: the step */
    int nchannels, cap_channels;
} step_list;

/* The step as a transform; a shear that flattens space is refused. */
static glint_rc step_xform(loader *L, uint32_t v, const anim_step *st, xform *out)
{
    if (st->kind == ANIM_STEP_SHEAR) {
        static const int at[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
        mat4 sm = mat4_identity();
        for (int i = 0; i < 6; i++)
            sm.m[at[i][0]][at[i][1]] = st->v[i];
        if (!xform_from_matrix(&sm, out))
            return load_fail(L, v, "shear is not invertible (it flattens space)");
        return GLINT_OK;
    }
    *out = anim_step_xform(st);
    return GLINT_OK;
}

/* One step: a mapping with one key naming its kind. */
static glint_rc load_step(loader *L, uint32_t step, step_list *list, xform *out)
{
    const ynode *m = load_node(L, step);
    if (m->kind != YNODE_MAP || m->count != 1) {
        char got[SHOWN + 32];
        ydoc_describe(load_doc(L), m, got, sizeof got);
        if (m->kind == YNODE_MAP)
            snprintf(got, sizeof got, "a mapping with %u keys", m->count);
        return load_fail(L, step,
                         "a transform step is a mapping with one key, such as {translate: [1, 2, "
                         "3]}, got %s",
                         got);
    }
    uint32_t k = ydoc_key(load_doc(L), m, 0), v = ydoc_value(load_doc(L), m, 0);
    int kind;
    anim_step st;
    glint_rc rc = load_enum(L, k, "transform", "transform", transform_keys, &kind);
    if (rc == GLINT_OK)
        rc = step_value(L, (step_kind)kind, v, &st);
    if (rc == GLINT_OK)
        rc = step_xform(L, v, &st, out);
    if (rc == GLINT_OK && !xform_is_finite(out))
        rc = load_fail(L, v, "%s makes the transform degenerate (not invertible in floats)",
                       transform_keys[kind]);
    if (rc != GLINT_OK)
        return rc;
    int i = array_push((void **)&list->steps, &list->n, &list->cap, sizeof *list->steps);
    if (i < 0)
        return err_nomem(L->err);
    list->steps[i] = st;
    for (int c = 0; c < L->npending; c++) {
        int j = array_push((void **)&list->channels, &list->nchannels, &list->cap_channels,
                           sizeof *list->channels);
        if (j < 0)
            return err_nomem(L->err);
        list->channels[j] = L->pending[c];
        list->channels[j].target = ANIM_STEP;
        list->channels[j].index = i;
    }
    load_anim_drop(L);
    return GLINT_OK;
}

/* Composes the steps of list onto *acc (*any: whether acc holds any step
 * yet). A step may itself be a list of steps, so that a transform written
 * once under an anchor can be used inside others. */
static glint_rc load_steps(loader *L, uint32_t list, step_list *steps, xform *acc, bool *any)
{
    const ynode *s = load_node(L, list);
    for (uint32_t i = 0; i < s->count; i++) {
        uint32_t item = ydoc_item(load_doc(L), s, i);
        glint_rc rc;
        if (load_node(L, item)->kind == YNODE_SEQ) {
            rc = load_steps(L, item, steps, acc, any);
            if (rc != GLINT_OK)
                return rc;
            continue;
        }
        xform step;
        rc = load_step(L, item, steps, &step);
        if (rc != GLINT_OK)
            return rc;
        /* both are affine and finite (checked as each was made) */
        *acc = *any ? xform_then_affine(acc, &step) : step;
        *any = true;
        if (!xform_is_finite(acc))
            return load_fail(L, item,
                        "this step makes the transform degenerate (not invertible in floats)");
    }
    return GLINT_OK;
}

/* The steps of list, composed into *out (*any: whether there was a step),
 * and read into steps for a motion. */
static glint_rc read_steps(loader *L, uint32_t list, step_list *steps, xform *out, bool *any)
{
    *out = xform_identity();
    *any = false;
    if (load_node(L, list)->kind != YNODE_SEQ)
        return load_expected(L, list, "a list of steps", "transform");
    return load_steps(L, list, steps, out, any);
}

/* An empty step list in the loader's room: a scene's thousands of
 * transforms need not each allocate and free one. */
static step_list borrow_steps(const loader *L)
{
    return (step_list){L->step_room, 0, L->cap_step_room, L->channel_room, 0,
                       L->cap_channel_room};
}

/* Gives the room back, as it may have grown. */
static void return_steps(loader *L, const step_list *steps)
{
    L->step_room = steps->steps;
    L->cap_step_room = steps->cap;
    L->channel_room = steps->channels;
    L->cap_channel_room = steps->cap_channels;
}

/* A list of steps, first applied first, composed into *out; *any says
 * whether there was a step. Only an object's own transform may be keyed. */
glint_rc load_xform(loader *L, uint32_t list, xform *out, bool *any)
{
    step_list steps = borrow_steps(L);
    glint_rc rc = read_steps(L, list, &steps, out, any);
    if (rc == GLINT_OK && steps.nchannels > 0)
        rc = load_fail(L, list, "only an object's own transform may be keyed, not this one");
    return_steps(L, &steps);
    return rc;
}

/* A list of steps, first applied first; *index gets the scene's xform, or
 * -1 when there are no steps. With keyed steps the xform is driven by a
 * motion (scene/anim.h) and holds the transform at the first keys until
 * the scene is set to a time. */
glint_rc load_transform(loader *L, uint32_t list, int *index)
{
    *index = -1;
    xform acc;
    bool any;
    step_list steps = borrow_steps(L);
    glint_rc rc = read_steps(L, list, &steps, &acc, &any);
    if (rc == GLINT_OK && any) {
        *index = scene_add_xform(L->s, &acc);
        if (*index < 0)
            rc = err_nomem(L->err);
    }
    if (rc == GLINT_OK && steps.nchannels > 0 &&
        anim_add_motion(&L->s->anim, *index, steps.steps, steps.n, steps.channels,
                        steps.nchannels) < 0)
        rc = err_nomem(L->err);
    return_steps(L, &steps);
    return rc;
}

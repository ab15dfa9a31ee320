/* Keyed values: anywhere the format allows animation, a number or vector
 * may be written as {keys: [[t0, v0], [t1, v1], ...], interpolation:
 * linear | smooth | step}, times in seconds, increasing. The values are
 * read and checked by the same reader as a plain value; the track goes to
 * the scene's anim, and the channel that will write it waits in the
 * loader's pending list until the thing it animates has its index
 * (load_anim_bind). */
#include "loader.h"

#include <stdlib.h>

#include "core/array.h"

static const char *const keyed_keys[] = {"keys", "interpolation", NULL};
static const char *const interpolations[] = {"linear", "smooth", "step", NULL};

bool load_is_keyed(const loader *L, uint32_t v)
{
    return load_node(L, v)->kind == YNODE_MAP && load_get(L, v, "keys") != YDOC_NONE;
}

/* Reads one [t, v] pair: *t and dim floats into out. */
static glint_rc read_key(loader *L, uint32_t item, const char *key, load_value_fn read,
                         float *t, float *out)
{
    const ynode *p = load_node(L, item);
    if (p->kind != YNODE_SEQ || p->count != 2)
        return load_expected(L, item, "a key [time, value]", key);
    glint_rc rc = load_number(L, ydoc_item(load_doc(L), p, 0), "a key's time", t);
    if (rc == GLINT_OK)
        rc = read(L, ydoc_item(load_doc(L), p, 1), key, out);
    return rc;
}

/* The keys of a keyed value, added to the scene as a track. */
static glint_rc read_track(loader *L, uint32_t map, const char *key, int dim,
                           load_value_fn read, int *track, float *first)
{
    uint32_t keys = load_get(L, map, "keys"), v;
    int interp = 0;
    glint_rc rc = load_check_keys(L, map, keyed_keys, "in keyed value");
    if (rc == GLINT_OK && (v = load_get(L, map, "interpolation")) != YDOC_NONE)
        rc = load_enum(L, v, "interpolation", "interpolation", interpolations, &interp);
    if (rc != GLINT_OK)
        return rc;
    const ynode *s = load_node(L, keys);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, keys, "a list of keys [[time, value], ...]", "keys");
    if (s->count == 0)
        return load_fail(L, keys, "keys needs at least one key [time, value]");
    float *times = malloc(sizeof *times * s->count);
    float *values = malloc(sizeof *values * s->count * (size_t)dim);
    if (!times || !values)
        rc = err_nomem(L->err);
    for (uint32_t i = 0; rc == GLINT_OK && i < s->count; i++) {
        uint32_t item = ydoc_item(load_doc(L), s, i);
        rc = read_key(L, item, key, read, &times[i], &values[i * (uint32_t)dim]);
        if (rc == GLINT_OK && i > 0 && !(times[i] > times[i - 1]))
            rc = load_fail(L, item, "key times must increase (%g s comes after %g s)",
                           (double)times[i], (double)times[i - 1]);
    }
    static const anim_interp kinds[] = {ANIM_INTERP_LINEAR, ANIM_INTERP_SMOOTH,
                                        ANIM_INTERP_STEP};
    if (rc == GLINT_OK) {
        *track = anim_add_track(&L->s->anim, kinds[interp], (int)s->count, dim, times, values);
        if (*track < 0)
            rc = err_nomem(L->err);
        for (int c = 0; rc == GLINT_OK && c < dim; c++)
            first[c] = values[c];
    }
    free(times);
    free(values);
    return rc;
}

glint_rc load_anim_value(loader *L, uint32_t v, const char *key, int dim, load_value_fn read,
                         float *out, int offset, float lo, float hi)
{
    if (!load_is_keyed(L, v))
        return read(L, v, key, out);
    int track = -1;
    glint_rc rc = read_track(L, v, key, dim, read, &track, out);
    if (rc != GLINT_OK)
        return rc;
    int i = array_push((void **)&L->pending, &L->npending, &L->cap_pending, sizeof *L->pending);
    if (i < 0)
        return err_nomem(L->err);
    L->pending[i] = (anim_channel){ANIM_CAMERA, 0, offset, track, lo, hi};
    return GLINT_OK;
}

glint_rc load_anim_bind(loader *L, anim_target target, int index)
{
    for (int i = 0; i < L->npending; i++) {
        anim_channel c = L->pending[i];
        c.target = target;
        c.index = index;
        if (anim_add_channel(&L->s->anim, &c) < 0)
            return err_nomem(L->err);
    }
    L->npending = 0;
    return GLINT_OK;
}

void load_anim_drop(loader *L) { L->npending = 0; }

/* ---- readers of one value, for load_anim_value ---------------------------- */

glint_rc load_read_number(loader *L, uint32_t v, const char *key, float *out)
{
    return load_number(L, v, key, out);
}

glint_rc load_read_nonneg(loader *L, uint32_t v, const char *key, float *out)
{
    return load_nonneg(L, v, key, out);
}

glint_rc load_read_positive(loader *L, uint32_t v, const char *key, float *out)
{
    return load_positive(L, v, key, out);
}

glint_rc load_read_vec3(loader *L, uint32_t v, const char *key, float *out)
{
    vec3 p;
    glint_rc rc = load_vec3(L, v, key, &p);
    if (rc == GLINT_OK) {
        out[0] = p.x;
        out[1] = p.y;
        out[2] = p.z;
    }
    return rc;
}

glint_rc load_read_nonzero_vec3(loader *L, uint32_t v, const char *key, float *out)
{
    vec3 p;
    glint_rc rc = load_nonzero_vec3(L, v, key, &p);
    if (rc == GLINT_OK) {
        out[0] = p.x;
        out[1] = p.y;
        out[2] = p.z;
    }
    return rc;
}

glint_rc load_read_color(loader *L, uint32_t v, const char *key, float *out)
{
    vec3 c;
    glint_rc rc = load_color(L, v, key, &c);
    if (rc == GLINT_OK) {
        out[0] = c.x;
        out[1] = c.y;
        out[2] = c.z;
    }
    return rc;
}

/* The materials: section, material mappings written inline where a name is
 * expected, and textures: (through textures.c). */
#include "loader.h"

#include <math.h>

#include <stdlib.h>
#include <string.h>

#include "core/array.h"

/* ---- materials -------------------------------------------------------- */

static const char *const material_keys[] = {"color",    "texture",    "ambient",  "diffuse",
                                            "specular", "shininess",  "reflect",  "transmit",
                                            "ior",      "tint",       "fresnel",  "absorption",
                                            "emission", "bump",       NULL};
static const char *const bump_keys[] = {"pattern", "strength", NULL};

/* A texture given by name (*name: resolved later) or inline (*index). */
static glint_rc read_texture_ref(loader *L, uint32_t v, const char *key, int *index,
                                 uint32_t *name)
{
    ynode_kind k = (ynode_kind)load_node(L, v)->kind;
    if (k == YNODE_MAP)
        return load_texture(L, v, index);
    if (k == YNODE_STRING || k == YNODE_NUMBER) {
        *name = v;
        return GLINT_OK;
    }
    return load_expected(L, v, "a texture name or mapping", key);
}

/* bump: {pattern: texture name or mapping, strength: number}. */
static glint_rc read_bump(loader *L, uint32_t v, material *m, uint32_t *name)
{
    uint32_t p, sv;
    glint_rc rc = load_want_map(L, v, "bump");
    if (rc == GLINT_OK)
        rc = load_check_keys(L, v, bump_keys, "in bump");
    if (rc == GLINT_OK)
        rc = load_need(L, v, "pattern", "bump", &p);
    m->bump_strength = 1.0f;
    if (rc == GLINT_OK && (sv = load_get(L, v, "strength")) != YDOC_NONE)
        rc = load_number(L, sv, "strength", &m->bump_strength);
    if (rc == GLINT_OK)
        rc = read_texture_ref(L, p, "pattern", &m->bump, name);
    if (rc == GLINT_OK && m->bump >= 0 && L->s->textures[m->bump].space == SPACE_UV)
        rc = load_fail(L, p, "a bump pattern must be in space object or world (its gradient is "
                             "taken in space), not on (u, v)");
    return rc;
}

/* The scalar keys, in material_keys order from ambient to ior. */
static glint_rc read_numbers(loader *L, uint32_t map, material *m)
{
    static const char *const keys[] = {"ambient", "diffuse", "specular", "shininess",
                                       "reflect", "transmit", "ior"};
    float *const at[] = {&m->ambient, &m->diffuse, &m->specular, &m->shininess,
                         &m->reflect, &m->transmit, &m->ior};
    glint_rc rc = GLINT_OK;
    for (int i = 0; rc == GLINT_OK && i < 7; i++) {
        uint32_t v = load_get(L, map, keys[i]);
        if (v == YDOC_NONE)
            continue;
        if (i < 4)
            rc = load_nonneg(L, v, keys[i], at[i]);
        else if (i < 6)
            rc = load_unit(L, v, keys[i], at[i]);
        else
            rc = load_positive(L, v, keys[i], at[i]);
    }
    return rc;
}

/* The colour keys. */
static glint_rc read_colors(loader *L, uint32_t map, material *m)
{
    static const char *const keys[] = {"color", "tint", "absorption", "emission"};
    vec3 *const at[] = {&m->color, &m->tint, &m->absorption, &m->emission};
    glint_rc rc = GLINT_OK;
    for (int i = 0; rc == GLINT_OK && i < 4; i++) {
        uint32_t v = load_get(L, map, keys[i]);
        if (v != YDOC_NONE) /* each may be keyed */
            rc = load_anim_value(L, v, keys[i], 3, load_read_color, &at[i]->x,
                                 (int)((float *)at[i] - (float *)m), 0.0f, INFINITY);
    }
    return rc;
}

/* A material mapping, added to the scene; its index goes to *index. */
glint_rc load_material(loader *L, uint32_t map, int *index)
{
    material m = material_default();
    uint32_t v, tex = YDOC_NONE, bump = YDOC_NONE;
    glint_rc rc = load_check_keys(L, map, material_keys, "in material");
    if (rc == GLINT_OK)
        rc = read_colors(L, map, &m);
    if (rc == GLINT_OK)
        rc = read_numbers(L, map, &m);
    if (rc == GLINT_OK && (v = load_get(L, map, "fresnel")) != YDOC_NONE)
        rc = load_bool(L, v, "fresnel", &m.fresnel);
    if (rc == GLINT_OK && (v = load_get(L, map, "texture")) != YDOC_NONE)
        rc = read_texture_ref(L, v, "texture", &m.texture, &tex);
    if (rc == GLINT_OK && (v = load_get(L, map, "bump")) != YDOC_NONE)
        rc = read_bump(L, v, &m, &bump);
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_material(L->s, &m);
    if (*index < 0)
        return err_nomem(L->err);
    rc = load_anim_bind(L, ANIM_MATERIAL, *index);
    if (rc == GLINT_OK && tex != YDOC_NONE)
        rc = load_add_ref(L, &L->texture_refs, &L->ntexture_refs, &L->cap_texture_refs, *index, tex);
    if (rc == GLINT_OK && bump != YDOC_NONE)
        rc = load_add_ref(L, &L->bump_refs, &L->nbump_refs, &L->cap_bump_refs, *index, bump);
    return rc;
}

/* textures: or materials: at the top level, a mapping from names to
 * definitions. Names are shared by every file of the scene. */
glint_rc load_named(loader *L, uint32_t map, bool textures)
{
    const char *what = textures ? "texture" : "material";
    names *table = textures ? &L->texture_names : &L->material_names;
    glint_rc rc = load_want_map(L, map, textures ? "textures" : "materials");
    const ynode *m = load_node(L, map);
    for (uint32_t i = 0; rc == GLINT_OK && i < m->count; i++) {
        uint32_t k = ydoc_key(load_doc(L), m, i), v = ydoc_value(load_doc(L), m, i);
        const ynode *kn = load_node(L, k);
        const char *name = ydoc_text(load_doc(L), kn);
        rc = load_name(L, k, what);
        if (rc != GLINT_OK)
            break;
        int seen = names_find(table, name, kn->count);
        if (seen >= 0) {
            const def *d = &L->defs[seen];
            const ynode *at = ydoc_node(L->files[d->file].doc, d->node);
            char buf[SHOWN];
            rc = load_fail(L, k, "duplicate %s name '%s' (first defined at %s:%u:%u)", what,
                      load_shown(L, k, buf), L->files[d->file].name, at->line, at->col);
            break;
        }
        if (load_node(L, v)->kind != YNODE_MAP) {
            char got[SHOWN + 32];
            ydoc_describe(load_doc(L), load_node(L, v), got, sizeof got);
            char buf[SHOWN];
            rc = load_fail(L, v, "expected a mapping for %s '%s', got %s", what, load_shown(L, k, buf),
                      got);
            break;
        }
        int index;
        rc = textures ? load_texture(L, v, &index) : load_material(L, v, &index);
        if (rc != GLINT_OK)
            break;
        int d = array_push((void **)&L->defs, &L->ndefs, &L->cap_defs, sizeof *L->defs);
        if (d < 0 || !names_put(table, name, kn->count, d))
            return err_nomem(L->err);
        L->defs[d] = (def){L->cur, k, index};
    }
    return rc;
}


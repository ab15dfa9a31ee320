/* The textures: and materials: sections, and texture or material mappings
 * written inline where a name is expected. */
#include "loader.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"

/* ---- textures and materials ------------------------------------------- */

static const char *const texture_types[] = {"image", "checker", NULL};
static const char *const image_texture_keys[] = {"type", "file", "wrap", "scale", "offset", NULL};
static const char *const checker_texture_keys[] = {"type", "even", "odd", "scale", "offset", NULL};
static const char *const wrap_modes[] = {"repeat", "clamp", NULL};

/* The image at a path written in the file, read once per resolved path. */
static glint_rc load_image_file(loader *L, uint32_t v, int *index)
{
    const char *written = ydoc_text(load_doc(L), load_node(L, v));
    char *resolved = path_join(L->files[L->cur].dir, written);
    char *shown_name = path_printable(written);
    char *data = NULL;
    glint_rc rc = GLINT_OK;
    if (!resolved || !shown_name) {
        rc = err_nomem(L->err);
        goto out;
    }
    *index = names_find(&L->images, resolved, strlen(resolved));
    if (*index >= 0)
        goto out;
    size_t size;
    rc = load_named_file(L, v, written, resolved, "texture", &data, &size);
    if (rc != GLINT_OK)
        goto out;
    image img;
    glint_error ierr = {0};
    rc = image_load_memory(data, size, shown_name, &img, &ierr);
    if (rc == GLINT_ERR_NOMEM) {
        rc = err_nomem(L->err);
        goto out;
    }
    if (rc != GLINT_OK) {
        rc = load_fail(L, v, "%s", ierr.msg);
        goto out;
    }
    *index = scene_add_image(L->s, &img);
    if (*index < 0 || !names_put(&L->images, resolved, strlen(resolved), *index)) {
        image_free(&img);
        rc = err_nomem(L->err);
    }
out:
    free(data);
    free(resolved);
    free(shown_name);
    return rc;
}

static glint_rc read_wrap(loader *L, uint32_t v, texture *t)
{
    const ynode *n = load_node(L, v);
    int u, w;
    glint_rc rc;
    if (n->kind == YNODE_SEQ) {
        if (n->count != 2)
            return load_fail(L, v, "expected 2 wrap modes for 'wrap' ([u, v]), got %u", n->count);
        rc = load_enum(L, ydoc_item(load_doc(L), n, 0), "wrap", "wrap mode", wrap_modes, &u);
        if (rc == GLINT_OK)
            rc = load_enum(L, ydoc_item(load_doc(L), n, 1), "wrap", "wrap mode", wrap_modes, &w);
    } else if (n->kind == YNODE_STRING) {
        rc = load_enum(L, v, "wrap", "wrap mode", wrap_modes, &u);
        w = u;
    } else {
        return load_expected(L, v, "repeat, clamp or [u, v]", "wrap");
    }
    if (rc == GLINT_OK) {
        t->wrap_u = u == 0 ? WRAP_REPEAT : WRAP_CLAMP;
        t->wrap_v = w == 0 ? WRAP_REPEAT : WRAP_CLAMP;
    }
    return rc;
}

/* scale (a number or [su, sv], not 0) and offset ([ou, ov]). */
static glint_rc read_placement(loader *L, uint32_t map, texture *t)
{
    uint32_t v = load_get(L, map, "scale");
    glint_rc rc = GLINT_OK;
    if (v != YDOC_NONE) {
        const ynode *n = load_node(L, v);
        if (n->kind == YNODE_NUMBER) {
            rc = load_nonzero(L, v, "scale", &t->scale_u);
            t->scale_v = t->scale_u;
        } else if (n->kind == YNODE_SEQ) {
            float f[2];
            rc = load_numbers(L, v, "scale", "[su, sv]", 2, f);
            for (int i = 0; rc == GLINT_OK && i < 2; i++)
                rc = load_nonzero(L, ydoc_item(load_doc(L), n, (uint32_t)i), "scale", &f[i]);
            if (rc == GLINT_OK) {
                t->scale_u = f[0];
                t->scale_v = f[1];
            }
        } else {
            return load_expected(L, v, "a number or [su, sv]", "scale");
        }
    }
    v = load_get(L, map, "offset");
    if (rc == GLINT_OK && v != YDOC_NONE) {
        float f[2];
        rc = load_numbers(L, v, "offset", "[ou, ov]", 2, f);
        if (rc == GLINT_OK) {
            t->offset_u = f[0];
            t->offset_v = f[1];
        }
    }
    return rc;
}

/* A texture mapping, added to the scene; its index goes to *index. */
glint_rc load_texture(loader *L, uint32_t map, int *index)
{
    uint32_t v;
    int type;
    glint_rc rc = load_need(L, map, "type", "texture", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "texture type", texture_types, &type);
    if (rc != GLINT_OK)
        return rc;
    texture t;
    if (type == 0) {
        rc = load_check_keys(L, map, image_texture_keys, "in image texture");
        if (rc == GLINT_OK)
            rc = load_need(L, map, "file", "image texture", &v);
        if (rc == GLINT_OK)
            rc = load_path_key(L, v, "file");
        t = texture_image(-1);
        uint32_t w = load_get(L, map, "wrap");
        if (rc == GLINT_OK && w != YDOC_NONE)
            rc = read_wrap(L, w, &t);
        if (rc == GLINT_OK)
            rc = read_placement(L, map, &t);
        /* The file last: the other fields are cheaper to check. */
        if (rc == GLINT_OK)
            rc = load_image_file(L, v, &t.image);
    } else {
        t = texture_checker(v3s(1.0f), v3s(0.0f), 1.0f, 1.0f);
        rc = load_check_keys(L, map, checker_texture_keys, "in checker texture");
        if (rc == GLINT_OK && (v = load_get(L, map, "even")) != YDOC_NONE)
            rc = load_color(L, v, "even", &t.even);
        if (rc == GLINT_OK && (v = load_get(L, map, "odd")) != YDOC_NONE)
            rc = load_color(L, v, "odd", &t.odd);
        if (rc == GLINT_OK)
            rc = read_placement(L, map, &t);
    }
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_texture(L->s, &t);
    return *index < 0 ? err_nomem(L->err) : GLINT_OK;
}

static const char *const material_keys[] = {"color",   "texture",  "ambient",
                                            "diffuse", "specular", "shininess",
                                            "reflect", "transmit", "ior",
                                            "tint",    NULL};

/* A material mapping, added to the scene; its index goes to *index. */
glint_rc load_material(loader *L, uint32_t map, int *index)
{
    material m = material_default();
    uint32_t v, tex = YDOC_NONE;
    glint_rc rc = load_check_keys(L, map, material_keys, "in material");
    if (rc == GLINT_OK && (v = load_get(L, map, "color")) != YDOC_NONE)
        rc = load_anim_value(L, v, "color", 3, load_read_color, &m.color.x,
                             (int)(offsetof(material, color) / sizeof(float)), 0.0f, INFINITY);
    if (rc == GLINT_OK && (v = load_get(L, map, "ambient")) != YDOC_NONE)
        rc = load_nonneg(L, v, "ambient", &m.ambient);
    if (rc == GLINT_OK && (v = load_get(L, map, "diffuse")) != YDOC_NONE)
        rc = load_nonneg(L, v, "diffuse", &m.diffuse);
    if (rc == GLINT_OK && (v = load_get(L, map, "specular")) != YDOC_NONE)
        rc = load_nonneg(L, v, "specular", &m.specular);
    if (rc == GLINT_OK && (v = load_get(L, map, "shininess")) != YDOC_NONE)
        rc = load_nonneg(L, v, "shininess", &m.shininess);
    if (rc == GLINT_OK && (v = load_get(L, map, "reflect")) != YDOC_NONE)
        rc = load_unit(L, v, "reflect", &m.reflect);
    if (rc == GLINT_OK && (v = load_get(L, map, "transmit")) != YDOC_NONE)
        rc = load_unit(L, v, "transmit", &m.transmit);
    if (rc == GLINT_OK && (v = load_get(L, map, "ior")) != YDOC_NONE)
        rc = load_positive(L, v, "ior", &m.ior);
    if (rc == GLINT_OK && (v = load_get(L, map, "tint")) != YDOC_NONE)
        rc = load_anim_value(L, v, "tint", 3, load_read_color, &m.tint.x,
                             (int)(offsetof(material, tint) / sizeof(float)), 0.0f, INFINITY);
    if (rc == GLINT_OK && (v = load_get(L, map, "texture")) != YDOC_NONE) {
        ynode_kind k = (ynode_kind)load_node(L, v)->kind;
        if (k == YNODE_MAP)
            rc = load_texture(L, v, &m.texture);
        else if (k == YNODE_STRING || k == YNODE_NUMBER)
            tex = v;
        else
            rc = load_expected(L, v, "a texture name or mapping", "texture");
    }
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_material(L->s, &m);
    if (*index < 0)
        return err_nomem(L->err);
    rc = load_anim_bind(L, ANIM_MATERIAL, *index);
    if (rc != GLINT_OK)
        return rc;
    if (tex != YDOC_NONE)
        return load_add_ref(L, &L->texture_refs, &L->ntexture_refs, &L->cap_texture_refs, *index, tex);
    return GLINT_OK;
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


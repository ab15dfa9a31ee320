/* The objects: section: one mapping per object, a shape with its keys, a
 * material (by name, inline, a mesh's own, or the default) and a
 * transform. Mesh files are imported once however many objects use them. */
#include "loader.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load/mesh_import.h"

/* ---- objects ---------------------------------------------------------- */

/* In shape_kind order. */
static const char *const object_types[] = {"sphere",   "plane",    "quad", "box",
                                           "cylinder", "triangle", "mesh", NULL};
static const char *const *const object_keys[] = {
    (const char *const[]){"type", "center", "radius", "material", "transform", NULL},
    (const char *const[]){"type", "point", "normal", "material", "transform", NULL},
    (const char *const[]){"type", "origin", "edge_u", "edge_v", "material", "transform", NULL},
    (const char *const[]){"type", "min", "max", "material", "transform", NULL},
    (const char *const[]){"type", "base", "radius", "height", "capped", "material", "transform",
                          NULL},
    (const char *const[]){"type", "p0", "p1", "p2", "uv", "material", "transform", NULL},
    (const char *const[]){"type", "file", "material", "transform", NULL},
};

static glint_rc load_box(loader *L, uint32_t map, shape *out)
{
    vec3 lo, hi;
    glint_rc rc = load_need_vec3(L, map, "min", "box", &lo);
    if (rc == GLINT_OK)
        rc = load_need_vec3(L, map, "max", "box", &hi);
    if (rc != GLINT_OK)
        return rc;
    uint32_t mn = load_get(L, map, "min"), mx = load_get(L, map, "max");
    for (int a = 0; a < 3; a++)
        if (!(v3_at(lo, a) < v3_at(hi, a))) {
            char b1[SHOWN], b2[SHOWN];
            return load_fail(L, mx, "max must be greater than min on every axis (%c: min %s, max %s)",
                        "xyz"[a], load_shown(L, ydoc_item(load_doc(L), load_node(L, mn), (uint32_t)a), b1),
                        load_shown(L, ydoc_item(load_doc(L), load_node(L, mx), (uint32_t)a), b2));
        }
    *out = shape_box(lo, hi);
    return GLINT_OK;
}

static glint_rc load_triangle(loader *L, uint32_t map, shape *out)
{
    vec3 p[3];
    static const char *const pk[3] = {"p0", "p1", "p2"};
    glint_rc rc = GLINT_OK;
    for (int i = 0; rc == GLINT_OK && i < 3; i++)
        rc = load_need_vec3(L, map, pk[i], "triangle", &p[i]);
    if (rc != GLINT_OK)
        return rc;
    if (v3_is_zero(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]))))
        return load_fail(L, map, "triangle is degenerate: p0, p1 and p2 lie on one line");
    *out = shape_triangle(p[0], p[1], p[2]);
    uint32_t v = load_get(L, map, "uv");
    if (v == YDOC_NONE)
        return GLINT_OK;
    const ynode *s = load_node(L, v);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, "[[u, v], [u, v], [u, v]]", "uv");
    if (s->count != 3)
        return load_fail(L, v, "expected 3 [u, v] pairs for 'uv', got %u", s->count);
    for (uint32_t i = 0; rc == GLINT_OK && i < 3; i++)
        rc = load_numbers(L, ydoc_item(load_doc(L), s, i), "uv", "[u, v]", 2, out->triangle.uv[i]);
    return rc;
}

/* The mesh at a path written in the file, imported once per resolved path
 * however many objects place it. Files on disk go to assimp by path (so an
 * OBJ finds its .mtl); through another reader, from memory. The file's own
 * materials join the scene's, and its triangles index them there. */
static glint_rc load_mesh_file(loader *L, uint32_t v, shape *out)
{
    const char *written = ydoc_text(load_doc(L), load_node(L, v));
    char *resolved = path_join(L->files[L->cur].dir, written);
    char *data = NULL;
    mesh_file mf = {0};
    glint_rc rc = GLINT_OK;
    if (!resolved) {
        rc = err_nomem(L->err);
        goto out;
    }
    int index = names_find(&L->meshes, resolved, strlen(resolved));
    if (index >= 0) {
        *out = shape_mesh(scene_mesh(L->s, index));
        goto out;
    }
    glint_error merr = {0};
    if (L->reader == scene_read_file) {
        FILE *probe = fopen(resolved, "rb");
        if (!probe) {
            rc = load_cannot_read(L, v, "mesh", written, resolved, strerror(errno));
            goto out;
        }
        fclose(probe);
        rc = scene_add_source(L->s, resolved) < 0 ? err_nomem(&merr) : mesh_import(resolved, &mf, &merr);
    } else {
        size_t size;
        rc = load_named_file(L, v, written, resolved, "mesh", &data, &size);
        if (rc != GLINT_OK)
            goto out;
        rc = mesh_import_memory(data, size, resolved, &mf, &merr);
    }
    if (rc == GLINT_ERR_NOMEM) {
        rc = err_nomem(L->err);
        goto out;
    }
    if (rc != GLINT_OK) {
        rc = load_fail(L, v, "%s", merr.msg);
        goto out;
    }
    rc = mesh_file_add(L->s, &mf, &index, L->err);
    if (rc != GLINT_OK)
        goto out;
    if (!names_put(&L->meshes, resolved, strlen(resolved), index)) {
        rc = err_nomem(L->err);
        goto out;
    }
    *out = shape_mesh(scene_mesh(L->s, index));
out:
    mesh_file_free(&mf);
    free(data);
    free(resolved);
    return rc;
}

static glint_rc load_shape(loader *L, uint32_t map, shape_kind kind, shape *out)
{
    const char *what = object_types[kind];
    vec3 a, b, c;
    float r, h;
    uint32_t v;
    glint_rc rc = GLINT_OK;
    switch (kind) {
    case SHAPE_SPHERE:
        rc = load_need_vec3(L, map, "center", what, &a);
        if (rc == GLINT_OK)
            rc = load_need_positive(L, map, "radius", what, &r);
        if (rc == GLINT_OK)
            *out = shape_sphere(a, r);
        return rc;
    case SHAPE_PLANE:
        rc = load_need_vec3(L, map, "point", what, &a);
        if (rc == GLINT_OK)
            rc = load_need(L, map, "normal", what, &v);
        if (rc == GLINT_OK)
            rc = load_nonzero_vec3(L, v, "normal", &b);
        if (rc == GLINT_OK)
            *out = shape_plane(a, b);
        return rc;
    case SHAPE_QUAD:
        rc = load_need_vec3(L, map, "origin", what, &a);
        if (rc == GLINT_OK)
            rc = load_need_vec3(L, map, "edge_u", what, &b);
        if (rc == GLINT_OK)
            rc = load_need_vec3(L, map, "edge_v", what, &c);
        if (rc == GLINT_OK && v3_is_zero(v3_cross(b, c)))
            rc = load_fail(L, load_get(L, map, "edge_v"),
                      "edge_v must not be parallel to edge_u (nor either be zero)");
        if (rc == GLINT_OK)
            *out = shape_quad(a, b, c);
        return rc;
    case SHAPE_BOX:
        return load_box(L, map, out);
    case SHAPE_CYLINDER: {
        bool capped = true;
        rc = load_need_vec3(L, map, "base", what, &a);
        if (rc == GLINT_OK)
            rc = load_need_positive(L, map, "radius", what, &r);
        if (rc == GLINT_OK)
            rc = load_need_positive(L, map, "height", what, &h);
        if (rc == GLINT_OK && (v = load_get(L, map, "capped")) != YDOC_NONE)
            rc = load_bool(L, v, "capped", &capped);
        if (rc == GLINT_OK)
            *out = shape_cylinder(a, r, h, capped);
        return rc;
    }
    case SHAPE_TRIANGLE:
        return load_triangle(L, map, out);
    case SHAPE_MESH:
        rc = load_need(L, map, "file", "mesh", &v);
        if (rc == GLINT_OK)
            rc = load_path_key(L, v, "file");
        if (rc == GLINT_OK)
            rc = load_mesh_file(L, v, out);
        return rc;
    }
    return rc;
}

/* The object's material: a name (resolved later), a mapping, or nothing:
 * a mesh's own materials (index -1) or the default material, added once. */
static glint_rc object_material(loader *L, uint32_t map, bool is_mesh, int *index, uint32_t *name)
{
    uint32_t v = load_get(L, map, "material");
    *name = YDOC_NONE;
    *index = -1;
    if (v == YDOC_NONE && is_mesh)
        return GLINT_OK;
    if (v == YDOC_NONE) {
        if (L->default_material < 0) {
            material m = material_default();
            L->default_material = scene_add_material(L->s, &m);
            if (L->default_material < 0)
                return err_nomem(L->err);
        }
        *index = L->default_material;
        return GLINT_OK;
    }
    ynode_kind k = (ynode_kind)load_node(L, v)->kind;
    if (k == YNODE_MAP)
        return load_material(L, v, index);
    if (k == YNODE_STRING || k == YNODE_NUMBER) {
        *name = v;
        return load_name(L, v, "material");
    }
    return load_expected(L, v, "a material name or mapping", "material");
}

glint_rc load_object(loader *L, uint32_t map)
{
    if (load_node(L, map)->kind != YNODE_MAP)
        return load_expected(L, map, "a mapping", "objects");
    if (scene_object_count(L->s) >= LOAD_MAX_OBJECTS)
        return load_fail(L, map, "more than %d objects", LOAD_MAX_OBJECTS);
    uint32_t v;
    int type;
    glint_rc rc = load_need(L, map, "type", "object", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "object type", object_types, &type);
    if (rc != GLINT_OK)
        return rc;
    char where[32];
    snprintf(where, sizeof where, "in %s", object_types[type]);
    rc = load_check_keys(L, map, object_keys[type], where);
    shape sh;
    if (rc == GLINT_OK)
        rc = load_shape(L, map, (shape_kind)type, &sh);
    int mat, xf = -1;
    uint32_t name;
    if (rc == GLINT_OK)
        rc = object_material(L, map, type == SHAPE_MESH, &mat, &name);
    if (rc == GLINT_OK && (v = load_get(L, map, "transform")) != YDOC_NONE)
        rc = load_transform(L, v, &xf);
    if (rc != GLINT_OK)
        return rc;
    int o = scene_add_object(L->s, &sh, mat, xf);
    if (o < 0)
        return err_nomem(L->err);
    if (name != YDOC_NONE)
        return load_add_ref(L, &L->material_refs, &L->nmaterial_refs, &L->cap_material_refs, o, name);
    return GLINT_OK;
}


/* The objects: section: one mapping per object, a shape with its keys, a
 * material (by name, inline, a mesh's own, or the default) and a
 * transform. Mesh files are imported once however many objects use them. */
#include "loader.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "load/mesh_import.h"

/* ---- objects ---------------------------------------------------------- */

/* The scene format's name for each shape_kind, in its order; the
 * compiler checks that there is one per kind. */
static const char *const object_types[] = {
    "sphere", "plane", "quad", "box",        "cylinder", "triangle", "mesh",
    "cone",   "disk",  "torus", "polyhedron", "csg",     NULL,
};
_Static_assert(sizeof object_types / sizeof *object_types == SHAPE_COUNT + 1,
               "object_types names every shape_kind, in order");

const char *load_type_name(shape_kind kind) { return object_types[kind]; }

static const char *const *const object_keys[] = {
    (const char *const[]){"type", "center", "radius", "material", "transform", NULL},
    (const char *const[]){"type", "point", "normal", "material", "transform", NULL},
    (const char *const[]){"type", "origin", "edge_u", "edge_v", "material", "transform", NULL},
    (const char *const[]){"type", "min", "max", "material", "transform", NULL},
    (const char *const[]){"type", "base", "radius", "height", "capped", "material", "transform",
                          NULL},
    (const char *const[]){"type", "p0", "p1", "p2", "uv", "material", "transform", NULL},
    (const char *const[]){"type", "file", "smooth_angle", "material", "transform", NULL},
    (const char *const[]){"type", "base", "radius", "top_radius", "height", "capped", "material",
                          "transform", NULL},
    (const char *const[]){"type", "center", "normal", "radius", "inner_radius", "material",
                          "transform", NULL},
    (const char *const[]){"type", "center", "major_radius", "minor_radius", "material",
                          "transform", NULL},
    (const char *const[]){"type", "vertices", "faces", "preset", "center", "radius", "material",
                          "transform", NULL},
    (const char *const[]){"type", "op", "objects", "material", "transform", NULL},
};
_Static_assert(sizeof object_keys / sizeof *object_keys == SHAPE_COUNT,
               "object_keys lists the keys of every shape_kind, in order");

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
    switch (triangle_check(p[0], p[1], p[2])) {
    case TRIANGLE_OK:
        break;
    case TRIANGLE_DEGENERATE:
        return load_fail(L, map, "triangle is degenerate: p0, p1 and p2 lie on one line");
    case TRIANGLE_TOO_LARGE:
        return load_fail(L, map, "triangle is too large for single precision (its normal "
                                 "overflows); scale it down");
    }
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
 * and smoothing angle however many objects place it. Files on disk go to
 * assimp by path (so an OBJ finds its .mtl); through another reader, from
 * memory. The file's own materials join the scene's, and its triangles
 * index them there; its warnings join the scene's. */
static glint_rc load_mesh_file(loader *L, uint32_t v, const mesh_options *opts, shape *out)
{
    const char *written = ydoc_text(load_doc(L), load_node(L, v));
    char *resolved = path_join(L->files[L->cur].dir, written);
    char *data = NULL, *cache = NULL, key[64];
    mesh_file mf = {0};
    glint_rc rc = GLINT_OK;
    if (!resolved) {
        rc = err_nomem(L->err);
        goto out;
    }
    snprintf(key, sizeof key, "%a", (double)opts->smooth_angle);
    cache = malloc(strlen(resolved) + strlen(key) + 2);
    if (cache)
        sprintf(cache, "%s\n%s", resolved, key);
    int index = cache ? names_find(&L->meshes, cache, strlen(cache)) : -1;
    if (index >= 0) {
        *out = shape_mesh(scene_mesh(L->s, index));
        goto out;
    }
    glint_error merr = {0};
    if (!cache) {
        rc = err_nomem(L->err);
        goto out;
    } else if (L->reader == scene_read_file) {
        int probe;
        rc = load_open_regular(resolved, &probe, &merr);
        if (rc != GLINT_OK) {
            rc = load_cannot_read(L, v, "mesh", written, resolved, merr.msg);
            goto out;
        }
        close(probe);
        rc = scene_add_source(L->s, resolved) < 0 ? err_nomem(&merr)
                                                  : mesh_import(resolved, opts, &mf, &merr);
    } else {
        size_t size;
        rc = load_named_file(L, v, written, resolved, "mesh", &data, &size);
        if (rc != GLINT_OK)
            goto out;
        rc = mesh_import_memory(data, size, resolved, opts, &mf, &merr);
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
    if (rc == GLINT_OK && !scene_add_warnings(L->s, mf.warnings))
        rc = err_nomem(L->err);
    if (rc != GLINT_OK)
        goto out;
    if (!names_put(&L->meshes, cache, strlen(cache), index)) {
        rc = err_nomem(L->err);
        goto out;
    }
    *out = shape_mesh(scene_mesh(L->s, index));
out:
    mesh_file_free(&mf);
    free(data);
    free(cache);
    free(resolved);
    return rc;
}

/* Cone: radius > 0 at the base, top_radius >= 0 (default 0, pointed). */
static glint_rc load_cone(loader *L, uint32_t map, shape *out)
{
    vec3 base;
    float r, top = 0.0f, h;
    bool capped = true;
    uint32_t v;
    glint_rc rc = load_need_vec3(L, map, "base", "cone", &base);
    if (rc == GLINT_OK)
        rc = load_need_positive(L, map, "radius", "cone", &r);
    if (rc == GLINT_OK && (v = load_get(L, map, "top_radius")) != YDOC_NONE)
        rc = load_nonneg(L, v, "top_radius", &top);
    if (rc == GLINT_OK)
        rc = load_need_positive(L, map, "height", "cone", &h);
    if (rc == GLINT_OK && (v = load_get(L, map, "capped")) != YDOC_NONE)
        rc = load_bool(L, v, "capped", &capped);
    if (rc == GLINT_OK)
        *out = shape_cone(base, r, top, h, capped);
    return rc;
}

/* Disk: radius > 0, 0 <= inner_radius < radius. */
static glint_rc load_disk(loader *L, uint32_t map, shape *out)
{
    vec3 c, n;
    float r, inner = 0.0f;
    uint32_t v, nv;
    glint_rc rc = load_need_vec3(L, map, "center", "disk", &c);
    if (rc == GLINT_OK)
        rc = load_need(L, map, "normal", "disk", &nv);
    if (rc == GLINT_OK)
        rc = load_nonzero_vec3(L, nv, "normal", &n);
    if (rc == GLINT_OK)
        rc = load_need_positive(L, map, "radius", "disk", &r);
    if (rc == GLINT_OK && (v = load_get(L, map, "inner_radius")) != YDOC_NONE) {
        rc = load_nonneg(L, v, "inner_radius", &inner);
        char b1[SHOWN], b2[SHOWN];
        if (rc == GLINT_OK && !(inner < r))
            rc = load_fail(L, v, "inner_radius must be less than radius (got %s, radius %s)",
                           load_shown(L, v, b1), load_shown(L, load_get(L, map, "radius"), b2));
    }
    if (rc == GLINT_OK)
        *out = shape_disk(c, n, r, inner);
    return rc;
}

static glint_rc load_torus(loader *L, uint32_t map, shape *out)
{
    vec3 c;
    float major, minor;
    glint_rc rc = load_need_vec3(L, map, "center", "torus", &c);
    if (rc == GLINT_OK)
        rc = load_need_positive(L, map, "major_radius", "torus", &major);
    if (rc == GLINT_OK)
        rc = load_need_positive(L, map, "minor_radius", "torus", &minor);
    if (rc == GLINT_OK)
        *out = shape_torus(c, major, minor);
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
    case SHAPE_MESH: {
        mesh_options mo = {MESH_DEFAULT_SMOOTH_ANGLE, L->s->threads};
        if ((v = load_get(L, map, "smooth_angle")) != YDOC_NONE) {
            rc = load_nonneg(L, v, "smooth_angle", &mo.smooth_angle);
            if (rc == GLINT_OK && mo.smooth_angle > 180.0f)
                rc = load_fail(L, v, "smooth_angle must be at most 180 degrees");
        }
        if (rc == GLINT_OK)
            rc = load_need(L, map, "file", "mesh", &v);
        if (rc == GLINT_OK)
            rc = load_path_key(L, v, "file");
        if (rc == GLINT_OK)
            rc = load_mesh_file(L, v, &mo, out);
        return rc;
    case SHAPE_CONE:
        return load_cone(L, map, out);
    case SHAPE_DISK:
        return load_disk(L, map, out);
    case SHAPE_TORUS:
        return load_torus(L, map, out);
    case SHAPE_POLYHEDRON:
        return load_polyhedron(L, map, out);
    case SHAPE_CSG: /* load_csg builds it whole */
    case SHAPE_COUNT:
        break;
    }
    }
    return rc;
}

/* The object's material: a name (resolved later), a mapping, or nothing:
 * a mesh's own materials (index -1) or the default material, added once. */
glint_rc load_object_material(loader *L, uint32_t map, bool is_mesh, int *index, uint32_t *name)
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

glint_rc load_object_type(loader *L, uint32_t map, const char *list, int *type)
{
    if (load_node(L, map)->kind != YNODE_MAP)
        return load_expected(L, map, "a mapping", list);
    uint32_t v;
    glint_rc rc = load_need(L, map, "type", "object", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "object type", object_types, type);
    if (rc != GLINT_OK)
        return rc;
    return load_check_keys_in(L, map, object_keys[*type], object_types[*type], "");
}

glint_rc load_object_shape(loader *L, uint32_t map, shape_kind kind, shape *out)
{
    return load_shape(L, map, kind, out);
}

glint_rc load_object(loader *L, uint32_t map)
{
    if (scene_object_count(L->s) >= LOAD_MAX_OBJECTS)
        return load_fail(L, map, "more than %d objects", LOAD_MAX_OBJECTS);
    uint32_t v;
    int type;
    glint_rc rc = load_object_type(L, map, "objects", &type);
    if (rc != GLINT_OK)
        return rc;
    if (type == SHAPE_CSG)
        return load_csg(L, map);
    shape sh;
    rc = load_shape(L, map, (shape_kind)type, &sh);
    int mat, xf = -1;
    uint32_t name;
    if (rc == GLINT_OK)
        rc = load_object_material(L, map, type == SHAPE_MESH, &mat, &name);
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

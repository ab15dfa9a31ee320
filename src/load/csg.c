/* A csg object: op, objects (two or more operands, each a solid object
 * with its own keys, material and transform, or a csg), and optionally a
 * material for operands without one and a transform. Nested csgs are
 * flattened into one tree (geom/csg.h): an operand's transform is its own
 * followed by those of the csgs it sits in, up to the outermost, whose
 * transform is the object's. */
#include "loader.h"

#include <stdlib.h>

#include "core/array.h"

/* What operands without a material get: nothing (the default, or a mesh's
 * own), an index, or a name to resolve later. */
typedef struct fallback {
    int index;
    uint32_t name;
    bool given;
} fallback;

typedef struct build {
    csg *c;
    ref *refs; /* operands' material names; index is set once the csg is added */
    int nrefs, cap_refs;
} build;

static glint_rc note_ref(loader *L, build *b, int leaf, uint32_t name)
{
    int i = array_push((void **)&b->refs, &b->nrefs, &b->cap_refs, sizeof *b->refs);
    if (i < 0)
        return err_nomem(L->err);
    b->refs[i] = (ref){.index = -1, .leaf = leaf, .file = L->cur, .node = name};
    return GLINT_OK;
}

static glint_rc leaf_material(loader *L, uint32_t map, build *b, int leaf, bool is_mesh,
                              const fallback *fb)
{
    int index = fb->index;
    uint32_t name = fb->name;
    if (!fb->given || load_get(L, map, "material") != YDOC_NONE) {
        glint_rc rc = load_object_material(L, map, is_mesh, &index, &name);
        if (rc != GLINT_OK)
            return rc;
    }
    b->c->leaves[leaf].material = index;
    return name != YDOC_NONE ? note_ref(L, b, leaf, name) : GLINT_OK;
}

/* Refuses shapes that enclose nothing. */
static glint_rc check_solid(loader *L, uint32_t map, const shape *sh, int type)
{
    if (shape_is_solid(sh))
        return GLINT_OK;
    uint32_t capped = load_get(L, map, "capped");
    if (type == SHAPE_CYLINDER || type == SHAPE_CONE)
        return load_fail(L, capped, "an open %s cannot be a csg operand: it does not enclose a "
                                    "solid (capped must be true)", load_type_name(type));
    return load_fail(L, load_get(L, map, "type"),
                     "a %s cannot be a csg operand: it does not enclose a solid (operands are "
                     "spheres, boxes, capped cylinders and cones, tori, polyhedra, meshes and "
                     "csgs)", load_type_name(type));
}

/* A mesh operand must be closed to have an inside. */
static glint_rc check_closed(loader *L, uint32_t map, const mesh *m)
{
    int open = mesh_open_edges(m);
    if (open < 0)
        return err_nomem(L->err);
    if (open == 0)
        return GLINT_OK;
    return load_fail(L, load_get(L, map, "file"),
                     "this mesh cannot be a csg operand: it is not a closed surface (%d of its "
                     "edges do not join exactly two triangles wound the same way), so it has no "
                     "inside", open);
}

static glint_rc node(loader *L, uint32_t map, build *b, const xform *outer, fallback fb,
                     bool top, int32_t *out);

/* One operand: *out gets its reference in the tree. */
static glint_rc operand(loader *L, uint32_t map, build *b, const xform *outer,
                        const fallback *fb, int32_t *out)
{
    int type;
    glint_rc rc = load_object_type(L, map, "objects", &type);
    if (rc != GLINT_OK)
        return rc;
    if (type == SHAPE_CSG)
        return node(L, map, b, outer, *fb, false, out);
    shape sh;
    rc = load_object_shape(L, map, (shape_kind)type, &sh);
    if (rc == GLINT_OK)
        rc = check_solid(L, map, &sh, type);
    if (rc == GLINT_OK && type == SHAPE_MESH)
        rc = check_closed(L, map, sh.mesh);
    xform x = outer ? *outer : xform_identity();
    bool moved = outer != NULL;
    uint32_t v = load_get(L, map, "transform");
    if (rc == GLINT_OK && v != YDOC_NONE) {
        xform own;
        bool any;
        rc = load_xform(L, v, &own, &any);
        if (rc == GLINT_OK && any) {
            x = outer ? xform_then(&own, outer) : own;
            moved = true;
        }
    }
    if (rc != GLINT_OK)
        return rc;
    int32_t leaf = csg_add_leaf(b->c, &sh, moved ? &x : NULL, -1);
    if (leaf == CSG_FULL)
        return load_fail(L, map, "a csg holds at most %d solids, counting those of the csgs "
                                 "inside it", CSG_MAX_LEAVES);
    if (leaf < 0)
        return err_nomem(L->err);
    *out = leaf;
    return leaf_material(L, map, b, leaf, type == SHAPE_MESH, fb);
}

/* The operands of a csg mapping, as a node; outer is the transform of the
 * csgs around it (NULL: none). The outermost csg's own transform is the
 * object's, which the scene applies, so top leaves it out. */
static glint_rc node(loader *L, uint32_t map, build *b, const xform *outer, fallback fb,
                     bool top, int32_t *out)
{
    uint32_t ov, list, v;
    int op;
    glint_rc rc = load_need(L, map, "op", "csg", &ov);
    if (rc == GLINT_OK)
        rc = load_enum(L, ov, "op", "csg op", csg_op_names, &op);
    if (rc == GLINT_OK)
        rc = load_need(L, map, "objects", "csg", &list);
    const ynode *s = rc == GLINT_OK ? load_node(L, list) : NULL;
    if (rc == GLINT_OK && s->kind != YNODE_SEQ)
        rc = load_expected(L, list, "a list", "objects");
    if (rc == GLINT_OK && s->count < 2)
        rc = load_fail(L, list, "a csg needs at least 2 objects (got %u)", s->count);
    xform x = outer ? *outer : xform_identity();
    bool moved = outer != NULL;
    if (rc == GLINT_OK && !top && (v = load_get(L, map, "transform")) != YDOC_NONE) {
        xform own;
        bool any;
        rc = load_xform(L, v, &own, &any);
        if (rc == GLINT_OK && any) {
            x = outer ? xform_then(&own, outer) : own;
            moved = true;
        }
    }
    if (rc == GLINT_OK && load_get(L, map, "material") != YDOC_NONE) {
        fb.given = true;
        rc = load_object_material(L, map, false, &fb.index, &fb.name);
    }
    int32_t *kids = rc == GLINT_OK ? malloc(sizeof *kids * s->count) : NULL;
    if (rc == GLINT_OK && !kids)
        rc = err_nomem(L->err);
    for (uint32_t i = 0; rc == GLINT_OK && i < s->count; i++)
        rc = operand(L, ydoc_item(load_doc(L), s, i), b, moved ? &x : NULL, &fb, &kids[i]);
    if (rc == GLINT_OK) {
        *out = csg_add_node(b->c, (csg_op)op, kids, (int)s->count);
        if (*out == CSG_NOMEM)
            rc = err_nomem(L->err);
    }
    free(kids);
    return rc;
}

glint_rc load_csg(loader *L, uint32_t map)
{
    build b = {calloc(1, sizeof(csg)), NULL, 0, 0};
    if (!b.c)
        return err_nomem(L->err);
    int32_t root;
    fallback fb = {-1, YDOC_NONE, false};
    int xf = -1;
    uint32_t v = load_get(L, map, "transform");
    glint_rc rc = node(L, map, &b, NULL, fb, true, &root);
    if (rc == GLINT_OK && v != YDOC_NONE)
        rc = load_transform(L, v, &xf);
    int index = -1;
    if (rc == GLINT_OK) {
        csg_finish(b.c);
        index = scene_add_csg(L->s, b.c);
        if (index < 0)
            rc = err_nomem(L->err);
    }
    if (rc != GLINT_OK) {
        csg_free(b.c);
        free(b.c);
        free(b.refs);
        return rc;
    }
    shape sh = shape_csg(b.c);
    if (scene_add_object(L->s, &sh, -1, xf) < 0)
        rc = err_nomem(L->err);
    for (int i = 0; rc == GLINT_OK && i < b.nrefs; i++) {
        int k = array_push((void **)&L->csg_refs, &L->ncsg_refs, &L->cap_csg_refs,
                           sizeof *L->csg_refs);
        if (k < 0)
            rc = err_nomem(L->err);
        else
            L->csg_refs[k] = b.refs[i], L->csg_refs[k].index = index;
    }
    free(b.refs);
    return rc;
}

/* A csg object built in code: the tree of glint_csg operands flattened
 * into one csg (geom/csg.h) as the scene format's nested csgs are
 * (src/load/csg.c): an operand's transform is its own followed by those
 * of the csgs it sits in, up to the outermost, whose transform is the
 * object's; an operand without a material takes the nearest enclosing
 * csg's. */
#include "api/build.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/check.h"
#include "core/error.h"
#include "geom/csg.h"
#include "geom/mesh.h"

static const char fn[] = "glint_scene_add_object";

typedef struct build {
    glint_scene *s;
    csg *c;
} build;

static glint_rc node(build *b, const glint_csg *in, const xform *outer, int fallback,
                     const char *where, int depth, int32_t *out, glint_error *err);

/* Refuses shapes that enclose nothing and meshes that are not closed. */
static glint_rc check_solid(const shape *sh, const char *where, glint_error *err)
{
    if (!shape_is_solid(sh))
        return api_bad(err, fn, "%sdoes not enclose a solid, so it cannot be a csg operand "
                                "(operands are spheres, boxes, capped cylinders and cones, "
                                "tori, polyhedra, closed meshes and csgs)", where);
    if (sh->kind != SHAPE_MESH)
        return GLINT_OK;
    int open = mesh_open_edges(sh->mesh);
    if (open < 0)
        return err_nomem(err);
    if (open > 0)
        return api_bad(err, fn, "%smesh cannot be a csg operand: it is not a closed surface "
                                "(%d of its edges do not join exactly two triangles wound the "
                                "same way), so it has no inside", where, open);
    return GLINT_OK;
}

/* The transform of an operand or a nested csg: its own, then outer's;
 * *moved says whether there is any. */
static glint_rc place(const glint_object *o, const xform *outer, const char *where, xform *x,
                      bool *moved, glint_error *err)
{
    xform own;
    glint_rc rc = api_xform(fn, where, o->steps, o->nsteps, &own, err);
    *moved = outer != NULL || o->nsteps > 0;
    *x = o->nsteps > 0 ? (outer ? xform_then(&own, outer) : own) : outer ? *outer : own;
    return rc;
}

/* One operand: *out gets its reference in the tree. */
static glint_rc operand(build *b, const glint_object *o, const xform *outer, int fallback,
                        const char *where, int depth, int32_t *out, glint_error *err)
{
    int nmaterials = scene_material_count(b->s);
    if (o->material < -1 || o->material >= nmaterials)
        return api_bad(err, fn, "%smaterial %d was not added (the scene has %d)", where,
                       o->material, nmaterials);
    int mat = o->material >= 0 ? o->material : fallback;
    xform x;
    bool moved;
    glint_rc rc = place(o, outer, where, &x, &moved, err);
    if (rc != GLINT_OK)
        return rc;
    if (o->shape.kind == GLINT_SHAPE_CSG)
        return node(b, &o->shape.csg, moved ? &x : NULL, mat, where, depth + 1, out, err);
    shape sh;
    rc = api_shape(b->s, fn, where, &o->shape, &sh, err);
    if (rc == GLINT_OK)
        rc = check_solid(&sh, where, err);
    if (rc == GLINT_OK && mat < 0 && sh.kind != SHAPE_MESH)
        rc = api_bad(err, fn, "%smaterial is -1 and no csg around it has one (only a mesh has "
                              "materials of its own)", where);
    if (rc != GLINT_OK)
        return rc;
    int32_t leaf = csg_add_leaf(b->c, &sh, moved ? &x : NULL, mat);
    if (leaf == CSG_FULL)
        return api_bad(err, fn, "a csg holds at most %d solids, counting those of the csgs "
                                "inside it", CSG_MAX_LEAVES);
    if (leaf < 0)
        return err_nomem(err);
    *out = leaf;
    return GLINT_OK;
}

/* The operands of a csg, as a node; outer is the transform of the csgs
 * around it (NULL: none), fallback the material of the nearest (-1: none). */
static glint_rc node(build *b, const glint_csg *in, const xform *outer, int fallback,
                     const char *where, int depth, int32_t *out, glint_error *err)
{
    if (depth >= CSG_MAX_LEAVES)
        return api_bad(err, fn, "%scsgs nest more than %d deep (does an operand hold its own "
                                "csg?)", where, CSG_MAX_LEAVES);
    if ((unsigned)in->op > GLINT_CSG_DIFFERENCE)
        return api_bad(err, fn, "%scsg op %d is not one of glint_csg_op", where, (int)in->op);
    if (!in->operands)
        return api_bad(err, fn, "%scsg operands is NULL", where);
    if (in->noperands < 2)
        return api_bad(err, fn, "%sa csg needs at least 2 operands (got %d)", where,
                       in->noperands);
    int32_t *kids = malloc(sizeof *kids * (size_t)in->noperands);
    if (!kids)
        return err_nomem(err);
    glint_rc rc = GLINT_OK;
    for (int i = 0; rc == GLINT_OK && i < in->noperands; i++) {
        /* where ends in ": " unless empty; nested: "operands[0].operands[1]: " */
        char sub[200];
        size_t n = strlen(where);
        if (n >= 2)
            snprintf(sub, sizeof sub, "%.*s.operands[%d]: ", (int)(n - 2 < 160 ? n - 2 : 160),
                     where, i);
        else
            snprintf(sub, sizeof sub, "operands[%d]: ", i);
        rc = operand(b, &in->operands[i], outer, fallback, sub, depth, &kids[i], err);
    }
    if (rc == GLINT_OK) {
        *out = csg_add_node(b->c, (csg_op)in->op, kids, in->noperands);
        if (*out == CSG_NOMEM)
            rc = err_nomem(err);
    }
    free(kids);
    return rc;
}

glint_rc api_add_csg(glint_scene *s, const glint_object *in, const xform *x, int *index,
                     glint_error *err)
{
    build b = {s, calloc(1, sizeof(csg))};
    if (!b.c)
        return err_nomem(err);
    int32_t root;
    glint_rc rc = node(&b, &in->shape.csg, NULL, in->material, "", 0, &root, err);
    if (rc == GLINT_OK) {
        csg_finish(b.c);
        if (scene_add_csg(s, b.c) < 0)
            rc = err_nomem(err);
    }
    if (rc != GLINT_OK) {
        csg_free(b.c);
        free(b.c);
        return rc;
    }
    int xf = -1;
    if (x && (xf = scene_add_xform(s, x)) < 0)
        return err_nomem(err);
    shape sh = shape_csg(b.c);
    return api_added(scene_add_object(s, &sh, -1, xf), index, err);
}

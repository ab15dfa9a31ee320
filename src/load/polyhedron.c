/* A polyhedron object: a preset (a Platonic solid with centre and
 * circumradius) or vertices and faces, checked by polyhedron_init, whose
 * findings become messages at the face or index they are about. */
#include "loader.h"

#include <stdlib.h>

#include "core/error.h"

static glint_rc load_preset(loader *L, uint32_t map, uint32_t pv, polyhedron *p)
{
    int kind;
    vec3 c = v3s(0.0f);
    float r = 1.0f;
    uint32_t v;
    glint_rc rc = load_enum(L, pv, "preset", "polyhedron preset", poly_preset_names, &kind);
    if (rc == GLINT_OK && (v = load_get(L, map, "center")) != YDOC_NONE)
        rc = load_vec3(L, v, "center", &c);
    if (rc == GLINT_OK && (v = load_get(L, map, "radius")) != YDOC_NONE)
        rc = load_positive(L, v, "radius", &r);
    if (rc != GLINT_OK)
        return rc;
    poly_error why;
    if (!polyhedron_preset(p, (poly_preset)kind, c, r, &why))
        return err_nomem(L->err); /* the presets are valid */
    return GLINT_OK;
}

/* The vertices: a list of at least four [x, y, z]. */
static glint_rc load_vertices(loader *L, uint32_t v, vec3 **out, int *n)
{
    const ynode *s = load_node(L, v);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, "a list of [x, y, z]", "vertices");
    if (s->count < 4)
        return load_fail(L, v, "a polyhedron needs at least 4 vertices (got %u)", s->count);
    *out = malloc(sizeof **out * s->count);
    if (!*out)
        return err_nomem(L->err);
    *n = (int)s->count;
    glint_rc rc = GLINT_OK;
    for (uint32_t i = 0; rc == GLINT_OK && i < s->count; i++)
        rc = load_vec3(L, ydoc_item(load_doc(L), s, i), "vertices", &(*out)[i]);
    return rc;
}

/* The faces: a list of at least four lists of vertex indices. */
static glint_rc load_faces(loader *L, uint32_t v, int nverts, int32_t **idx, int **sizes,
                           int *nfaces)
{
    const ydoc *d = load_doc(L);
    const ynode *s = load_node(L, v);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, "a list of faces (lists of vertex indices)", "faces");
    if (s->count < 4)
        return load_fail(L, v, "a polyhedron needs at least 4 faces (got %u)", s->count);
    size_t total = 0;
    for (uint32_t f = 0; f < s->count; f++) {
        uint32_t fv = ydoc_item(d, s, f);
        if (load_node(L, fv)->kind != YNODE_SEQ)
            return load_expected(L, fv, "a list of vertex indices", "faces");
        total += load_node(L, fv)->count;
    }
    *idx = malloc(sizeof **idx * (total ? total : 1));
    *sizes = malloc(sizeof **sizes * s->count);
    if (!*idx || !*sizes)
        return err_nomem(L->err);
    *nfaces = (int)s->count;
    size_t k = 0;
    for (uint32_t f = 0; f < s->count; f++) {
        const ynode *face = load_node(L, ydoc_item(d, s, f));
        (*sizes)[f] = (int)face->count;
        for (uint32_t i = 0; i < face->count; i++) {
            int x;
            uint32_t iv = ydoc_item(d, face, i);
            glint_rc rc = load_int(L, iv, "faces", -2147483647 - 1, 2147483647, &x);
            if (rc == GLINT_OK && (x < 0 || x >= nverts))
                rc = load_fail(L, iv, "vertex index %d is out of range (the polyhedron has %d "
                                      "vertices, 0 to %d)", x, nverts, nverts - 1);
            if (rc != GLINT_OK)
                return rc;
            (*idx)[k++] = x;
        }
    }
    return GLINT_OK;
}

/* polyhedron_init's finding as a message at the node it is about: the
 * index, the face, or the list of faces. */
static glint_rc poly_message(loader *L, uint32_t faces, const poly_error *e)
{
    if (e->what == POLY_NOMEM)
        return err_nomem(L->err);
    const ydoc *d = load_doc(L);
    uint32_t fv = e->face >= 0 ? ydoc_item(d, load_node(L, faces), (uint32_t)e->face) : faces;
    uint32_t iv = e->corner >= 0 ? ydoc_item(d, load_node(L, fv), (uint32_t)e->corner) : fv;
    uint32_t at = e->what == POLY_INSIDE_OUT                            ? faces
                  : e->what == POLY_INDEX || e->what == POLY_REPEAT ||
                    e->what == POLY_NOT_PLANAR ? iv
                                               : fv;
    char msg[512];
    polyhedron_explain(e, msg, sizeof msg);
    return load_fail(L, at, "%s", msg);
}

static glint_rc load_mesh_form(loader *L, uint32_t map, polyhedron *p)
{
    uint32_t vv = load_get(L, map, "vertices"), fv;
    if (vv == YDOC_NONE && load_get(L, map, "faces") == YDOC_NONE)
        return load_fail(L, map, "polyhedron needs 'preset', or 'vertices' and 'faces'");
    glint_rc rc = load_need(L, map, "vertices", "polyhedron", &vv);
    if (rc == GLINT_OK)
        rc = load_need(L, map, "faces", "polyhedron", &fv);
    static const char *const preset_only[] = {"center", "radius"};
    for (int i = 0; rc == GLINT_OK && i < 2; i++) {
        uint32_t k = load_get(L, map, preset_only[i]);
        if (k != YDOC_NONE)
            rc = load_fail(L, k, "'%s' goes with 'preset'; a polyhedron made of vertices and "
                                 "faces is placed by its vertices (or a transform)",
                           preset_only[i]);
    }
    vec3 *verts = NULL;
    int32_t *idx = NULL;
    int *sizes = NULL, nverts = 0, nfaces = 0;
    if (rc == GLINT_OK)
        rc = load_vertices(L, vv, &verts, &nverts);
    if (rc == GLINT_OK)
        rc = load_faces(L, fv, nverts, &idx, &sizes, &nfaces);
    if (rc != GLINT_OK) {
        free(verts);
        free(idx);
        free(sizes);
        return rc;
    }
    poly_error why;
    bool ok = polyhedron_init(p, verts, nverts, idx, sizes, nfaces, &why);
    free(sizes);
    return ok ? GLINT_OK : poly_message(L, fv, &why);
}

glint_rc load_polyhedron(loader *L, uint32_t map, shape *out)
{
    polyhedron *p = calloc(1, sizeof *p);
    if (!p)
        return err_nomem(L->err);
    uint32_t pv = load_get(L, map, "preset");
    glint_rc rc = pv != YDOC_NONE ? load_preset(L, map, pv, p) : load_mesh_form(L, map, p);
    if (rc == GLINT_OK && pv != YDOC_NONE) {
        static const char *const mesh_only[] = {"vertices", "faces"};
        for (int i = 0; rc == GLINT_OK && i < 2; i++) {
            uint32_t k = load_get(L, map, mesh_only[i]);
            if (k != YDOC_NONE)
                rc = load_fail(L, k, "a polyhedron takes either 'preset' or 'vertices' and "
                                     "'faces', not both");
        }
    }
    if (rc == GLINT_OK && scene_add_polyhedron(L->s, p) < 0)
        rc = err_nomem(L->err);
    if (rc != GLINT_OK) {
        polyhedron_free(p);
        free(p);
        return rc;
    }
    *out = shape_polyhedron(p);
    return GLINT_OK;
}

/* The shapes of objects built in code, with the scene format's rules and
 * words (docs/scene-format.md, src/load/objects.c and polyhedron.c). */
#include "api/build.h"

#include <stdlib.h>

#include "api/check.h"
#include "core/error.h"
#include "geom/polyhedron.h"

/* All finite: a, and b and c unless NULL (three values each). */
static bool finite3(const double *a, const double *b, const double *c)
{
    return api_finite(a, 3) && (!b || api_finite(b, 3)) && (!c || api_finite(c, 3));
}

static bool positive(double x) { return isfinite((float)x) && (float)x > 0.0f; }

static glint_rc make_triangle(const glint_triangle *t, const char *fn, const char *where,
                              shape *out, glint_error *err)
{
    vec3 p0 = api_vec3(t->p0), p1 = api_vec3(t->p1), p2 = api_vec3(t->p2);
    if (!finite3(t->p0, t->p1, t->p2) || triangle_check(p0, p1, p2) == TRIANGLE_DEGENERATE)
        return api_bad(err, fn, "%striangle is degenerate (p0, p1 and p2 lie on one line) or "
                                "not finite", where);
    if (triangle_check(p0, p1, p2) == TRIANGLE_TOO_LARGE)
        return api_bad(err, fn, "%striangle is too large for single precision (its normal "
                                "overflows)", where);
    *out = shape_triangle(p0, p1, p2);
    if (!t->has_uv)
        return GLINT_OK;
    if (!api_finite(&t->uv[0][0], 6))
        return api_bad(err, fn, "%striangle uv must be finite", where);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 2; k++)
            out->triangle.uv[i][k] = (float)t->uv[i][k];
    return GLINT_OK;
}

/* A cone, a disk or (any other kind) a torus. */
static glint_rc make_round(const glint_shape *in, const char *fn, const char *where, shape *out,
                           glint_error *err)
{
    const glint_cone *c = &in->cone;
    const glint_disk *d = &in->disk;
    const glint_torus *t = &in->torus;
    if (in->kind == GLINT_SHAPE_CONE) {
        if (!finite3(c->base, NULL, NULL) || !positive(c->radius) || !positive(c->height) ||
            !isfinite((float)c->top_radius) || !(c->top_radius >= 0))
            return api_bad(err, fn, "%scone radius and height must be > 0, top_radius >= 0 and "
                                    "every value finite", where);
        *out = shape_cone(api_vec3(c->base), (float)c->radius, (float)c->top_radius,
                          (float)c->height, c->capped != 0);
        return GLINT_OK;
    }
    if (in->kind == GLINT_SHAPE_DISK) {
        if (!finite3(d->center, d->normal, NULL) || v3_is_zero(api_vec3(d->normal)) ||
            !positive(d->radius) || !isfinite((float)d->inner_radius))
            return api_bad(err, fn, "%sdisk normal must not be zero, radius must be > 0 and "
                                    "every value finite", where);
        if (!(d->inner_radius >= 0 && (float)d->inner_radius < (float)d->radius))
            return api_bad(err, fn, "%sdisk inner_radius must be >= 0 and less than radius "
                                    "(got %g, radius %g)", where, d->inner_radius, d->radius);
        *out = shape_disk(api_vec3(d->center), api_vec3(d->normal), (float)d->radius,
                          (float)d->inner_radius);
        return GLINT_OK;
    }
    if (!finite3(t->center, NULL, NULL) || !positive(t->major_radius) ||
        !positive(t->minor_radius))
        return api_bad(err, fn, "%storus major_radius and minor_radius must be > 0 and every "
                                "value finite", where);
    *out = shape_torus(api_vec3(t->center), (float)t->major_radius, (float)t->minor_radius);
    return GLINT_OK;
}

/* Vertices and faces, checked by polyhedron_init. */
static glint_rc make_faces(const glint_polyhedron *in, const char *fn, const char *where,
                           polyhedron *p, glint_error *err)
{
    if (!in->vertices || !in->indices || !in->face_sizes)
        return api_bad(err, fn, "%spolyhedron %s is NULL", where,
                       !in->vertices ? "vertices" : !in->indices ? "indices" : "face_sizes");
    if (in->nvertices < 4 || in->nfaces < 4)
        return api_bad(err, fn, "%sa polyhedron needs at least 4 vertices and 4 faces (got %d "
                                "and %d)", where, in->nvertices, in->nfaces);
    size_t total = 0;
    for (int f = 0; f < in->nfaces; f++) {
        if (in->face_sizes[f] < 0 || in->face_sizes[f] > in->nvertices)
            return api_bad(err, fn, "%sface %d has %d vertices (a face has 3 to %d, the "
                                    "vertex count)", where, f, in->face_sizes[f], in->nvertices);
        total += (size_t)in->face_sizes[f];
    }
    for (int i = 0; i < in->nvertices; i++)
        if (!api_finite(in->vertices[i], 3))
            return api_bad(err, fn, "%svertex %d is not finite", where, i);
    vec3 *verts = malloc(sizeof *verts * (size_t)in->nvertices);
    int32_t *idx = malloc(sizeof *idx * (total ? total : 1));
    if (!verts || !idx) {
        free(verts);
        free(idx);
        return err_nomem(err);
    }
    for (int i = 0; i < in->nvertices; i++)
        verts[i] = api_vec3(in->vertices[i]);
    for (size_t k = 0; k < total; k++)
        idx[k] = in->indices[k];
    poly_error why;
    if (polyhedron_init(p, verts, in->nvertices, idx, in->face_sizes, in->nfaces, &why))
        return GLINT_OK;
    if (why.what == POLY_NOMEM)
        return err_nomem(err);
    char msg[512];
    polyhedron_explain(&why, msg, sizeof msg);
    return api_bad(err, fn, "%s%s", where, msg);
}

static glint_rc make_polyhedron(glint_scene *s, const glint_polyhedron *in, const char *fn,
                                const char *where, shape *out, glint_error *err)
{
    if ((unsigned)in->preset > GLINT_POLYHEDRON_ICOSAHEDRON)
        return api_bad(err, fn, "%spolyhedron preset %d is not one of glint_polyhedron_preset",
                       where, (int)in->preset);
    if (in->preset != GLINT_POLYHEDRON_FACES &&
        (!finite3(in->center, NULL, NULL) || !positive(in->radius)))
        return api_bad(err, fn, "%spolyhedron radius must be > 0 and the centre finite", where);
    polyhedron *p = calloc(1, sizeof *p);
    if (!p)
        return err_nomem(err);
    glint_rc rc = GLINT_OK;
    poly_error why;
    if (in->preset == GLINT_POLYHEDRON_FACES)
        rc = make_faces(in, fn, where, p, err);
    else if (!polyhedron_preset(p, (poly_preset)(in->preset - 1), api_vec3(in->center),
                                (float)in->radius, &why))
        rc = err_nomem(err); /* the presets are valid */
    if (rc == GLINT_OK && scene_add_polyhedron(s, p) < 0)
        rc = err_nomem(err);
    if (rc != GLINT_OK) {
        polyhedron_free(p);
        free(p);
        return rc;
    }
    *out = shape_polyhedron(p);
    return GLINT_OK;
}

glint_rc api_shape(glint_scene *s, const char *fn, const char *where, const glint_shape *in,
                   shape *out, glint_error *err)
{
    switch (in->kind) {
    case GLINT_SHAPE_SPHERE:
        if (!finite3(in->sphere.center, NULL, NULL) || !positive(in->sphere.radius))
            return api_bad(err, fn, "%ssphere radius must be > 0 and every value finite", where);
        *out = shape_sphere(api_vec3(in->sphere.center), (float)in->sphere.radius);
        return GLINT_OK;
    case GLINT_SHAPE_PLANE:
        if (!finite3(in->plane.point, in->plane.normal, NULL) ||
            v3_is_zero(api_vec3(in->plane.normal)))
            return api_bad(err, fn, "%splane normal must not be zero and every value finite",
                           where);
        *out = shape_plane(api_vec3(in->plane.point), api_vec3(in->plane.normal));
        return GLINT_OK;
    case GLINT_SHAPE_QUAD: {
        vec3 u = api_vec3(in->quad.edge_u), v = api_vec3(in->quad.edge_v);
        if (!finite3(in->quad.origin, in->quad.edge_u, in->quad.edge_v) ||
            v3_is_zero(v3_cross(u, v)))
            return api_bad(err, fn, "%squad edge_v must not be parallel to edge_u (nor either be "
                                    "zero) and every value finite", where);
        *out = shape_quad(api_vec3(in->quad.origin), u, v);
        return GLINT_OK;
    }
    case GLINT_SHAPE_BOX: {
        vec3 lo = api_vec3(in->box.min), hi = api_vec3(in->box.max);
        if (!finite3(in->box.min, in->box.max, NULL) ||
            !(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            return api_bad(err, fn, "%sbox max must be greater than min on every axis and every "
                                    "value finite", where);
        *out = shape_box(lo, hi);
        return GLINT_OK;
    }
    case GLINT_SHAPE_CYLINDER: {
        const glint_cylinder *c = &in->cylinder;
        if (!finite3(c->base, NULL, NULL) || !positive(c->radius) || !positive(c->height))
            return api_bad(err, fn, "%scylinder radius and height must be > 0 and every value "
                                    "finite", where);
        *out = shape_cylinder(api_vec3(c->base), (float)c->radius, (float)c->height,
                              c->capped != 0);
        return GLINT_OK;
    }
    case GLINT_SHAPE_TRIANGLE:
        return make_triangle(&in->triangle, fn, where, out, err);
    case GLINT_SHAPE_MESH:
        if (in->mesh.index < 0 || in->mesh.index >= scene_mesh_count(s))
            return api_bad(err, fn, "%smesh %d was not added (the scene has %d)", where,
                           in->mesh.index, scene_mesh_count(s));
        *out = shape_mesh(scene_mesh(s, in->mesh.index));
        return GLINT_OK;
    case GLINT_SHAPE_CONE:
    case GLINT_SHAPE_DISK:
    case GLINT_SHAPE_TORUS:
        return make_round(in, fn, where, out, err);
    case GLINT_SHAPE_POLYHEDRON:
        return make_polyhedron(s, &in->polyhedron, fn, where, out, err);
    case GLINT_SHAPE_CSG: /* api_add_csg builds it whole */
        break;
    }
    return api_bad(err, fn, "%sshape kind %d is not one of glint_shape_kind", where,
                   (int)in->kind);
}

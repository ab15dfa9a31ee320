#include "shape.h"

#include "csg.h"
#include "mesh.h"
#include "polyhedron.h"
#include "shape_bounds.h"
#include "shape_inline.h"

bool shape_intersect(const shape *s, const ray *r, shape_hit *hit)
{
    switch (s->kind) {
    case SHAPE_SPHERE:
        return sphere_intersect(&s->sphere, r, hit);
    case SHAPE_PLANE:
        return plane_intersect(&s->plane, r, hit);
    case SHAPE_QUAD:
        return quad_intersect(&s->quad, r, hit);
    case SHAPE_BOX:
        return box_intersect(&s->box, r, hit);
    case SHAPE_CYLINDER:
        return cylinder_intersect(&s->cylinder, r, hit);
    case SHAPE_TRIANGLE:
        return triangle_intersect(&s->triangle, r, hit);
    case SHAPE_MESH:
        return mesh_intersect(s->mesh, r, hit);
    case SHAPE_CONE:
        return cone_intersect(&s->cone, r, hit);
    case SHAPE_DISK:
        return disk_intersect(&s->disk, r, hit);
    case SHAPE_TORUS:
        return torus_intersect(&s->torus, r, hit);
    case SHAPE_POLYHEDRON:
        return polyhedron_intersect(s->polyhedron, r, hit);
    case SHAPE_CSG:
        return csg_intersect(s->csg, r, hit);
    case SHAPE_COUNT:
        break;
    }
    return false;
}

/* Analytic shapes find their nearest hit without computing normals, so
 * for them the occlusion query costs the same as intersect, but for the
 * torus, which often knows that a root lies ahead without finding it;
 * meshes stop at the first triangle found. A csg has to classify the ray up to its first
 * boundary whichever query it answers. */
bool shape_occluded(const shape *s, const ray *r)
{
    shape_hit h;
    switch (s->kind) {
    case SHAPE_SPHERE:
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_BOX:
    case SHAPE_CYLINDER:
    case SHAPE_TRIANGLE:
    case SHAPE_CONE:
    case SHAPE_DISK:
    case SHAPE_POLYHEDRON:
    case SHAPE_CSG:
        return shape_intersect(s, r, &h);
    case SHAPE_TORUS:
        return torus_occluded(&s->torus, r);
    case SHAPE_MESH:
        return mesh_occluded(s->mesh, r);
    case SHAPE_COUNT:
        break;
    }
    return false;
}

void shape_surface_no_uv(const shape *s, const ray *r, const shape_hit *hit, surface *out)
{
    switch (s->kind) {
    case SHAPE_SPHERE:
        sphere_surface_plain(&s->sphere, ray_at(r, hit->t), out);
        return;
    case SHAPE_CYLINDER:
        cylinder_surface_no_uv(&s->cylinder, ray_at(r, hit->t), hit, out);
        break;
    case SHAPE_CONE:
        cone_surface_no_uv(&s->cone, ray_at(r, hit->t), hit, out);
        break;
    case SHAPE_TORUS:
        torus_surface_no_uv(&s->torus, ray_at(r, hit->t), out);
        break;
    case SHAPE_CSG:
        csg_surface(s->csg, r, hit, false, out);
        return;
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_BOX:
    case SHAPE_TRIANGLE:
    case SHAPE_DISK:
    case SHAPE_POLYHEDRON:
    case SHAPE_MESH:
    case SHAPE_COUNT:
        shape_surface(s, r, hit, out);
        return;
    }
    out->ng = out->n;
}

void shape_surface(const shape *s, const ray *r, const shape_hit *hit, surface *out)
{
    vec3 p = ray_at(r, hit->t);
    switch (s->kind) {
    case SHAPE_SPHERE:
        sphere_surface(&s->sphere, p, out);
        break;
    case SHAPE_PLANE:
        plane_surface(&s->plane, p, out);
        break;
    case SHAPE_QUAD:
        quad_surface(&s->quad, p, hit, out);
        break;
    case SHAPE_BOX:
        box_surface(&s->box, p, hit, out);
        break;
    case SHAPE_CYLINDER:
        cylinder_surface(&s->cylinder, p, hit, out);
        break;
    case SHAPE_TRIANGLE:
        triangle_surface(&s->triangle, p, hit, out);
        break;
    case SHAPE_CONE:
        cone_surface(&s->cone, p, hit, out);
        break;
    case SHAPE_DISK:
        disk_surface(&s->disk, p, out);
        break;
    case SHAPE_TORUS:
        torus_surface(&s->torus, p, out);
        break;
    case SHAPE_POLYHEDRON:
        polyhedron_surface(s->polyhedron, p, hit, out);
        break;
    case SHAPE_MESH:
        mesh_surface(s->mesh, p, hit, out);
        return;
    case SHAPE_CSG:
        csg_surface(s->csg, r, hit, true, out);
        return;
    case SHAPE_COUNT:
        break;
    }
    out->ng = out->n;
}

aabb shape_bounds(const shape *s) { return shape_bounds_inline(s); }

static aabb corner_bounds(aabb b, const mat4 *m)
{
    if (aabb_is_empty(b))
        return b;
    aabb r = aabb_empty();
    for (int i = 0; i < 8; i++) {
        vec3 c = v3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
        r = aabb_grow(r, mat4_point(m, c));
    }
    return r;
}

/* A torus is its centre circle (radius R in the xz plane) swept by a ball
 * of radius r, so its image is the mapped circle, an ellipse reaching
 * R sqrt(m_ix^2 + m_iz^2) along axis i, swept by the mapped ball, an
 * ellipsoid reaching r |row i|; a sphere is the ball alone. The extents
 * are worked out in double and the box is grown by 1e-5 of them and of
 * the centre's distance from the origin, far more than float rounding, so
 * that it holds the shape as the single-precision transforms place it. */
static aabb swept_bounds(const mat4 *m, vec3 center, float R, float r)
{
    const float(*a)[4] = m->m;
    vec3 c = mat4_point(m, center);
    float lo[3], hi[3], cc[3] = {c.x, c.y, c.z};
    for (int i = 0; i < 3; i++) {
        double x = a[i][0], y = a[i][1], z = a[i][2];
        double e = R * sqrt(x * x + z * z) + r * sqrt(x * x + y * y + z * z);
        e += 1e-5 * (e + fabs(cc[i]));
        lo[i] = (float)(cc[i] - e);
        hi[i] = (float)(cc[i] + e);
    }
    return (aabb){v3(lo[0], lo[1], lo[2]), v3(hi[0], hi[1], hi[2])};
}

aabb shape_bounds_mapped(const shape *s, const mat4 *m)
{
    switch (s->kind) {
    case SHAPE_TORUS:
        return swept_bounds(m, s->torus.center, s->torus.major, s->torus.minor);
    case SHAPE_SPHERE:
        return swept_bounds(m, s->sphere.center, 0.0f, s->sphere.radius);
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_BOX:
    case SHAPE_CYLINDER:
    case SHAPE_TRIANGLE:
    case SHAPE_MESH:
    case SHAPE_CONE:
    case SHAPE_DISK:
    case SHAPE_POLYHEDRON:
    case SHAPE_CSG:
    case SHAPE_COUNT:
        break;
    }
    return corner_bounds(shape_bounds(s), m);
}

bool shape_is_convex(const shape *s)
{
    switch (s->kind) {
    case SHAPE_SPHERE:
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_BOX:
    case SHAPE_TRIANGLE:
    case SHAPE_DISK:
        return true;
    case SHAPE_CYLINDER:
        return s->cylinder.capped;
    case SHAPE_CONE:
        return s->cone.capped;
    case SHAPE_POLYHEDRON:
        return s->polyhedron->convex;
    case SHAPE_MESH:
    case SHAPE_TORUS:
    case SHAPE_CSG:
        return false;
    case SHAPE_COUNT:
        break;
    }
    return false;
}

bool shape_is_solid(const shape *s)
{
    switch (s->kind) {
    case SHAPE_SPHERE:
    case SHAPE_BOX:
    case SHAPE_MESH:
    case SHAPE_TORUS:
    case SHAPE_POLYHEDRON:
    case SHAPE_CSG:
        return true;
    case SHAPE_CYLINDER:
        return s->cylinder.capped;
    case SHAPE_CONE:
        return s->cone.capped;
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_TRIANGLE:
    case SHAPE_DISK:
    case SHAPE_COUNT:
        break;
    }
    return false;
}

int shape_crossings(const shape *s, const ray *r, crossing *x, int max, bool *more)
{
    shape_hit in, out;
    bool found = false;
    *more = false;
    switch (s->kind) {
    case SHAPE_SPHERE:
        found = sphere_span(&s->sphere, r, &in, &out);
        break;
    case SHAPE_BOX:
        found = box_span(&s->box, r, &in, &out);
        break;
    case SHAPE_CYLINDER:
        found = cylinder_span(&s->cylinder, r, &in, &out);
        break;
    case SHAPE_CONE:
        found = cone_span(&s->cone, r, &in, &out);
        break;
    case SHAPE_TORUS:
        return torus_crossings(&s->torus, r, x, max);
    case SHAPE_POLYHEDRON:
        return polyhedron_crossings(s->polyhedron, r, x, max, more);
    case SHAPE_MESH:
        return mesh_crossings(s->mesh, r, x, max, more);
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_TRIANGLE:
    case SHAPE_DISK:
    case SHAPE_CSG:
    case SHAPE_COUNT:
        return 0;
    }
    return shape_span_crossings(found, in, out, r->tmin, x, max);
}

int shape_hit_material(const shape *s, const shape_hit *hit)
{
    if (s->kind == SHAPE_MESH)
        return s->mesh->tri_material ? s->mesh->tri_material[hit->part] : -1;
    if (s->kind != SHAPE_CSG)
        return -1;
    const csg_leaf *l = &s->csg->leaves[hit->leaf];
    if (l->material >= 0 || l->shape.kind != SHAPE_MESH || !l->shape.mesh->tri_material)
        return l->material;
    return l->shape.mesh->tri_material[hit->part];
}

shape shape_sphere(vec3 center, float radius)
{
    return (shape){.kind = SHAPE_SPHERE, .sphere = {center, radius}};
}

shape shape_plane(vec3 point, vec3 normal)
{
    vec3 n = v3_norm(normal), tu, tv;
    v3_basis(n, &tu, &tv);
    return (shape){.kind = SHAPE_PLANE, .plane = {point, n, tu, tv}};
}

shape shape_quad(vec3 origin, vec3 edge_u, vec3 edge_v)
{
    vec3 n = v3_cross(edge_u, edge_v);
    float nn = v3_dot(n, n);
    vec3 w = nn > 0.0f ? v3_scale(n, 1.0f / nn) : v3s(0.0f);
    return (shape){.kind = SHAPE_QUAD, .quad = {origin, edge_u, edge_v, v3_norm(n), w}};
}

shape shape_box(vec3 lo, vec3 hi)
{
    return (shape){.kind = SHAPE_BOX, .box = {v3_min(lo, hi), v3_max(lo, hi)}};
}

shape shape_cylinder(vec3 base, float radius, float height, bool capped)
{
    return (shape){.kind = SHAPE_CYLINDER, .cylinder = {base, radius, height, capped}};
}

shape shape_mesh(const struct mesh *m)
{
    return (shape){.kind = SHAPE_MESH, .mesh = m};
}

shape shape_triangle(vec3 p0, vec3 p1, vec3 p2)
{
    return (shape){.kind = SHAPE_TRIANGLE,
                   .triangle = {p0, p1, p2, {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}}}};
}

shape shape_cone(vec3 base, float radius, float top_radius, float height, bool capped)
{
    return (shape){.kind = SHAPE_CONE, .cone = {base, radius, top_radius, height, capped}};
}

shape shape_disk(vec3 center, vec3 normal, float radius, float inner_radius)
{
    vec3 n = v3_norm(normal), tu, tv;
    v3_basis(n, &tu, &tv);
    return (shape){.kind = SHAPE_DISK, .disk = {center, n, tu, tv, radius, inner_radius}};
}

shape shape_torus(vec3 center, float major_radius, float minor_radius)
{
    return (shape){.kind = SHAPE_TORUS, .torus = {center, major_radius, minor_radius}};
}

shape shape_polyhedron(const struct polyhedron *p)
{
    return (shape){.kind = SHAPE_POLYHEDRON, .polyhedron = p};
}

shape shape_csg(const struct csg *c)
{
    return (shape){.kind = SHAPE_CSG, .csg = c};
}

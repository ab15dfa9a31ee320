#include "shape.h"

#include "mesh.h"

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
    }
    return false;
}

/* Analytic shapes find their nearest hit without computing normals, so
 * for them the occlusion query costs the same as intersect; meshes stop at
 * the first triangle found. */
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
        return shape_intersect(s, r, &h);
    case SHAPE_MESH:
        return mesh_occluded(s->mesh, r);
    }
    return false;
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
    case SHAPE_MESH:
        mesh_surface(s->mesh, p, hit, out);
        return;
    }
    out->ng = out->n;
}

aabb shape_bounds(const shape *s)
{
    switch (s->kind) {
    case SHAPE_SPHERE: {
        vec3 r = v3s(s->sphere.radius);
        return (aabb){v3_sub(s->sphere.center, r), v3_add(s->sphere.center, r)};
    }
    case SHAPE_PLANE:
        return aabb_empty();
    case SHAPE_QUAD: {
        const struct quad *q = &s->quad;
        aabb b = aabb_point(q->origin);
        b = aabb_grow(b, v3_add(q->origin, q->edge_u));
        b = aabb_grow(b, v3_add(q->origin, q->edge_v));
        return aabb_grow(b, v3_add(v3_add(q->origin, q->edge_u), q->edge_v));
    }
    case SHAPE_BOX:
        return (aabb){s->box.lo, s->box.hi};
    case SHAPE_CYLINDER: {
        const struct cylinder *c = &s->cylinder;
        vec3 lo = v3(c->base.x - c->radius, c->base.y, c->base.z - c->radius);
        vec3 hi = v3(c->base.x + c->radius, c->base.y + c->height, c->base.z + c->radius);
        return (aabb){lo, hi};
    }
    case SHAPE_TRIANGLE:
        return aabb_grow(aabb_grow(aabb_point(s->triangle.p0), s->triangle.p1), s->triangle.p2);
    case SHAPE_MESH:
        return s->mesh->bounds;
    }
    return aabb_empty();
}

bool shape_is_convex(const shape *s)
{
    switch (s->kind) {
    case SHAPE_SPHERE:
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_BOX:
    case SHAPE_TRIANGLE:
        return true;
    case SHAPE_CYLINDER:
        return s->cylinder.capped;
    case SHAPE_MESH:
        return false;
    }
    return false;
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

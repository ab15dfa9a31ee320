/* The loader's sections for cone, disk, torus, polyhedron and csg: what
 * each key means and its default, the csg's tree, materials and transforms,
 * and every kind of bad input as one exact line with file:line:column
 * (GLINT_ERR_INPUT, exit code 2), in the manner of test_load.c. */
#include <criterion/criterion.h>
#include <math.h>

#include "load_check.h"
#include "near.h"

#define TETRA_OBJ                                                                                  \
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"                                                         \
    "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

Test(load_geometry, every_new_shape_and_its_defaults)
{
    scene *s = load_ok("objects:\n"
                       "  - {type: cone, base: [1, 2, 3], radius: 2, height: 4}\n"
                       "  - {type: cone, base: [0, 0, 0], radius: 2, top_radius: 0.5, height: 1,\n"
                       "     capped: false}\n"
                       "  - {type: disk, center: [0, 1, 0], normal: [0, 2, 0], radius: 3}\n"
                       "  - {type: disk, center: [0, 1, 0], normal: [1, 0, 0], radius: 3,\n"
                       "     inner_radius: 1}\n"
                       "  - {type: torus, center: [0, 1, 0], major_radius: 2, minor_radius: 0.5}\n"
                       "  - {type: polyhedron, preset: octahedron}\n"
                       "  - {type: polyhedron, preset: cube, center: [5, 0, 0], radius: 2}\n"
                       "  - type: polyhedron\n"
                       "    vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]\n"
                       "    faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]\n");
    cr_assert_eq(s->nobjects, 8);
    const struct cone *c = &s->objects[0].shape.cone;
    cr_expect_eq(s->objects[0].shape.kind, SHAPE_CONE);
    ASSERT_V3_NEAR(c->base, 1, 2, 3, 0);
    cr_expect(c->radius == 2 && c->height == 4);
    cr_expect_eq(c->top_radius, 0.0f, "pointed by default");
    cr_expect(c->capped, "capped by default");
    c = &s->objects[1].shape.cone;
    cr_expect(c->top_radius == 0.5f && !c->capped);
    const struct disk *d = &s->objects[2].shape.disk;
    cr_expect_eq(s->objects[2].shape.kind, SHAPE_DISK);
    ASSERT_V3_NEAR(d->normal, 0, 1, 0, 0);
    cr_expect(d->radius == 3 && d->inner == 0);
    cr_expect_eq(s->objects[3].shape.disk.inner, 1.0f);
    const struct torus *t = &s->objects[4].shape.torus;
    cr_expect_eq(s->objects[4].shape.kind, SHAPE_TORUS);
    cr_expect(t->major == 2 && t->minor == 0.5f);
    const polyhedron *p = s->objects[5].shape.polyhedron;
    cr_expect_eq(p->nfaces, 8);
    ASSERT_NEAR(v3_len(p->verts[0]), 1, 1e-6); /* centre 0, radius 1 by default */
    p = s->objects[6].shape.polyhedron;
    ASSERT_V3_NEAR(p->bounds.lo, 5 - 2 / sqrt(3), -2 / sqrt(3), -2 / sqrt(3), 1e-5);
    p = s->objects[7].shape.polyhedron;
    cr_expect(p->nverts == 4 && p->nfaces == 4 && p->convex);
    cr_expect_eq(s->npolyhedra, 3);
    scene_free(s);
}

/* A die: (cube & sphere) - dot - dot, nested one level; the csg's material
 * goes to operands without one, names resolve wherever they are defined,
 * and a nested csg's transform applies to its operands after their own. */
Test(load_geometry, csg_tree_materials_and_transforms)
{
    scene *s = load_ok(
        "objects:\n"
        "  - type: csg\n"
        "    op: difference\n"
        "    material: ivory\n"
        "    transform: [translate: [0, 0, -5]]\n"
        "    objects:\n"
        "      - type: csg\n"
        "        op: intersection\n"
        "        transform: [scale: 2]\n"
        "        objects:\n"
        "          - {type: box, min: [-1, -1, -1], max: [1, 1, 1]}\n"
        "          - {type: sphere, center: [0, 0, 0], radius: 1.4, material: red,\n"
        "             transform: [translate: [0.1, 0, 0]]}\n"
        "      - {type: sphere, center: [0, 0, 2], radius: 0.3, material: {color: [0, 0, 0]}}\n"
        "      - {type: sphere, center: [0, 2, 0], radius: 0.3}\n"
        "materials:\n"
        "  ivory: {color: [1, 1, 0.9]}\n"
        "  red: {color: [1, 0, 0]}\n");
    cr_assert_eq(s->nobjects, 1);
    const object *o = &s->objects[0];
    cr_assert_eq(o->shape.kind, SHAPE_CSG);
    cr_expect_eq(o->material, -1, "materials are the operands'");
    cr_expect_geq(o->xform, 0, "the outer transform is the object's");
    const csg *c = o->shape.csg;
    cr_assert_eq(c->nleaves, 4);
    cr_assert_eq(c->nnodes, 2);
    cr_expect_eq(c->nodes[1].op, CSG_DIFFERENCE);
    cr_expect_eq(c->nodes[0].op, CSG_INTERSECTION);
    const material *ivory = &s->materials[c->leaves[0].material];
    ASSERT_V3_NEAR(ivory->color, 1, 1, 0.9, 1e-6);
    ASSERT_V3_NEAR(s->materials[c->leaves[1].material].color, 1, 0, 0, 0);
    ASSERT_V3_NEAR(s->materials[c->leaves[2].material].color, 0, 0, 0, 0);
    cr_expect_eq(c->leaves[3].material, c->leaves[0].material);
    cr_expect(!c->leaves[0].flip && !c->leaves[1].flip && c->leaves[2].flip && c->leaves[3].flip);
    /* Leaf 1: its own translate, then the nested scale 2. */
    cr_assert(c->leaves[1].moved);
    vec3 q = mat4_point(&c->leaves[1].x.fwd, v3(0, 0, 0));
    ASSERT_V3_NEAR(q, 0.2, 0, 0, 1e-6);
    cr_expect(!c->leaves[2].moved, "the outer transform is not the operands'");
    /* The bound is the intersection's: the scaled cube. */
    ASSERT_V3_NEAR(s->bounds[0].lo, -2, -2, -7, 1e-5);
    /* Down the z axis: the dot's hole, at the cube face z = 2 minus 0.3. */
    ray r = ray_make(v3(0, 0, 5), v3(0, 0, -1), INFINITY);
    scene_hit h;
    cr_assert(scene_intersect(s, &r, &h));
    ASSERT_NEAR(h.h.t, 8.3, 1e-5);
    ASSERT_V3_NEAR(scene_hit_material(s, &h)->color, 0, 0, 0, 0);
    scene_free(s);
}

Test(load_geometry, csg_of_a_closed_mesh)
{
    vfile files[] = {{"tetra.obj", TETRA_OBJ}, {NULL, NULL}};
    scene *s = load_ok_with("objects:\n"
                            "  - type: csg\n"
                            "    op: difference\n"
                            "    objects:\n"
                            "      - {type: mesh, file: tetra.obj}\n"
                            "      - {type: sphere, center: [0, 0, 0], radius: 0.3}\n",
                            files);
    const csg *c = s->objects[0].shape.csg;
    cr_expect_eq(c->leaves[0].material, -1, "a mesh operand keeps the file's materials");
    ray r = ray_make(v3(0.1f, 0.1f, 5), v3(0, 0, -1), INFINITY);
    scene_hit h;
    cr_assert(scene_intersect(s, &r, &h));
    ASSERT_NEAR(h.h.t, 5 - 0.8, 1e-5);
    cr_assert_not_null(scene_hit_material(s, &h));
    scene_free(s);
}

/* ---- bad input -------------------------------------------------------------- */

Test(load_geometry_errors, cone_disk_torus)
{
    expect_error("objects: [{type: cone, base: [0, 0, 0], radius: 1, height: 1, top_radius: -1}]\n",
                 "scene.yaml:1:75: top_radius must be >= 0 (got -1)");
    expect_error("objects: [{type: cone, base: [0, 0, 0], radius: 0, height: 1}]\n",
                 "scene.yaml:1:49: radius must be > 0 (got 0)");
    expect_error("objects: [{type: cone, base: [0, 0, 0], radius: 1}]\n",
                 "scene.yaml:1:11: cone needs 'height'");
    expect_error("objects: [{type: cone, base: [0, 0], radius: 1, height: 1}]\n",
                 "scene.yaml:1:30: expected 3 numbers for 'base', got 2");
    expect_error("objects: [{type: cone, base: [0, 0, 0], radius: 1, height: 1, capped: 2}]\n",
                 "scene.yaml:1:71: expected true or false for 'capped', got a number");
    expect_error("objects: [{type: cone, base: [0, 0, 0], radius: 1, heigth: 1}]\n",
                 "scene.yaml:1:52: unknown key 'heigth' in cone (did you mean 'height'?)");
    expect_error("objects: [{type: disk, center: [0, 0, 0], normal: [0, 0, 0], radius: 1}]\n",
                 "scene.yaml:1:51: normal must not be [0, 0, 0]");
    expect_error("objects: [{type: disk, center: [0, 0, 0], normal: [0, 1, 0], radius: 1,"
                 " inner_radius: 1}]\n",
                 "scene.yaml:1:87: inner_radius must be less than radius (got 1, radius 1)");
    expect_error("objects: [{type: disk, center: [0, 0, 0], normal: [0, 1, 0], radius: 1,"
                 " inner_radius: -1}]\n",
                 "scene.yaml:1:87: inner_radius must be >= 0 (got -1)");
    expect_error("objects: [{type: disk, center: [0, 0, 0], normal: [0, 1, 0]}]\n",
                 "scene.yaml:1:11: disk needs 'radius'");
    expect_error("objects: [{type: torus, center: [0, 0, 0], major_radius: 1, minor_radius: 0}]\n",
                 "scene.yaml:1:75: minor_radius must be > 0 (got 0)");
    expect_error("objects: [{type: torus, center: [0, 0, 0], major_radius: -1, minor_radius: 1}]\n",
                 "scene.yaml:1:58: major_radius must be > 0 (got -1)");
    expect_error("objects: [{type: torus, center: [0, 0, 0], major_radius: 1}]\n",
                 "scene.yaml:1:11: torus needs 'minor_radius'");
    expect_error("objects: [{type: torus, center: [0, 0, 0], major_radius: 1, minor_radius: .inf}]\n",
                 "scene.yaml:1:75: minor_radius must be a finite number (got .inf)");
    expect_error("objects: [{type: torus, center: [0, 0, 0], major: 1, minor_radius: 1}]\n",
                 "scene.yaml:1:44: unknown key 'major' in torus (valid: type, center, "
                 "major_radius, minor_radius, material, transform)");
}

#define TET_V "vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]"

Test(load_geometry_errors, polyhedron)
{
    expect_error("objects: [{type: polyhedron, preset: cubee}]\n",
                 "scene.yaml:1:38: unknown polyhedron preset 'cubee' (did you mean 'cube'?)");
    expect_error("objects: [{type: polyhedron}]\n",
                 "scene.yaml:1:11: polyhedron needs 'preset', or 'vertices' and 'faces'");
    expect_error("objects: [{type: polyhedron, preset: cube, radius: 0}]\n",
                 "scene.yaml:1:52: radius must be > 0 (got 0)");
    expect_error("objects: [{type: polyhedron, preset: cube, vertices: [[0, 0, 0]]}]\n",
                 "scene.yaml:1:54: a polyhedron takes either 'preset' or 'vertices' and 'faces', "
                 "not both");
    expect_error("objects: [{type: polyhedron, " TET_V "}]\n",
                 "scene.yaml:1:11: polyhedron needs 'faces'");
    expect_error("objects: [{type: polyhedron, " TET_V ", radius: 2,\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]}]\n",
                 "scene.yaml:1:94: 'radius' goes with 'preset'; a polyhedron made of vertices and "
                 "faces is placed by its vertices (or a transform)");
    expect_error("objects: [{type: polyhedron, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]],\n"
                 "  faces: [[0, 2, 1]]}]\n",
                 "scene.yaml:1:40: a polyhedron needs at least 4 vertices (got 3)");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2]]}]\n",
                 "scene.yaml:2:10: a polyhedron needs at least 4 faces (got 3)");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 4]]}]\n",
                 "scene.yaml:2:51: vertex index 4 is out of range (the polyhedron has 4 vertices, "
                 "0 to 3)");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, -1]]}]\n",
                 "scene.yaml:2:51: vertex index -1 is out of range (the polyhedron has 4 vertices, "
                 "0 to 3)");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3.5]]}]\n",
                 "scene.yaml:2:51: expected a whole number for 'faces', got 3.5");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], 3]}]\n",
                 "scene.yaml:2:44: expected a list of vertex indices for 'faces', got a number");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2], [0, 1, 3], [0, 3, 2], [1, 2, 3]]}]\n",
                 "scene.yaml:2:11: face 0 has 2 vertices (a face needs at least 3)");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 2], [0, 1, 3], [0, 3, 2], [1, 2, 3]]}]\n",
                 "scene.yaml:2:18: face 0 names a vertex twice");
    expect_error("objects: [{type: polyhedron, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1],\n"
                 "  [0.5, 0.5, -0.2]], faces: [[0, 2, 4, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]}]\n",
                 "scene.yaml:2:31: face 0 is not planar: its vertex 0 is 0.0962 off the face's "
                 "plane (at most 0.001, 0.1% of the face's size, is allowed)");
    expect_error("objects: [{type: polyhedron, vertices: [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 0, 1]],\n"
                 "  faces: [[0, 1, 2], [0, 1, 3], [0, 3, 2], [1, 2, 3]]}]\n",
                 "scene.yaml:2:11: face 0 has no area (its vertices lie on one line)");
    /* A pentagram for a base. */
    expect_error("objects: [{type: polyhedron, vertices: [[0, 1, 0], [-0.951, 0.309, 0],\n"
                 "  [-0.588, -0.809, 0], [0.588, -0.809, 0], [0.951, 0.309, 0], [0, 0, 1]],\n"
                 "  faces: [[0, 2, 4, 1, 3], [0, 1, 5], [1, 2, 5], [2, 3, 5], [3, 4, 5]]}]\n",
                 "scene.yaml:3:11: face 0 crosses itself (a face must be a simple polygon)");
    /* A cube without its top. */
    expect_error("objects: [{type: polyhedron, vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],\n"
                 "  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],\n"
                 "  faces: [[0, 3, 2, 1], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]}]\n",
                 "scene.yaml:3:25: the solid is not closed: the edge from vertex 5 to 4 of face 1 "
                 "belongs to no other face");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 3, 2]]}]\n",
                 "scene.yaml:2:11: faces 0 and 3 both run from vertex 2 to 1: neighbouring faces "
                 "must run along their shared edge in opposite directions (each "
                 "counter-clockwise seen from outside)");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]}]\n",
                 "scene.yaml:2:10: the faces are clockwise seen from outside (the solid is inside "
                 "out): list each face's vertices the other way round");
    expect_error("objects: [{type: polyhedron, " TET_V ",\n"
                 "  faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 2, 1]]}]\n",
                 "scene.yaml:2:11: the solid is not manifold: the edge between vertices 0 and 1 "
                 "belongs to more than two faces (0, 1 and more)");
}

Test(load_geometry_errors, csg)
{
    const char *ball = "{type: sphere, center: [0, 0, 0], radius: 1}";
    char buf[512];
    expect_error("objects: [{type: csg, op: union, objects: [{type: sphere, center: [0, 0, 0], "
                 "radius: 1}]}]\n",
                 "scene.yaml:1:43: a csg needs at least 2 objects (got 1)");
    expect_error("objects: [{type: csg, op: unoin, objects: []}]\n",
                 "scene.yaml:1:27: unknown csg op 'unoin' (did you mean 'union'?)");
    expect_error("objects: [{type: csg, objects: []}]\n", "scene.yaml:1:11: csg needs 'op'");
    expect_error("objects: [{type: csg, op: union}]\n", "scene.yaml:1:11: csg needs 'objects'");
    expect_error("objects: [{type: csg, op: union, objects: {a: 1}}]\n",
                 "scene.yaml:1:43: expected a list for 'objects', got a mapping");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: plane, point: [0, 0, 0], normal: [0, 1, 0]}]}]\n", ball);
    expect_error(buf, "scene.yaml:2:10: a plane cannot be a csg operand: it does not enclose a "
                      "solid (operands are spheres, boxes, capped cylinders and cones, tori, "
                      "polyhedra, meshes and csgs)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: disk, center: [0, 0, 0], normal: [0, 1, 0], radius: 1}]}]\n", ball);
    expect_error(buf, "scene.yaml:2:10: a disk cannot be a csg operand: it does not enclose a "
                      "solid (operands are spheres, boxes, capped cylinders and cones, tori, "
                      "polyhedra, meshes and csgs)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: cone, base: [0, 0, 0], radius: 1, height: 1, capped: false}]}]\n", ball);
    expect_error(buf, "scene.yaml:2:63: an open cone cannot be a csg operand: it does not "
                      "enclose a solid (capped must be true)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: sphere, center: [0, 0, 0], radius: 1, material: nope}]}]\n", ball);
    expect_error(buf, "scene.yaml:2:58: unknown material 'nope' (no materials are defined)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, material: nope, objects: [%s, %s]}]\n",
             ball, ball);
    expect_error(buf, "scene.yaml:1:44: unknown material 'nope' (no materials are defined)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: csg, op: difference, objects: [%s]}]}]\n", ball, ball);
    expect_error(buf, "scene.yaml:2:40: a csg needs at least 2 objects (got 1)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s, 3]}]\n", ball);
    expect_error(buf, "scene.yaml:1:90: expected a mapping for 'objects', got a number");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, radius: 3, objects: [%s, %s]}]\n",
             ball, ball);
    expect_error(buf, "scene.yaml:1:34: unknown key 'radius' in csg (valid: type, op, objects, "
                      "material, transform)");
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: sphere, center: [0, 0, 0], radius: 1, transform: [scale: 0]}]}]\n", ball);
    expect_error(buf, "scene.yaml:2:67: scale must not be 0 (got 0)");
    vfile files[] = {{"tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}, {NULL, NULL}};
    snprintf(buf, sizeof buf, "objects: [{type: csg, op: union, objects: [%s,\n"
             "  {type: mesh, file: tri.obj}]}]\n", ball);
    expect_error_with(buf, files,
                      "scene.yaml:2:22: this mesh cannot be a csg operand: it is not a closed "
                      "surface (3 of its edges do not join exactly two triangles wound the same "
                      "way), so it has no inside");
}

/* More operands than a csg holds, counting nested ones. */
Test(load_geometry_errors, csg_size_is_bounded)
{
    size_t cap = 64 * (CSG_MAX_LEAVES + 2), n = 0;
    char *text = malloc(cap);
    n += (size_t)snprintf(text + n, cap - n, "objects:\n  - type: csg\n    op: union\n    objects:\n");
    for (int i = 0; i <= CSG_MAX_LEAVES; i++)
        n += (size_t)snprintf(text + n, cap - n,
                              "      - {type: sphere, center: [%d, 0, 0], radius: 1}\n", i);
    char want[128];
    snprintf(want, sizeof want, "scene.yaml:%d:9: a csg holds at most %d solids, counting those "
             "of the csgs inside it", 5 + CSG_MAX_LEAVES, CSG_MAX_LEAVES);
    expect_error(text, want);
    free(text);
}

/* Eight rays at once (mesh_intersect8, scene_intersect8) against one at a
 * time (mesh_intersect, scene_intersect): the same hits to the bit, on
 * every SIMD path this CPU has, for coherent packets (which the eight-wide
 * paths walk together), incoherent ones (which go one ray at a time),
 * partly idle ones, and rays along the edges and through the corners of a
 * grid of triangles, where several triangles are hit at the same
 * distance. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "accel/isa.h"
#include "core/rng.h"
#include "geom/csg.h"
#include "geom/mesh.h"
#include "geom/mesh_trace.h"
#include "geom/shape.h"
#include "scene/scene.h"
#include "scene/scene_packet8.h"

static float uniform(rng *g, float lo, float hi) { return lo + (hi - lo) * rng_float(g); }

static mesh *mesh_take(vec3 *pos, int nverts, uint32_t (*tri)[3], int ntris)
{
    mesh *m = calloc(1, sizeof *m);
    cr_assert_not_null(m);
    m->pos = pos;
    m->nverts = nverts;
    m->tri = tri;
    m->ntris = ntris;
    glint_error err = {0};
    cr_assert_eq(mesh_init(m, "packet", 0, NULL, &err), GLINT_OK, "%s", err.msg);
    return m;
}

static void mesh_drop(mesh *m)
{
    mesh_free(m);
    free(m);
}

/* n x n unit squares in the plane z = 0, each split into two triangles. */
static mesh *grid_mesh(int n)
{
    int nv = (n + 1) * (n + 1);
    vec3 *pos = malloc(sizeof *pos * (size_t)nv);
    uint32_t(*tri)[3] = malloc(sizeof *tri * (size_t)(2 * n * n));
    cr_assert(pos && tri);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++)
            pos[j * (n + 1) + i] = v3((float)i, (float)j, 0.0f);
    int t = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 1, d = c + 1;
            tri[t][0] = a, tri[t][1] = b, tri[t][2] = d, t++;
            tri[t][0] = a, tri[t][1] = d, tri[t][2] = c, t++;
        }
    return mesh_take(pos, nv, tri, t);
}

/* n random triangles of size about 3 in a cube of side 20. */
static mesh *soup_mesh(int n, uint64_t seed)
{
    rng g = rng_seed(seed, 1);
    vec3 *pos = malloc(sizeof *pos * (size_t)(3 * n));
    uint32_t(*tri)[3] = malloc(sizeof *tri * (size_t)n);
    cr_assert(pos && tri);
    for (int i = 0; i < n; i++) {
        vec3 c = v3(uniform(&g, -10, 10), uniform(&g, -10, 10), uniform(&g, -10, 10));
        for (int k = 0; k < 3; k++) {
            pos[3 * i + k] = v3_add(c, v3(uniform(&g, -1.5f, 1.5f), uniform(&g, -1.5f, 1.5f),
                                          uniform(&g, -1.5f, 1.5f)));
            tri[i][k] = (uint32_t)(3 * i + k);
        }
    }
    return mesh_take(pos, 3 * n, tri, n);
}

static void put(ray8 *p, int k, vec3 o, vec3 d, float tmin, float tmax)
{
    ray8_put(p, k, &(ray){.o = o, .d = d, .tmin = tmin, .tmax = tmax, .time = 0.0f});
}

/* Packet i of a few kinds: a pinhole camera's rays through eight pixels
 * in a row, sometimes with a far limit; rays straight down onto the grid
 * through its corners and along its edges; random rays. */
static ray8 packet_of(rng *g, int i, vec3 eye)
{
    ray8 p;
    int kind = i % 4;
    float y = uniform(g, -0.5f, 0.5f), x0 = uniform(g, -0.5f, 0.4f);
    float tmax = i % 3 == 0 ? uniform(g, 5.0f, 40.0f) : INFINITY;
    for (int k = 0; k < 8; k++) {
        vec3 o = eye, d;
        if (kind == 0 || kind == 1) {
            d = v3(x0 + 0.0125f * (float)k, y, -1.0f);
        } else if (kind == 2) { /* the half-unit lattice: corners, edges, centres */
            o = v3(0.5f * (float)(i % 31) + 0.5f * (float)(k % 2), 0.5f * (float)((i / 31) % 31),
                   10.0f);
            d = v3(0.0f, 0.0f, -1.0f);
        } else {
            o = v3(uniform(g, -15, 15), uniform(g, -15, 15), uniform(g, -15, 15));
            d = v3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
        }
        put(&p, k, o, d, i % 5 == 0 ? 0.5f : 0.0f, tmax);
    }
    return p;
}

static void expect_same_hit(const shape_hit *a, const shape_hit *b, int i, int k)
{
    cr_assert(a->t == b->t && a->part == b->part && a->b1 == b->b1 && a->b2 == b->b2,
              "packet %d ray %d: t %.9g tri %d (%.9g %.9g) against one ray's %.9g tri %d "
              "(%.9g %.9g)",
              i, k, a->t, a->part, a->b1, a->b2, b->t, b->part, b->b1, b->b2);
}

/* mesh_intersect8 against mesh_intersect for every ray of n packets; returns
 * how many of the packets the eight-wide kernel took whole. */
static int check_mesh(const mesh *m, vec3 eye, int n, uint64_t seed)
{
    rng g = rng_seed(seed, 3);
    int whole = 0;
    for (int i = 0; i < n; i++) {
        ray8 p = packet_of(&g, i, eye);
        int active = i % 7 == 0 ? 0x5b : 0xff;
        shape_hit h8[8], h1;
        int found = mesh_intersect8(m, &p, active, h8);
#if defined(GLINT_WIDE_KERNELS)
        shape_hit spare[8];
        if (m->bvh.isa == ACCEL_AVX512)
            whole += mesh_intersect8_avx512(m, &p, active, spare) >= 0;
        if (m->bvh.isa == ACCEL_AVX2)
            whole += mesh_intersect8_avx2(m, &p, active, spare) >= 0;
#endif
        for (int k = 0; k < 8; k++) {
            ray r = ray8_get(&p, k);
            bool hit = (active >> k & 1) && mesh_intersect(m, &r, &h1);
            cr_assert_eq(found >> k & 1, hit, "packet %d ray %d: hit %d against %d", i, k,
                         found >> k & 1, hit);
            if (hit)
                expect_same_hit(&h8[k], &h1, i, k);
        }
    }
    return whole;
}

Test(packet, mesh_hits_match_one_ray_at_a_time_on_every_path)
{
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        mesh *grid = grid_mesh(16), *soup = soup_mesh(3000, 11);
        int whole = check_mesh(grid, v3(8.0f, 8.0f, 10.0f), 4000, 5) +
                    check_mesh(soup, v3(0.3f, -0.2f, 25.0f), 4000, 6);
        if (path >= ACCEL_AVX2) /* the camera and lattice packets, at least */
            cr_assert_gt(whole, 3500, "%s: only %d packets walked together",
                         accel_isa_name((accel_isa)path), whole);
        mesh_drop(grid);
        mesh_drop(soup);
    }
    accel_isa_force(ACCEL_AUTO);
}

/* Two triangles in the same place: the lower index wins, walked one ray
 * at a time or eight together, whichever the walk meets first. */
Test(packet, equal_distances_go_to_the_lower_triangle)
{
    enum { COPIES = 40 };
    vec3 *pos = malloc(sizeof *pos * 3 * COPIES);
    uint32_t(*tri)[3] = malloc(sizeof *tri * COPIES);
    cr_assert(pos && tri);
    for (int i = 0; i < COPIES; i++) { /* twenty places, each twice */
        vec3 c = v3((float)(i % 20) * 3.0f, 0.0f, 0.0f);
        pos[3 * i] = v3_add(c, v3(-1, -1, 0));
        pos[3 * i + 1] = v3_add(c, v3(1, -1, 0));
        pos[3 * i + 2] = v3_add(c, v3(0, 1, 0));
        for (int k = 0; k < 3; k++)
            tri[i][k] = (uint32_t)(3 * i + k);
    }
    mesh *m = mesh_take(pos, 3 * COPIES, tri, COPIES);
    for (int place = 0; place < 20; place++) {
        int lower = -1; /* of the two triangles now at this place */
        for (int t = 0; t < m->ntris && lower < 0; t++)
            if ((int)(m->tri[t][0] / 3) % 20 == place)
                lower = t;
        ray8 p;
        for (int k = 0; k < 8; k++)
            put(&p, k, v3((float)place * 3.0f + 0.01f * (float)k, 0.0f, 5.0f), v3(0, 0, -1), 0.0f,
                INFINITY);
        shape_hit h8[8], h1;
        cr_assert_eq(mesh_intersect8(m, &p, 0xff, h8), 0xff);
        for (int k = 0; k < 8; k++) {
            ray r = ray8_get(&p, k);
            cr_assert(mesh_intersect(m, &r, &h1));
            cr_assert_eq(h1.part, lower, "place %d: triangle %d, not %d", place, h1.part, lower);
            expect_same_hit(&h8[k], &h1, place, k);
        }
    }
    mesh_drop(m);
}

/* Packet i, p, of which the rays of active ask, against scene s: each
 * ray's hit is scene_intersect's to the bit. Returns how many hits were
 * of kind. */
static int same_packet_hits(scene *s, const ray8 *p, int active, int i, shape_kind kind)
{
    int of_kind = 0;
    scene_hit h8[8], h1;
    int found = scene_intersect8(s, p, active, h8);
    for (int k = 0; k < 8; k++) {
        ray r = ray8_get(p, k);
        bool hit = (active >> k & 1) && scene_intersect(s, &r, &h1);
        cr_assert_eq(found >> k & 1, hit, "packet %d ray %d", i, k);
        if (!hit)
            continue;
        cr_assert_eq(h8[k].object, h1.object, "packet %d ray %d", i, k);
        expect_same_hit(&h8[k].h, &h1.h, i, k);
        of_kind += s->objects[h1.object].shape.kind == kind;
    }
    return of_kind;
}

/* A ground plane and copies of a turned mesh with a sphere beside each:
 * one copy makes a flat scene, three a tree of one node, twelve a deeper
 * tree. */
static scene *packet_scene(int copies)
{
    scene *s = scene_new();
    cr_assert_not_null(s);
    material mt = material_default();
    int mat = scene_add_material(s, &mt);
    shape ground = shape_plane(v3(0, -12, 0), v3(0, 1, 0));
    cr_assert_geq(scene_add_object(s, &ground, mat, -1), 0);
    for (int c = 0; c < copies; c++) {
        mesh *m = soup_mesh(500, 20u + (uint64_t)c);
        cr_assert_geq(scene_add_mesh(s, m), 0);
        xform r = xform_rotate(v3(1.0f, 2.0f, 0.5f), 25.0f + 10.0f * (float)c);
        xform t = xform_translate(v3(30.0f * (float)c, 0.0f, 0.0f));
        xform rt = xform_then(&r, &t);
        shape sh = shape_mesh(m);
        cr_assert_geq(scene_add_object(s, &sh, mat, scene_add_xform(s, &rt)), 0);
        shape ball = shape_sphere(v3(30.0f * (float)c + 3.0f, 2.0f, 4.0f), 3.0f);
        cr_assert_geq(scene_add_object(s, &ball, mat, -1), 0);
    }
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

Test(packet, scene_hits_match_one_ray_at_a_time_on_every_path)
{
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        static const int sizes[] = {1, 3, 12};
        for (int z = 0; z < 3; z++) {
            int copies = sizes[z];
            scene *s = packet_scene(copies);
            cr_assert_eq(s->flat, copies == 1);
            cr_assert_eq(!s->flat && s->bvh.nnodes == 1, copies == 3);
            cr_assert_eq(scene_packets_pay(s), path >= ACCEL_AVX2);
            rng g = rng_seed(9, 4);
            for (int i = 0; i < 3000; i++) {
                ray8 p = packet_of(&g, i, v3(0.3f, -0.2f, 25.0f));
                same_packet_hits(s, &p, i % 7 == 0 ? 0xe6 : 0xff, i, SHAPE_MESH);
            }
            scene_free(s);
        }
    }
    accel_isa_force(ACCEL_AUTO);
}

/* packet_scene with shadow casters that let light through, and boxes and
 * a cylinder that do not, each copy's: a glass ball that absorbs and
 * bends, a tinted pane, a box straight and one turned. */
static void add_casters(scene *s, int copies)
{
    material glass = material_default(), pane = material_default(), solid = material_default();
    glass.transmit = 0.8f, glass.ior = 1.5f, glass.absorption = v3(0.05f, 0.1f, 0.2f);
    pane.transmit = 0.6f, pane.tint = v3(1.0f, 0.6f, 0.3f);
    /* highlights: a whole shininess, one powf takes, and one of 1 */
    glass.specular = 1.0f, glass.shininess = 200.0f;
    pane.specular = 0.8f, pane.shininess = 37.5f;
    solid.specular = 0.5f, solid.shininess = 1.0f;
    int mg = scene_add_material(s, &glass), mp = scene_add_material(s, &pane);
    int ms = scene_add_material(s, &solid);
    xform turn = xform_rotate(v3(0, 1, 0), 30.0f);
    int xt = scene_add_xform(s, &turn);
    for (int c = 0; c < copies; c++) {
        float x = 30.0f * (float)c;
        shape ball = shape_sphere(v3(x - 4.0f, 4.0f, 2.0f), 2.5f);
        shape quad = shape_quad(v3(x - 6.0f, -3.0f, 6.0f), v3(7, 0, 0), v3(0, 6, 1));
        shape box = shape_box(v3(x + 5.0f, -9.0f, -2.0f), v3(x + 8.0f, -5.0f, 1.0f));
        shape turned = shape_box(v3(x - 2.0f, -11.0f, 5.0f), v3(x, -8.0f, 7.0f));
        shape can = shape_cylinder(v3(x + 9.0f, -12.0f, 6.0f), 1.5f, 5.0f, true);
        cr_assert_geq(scene_add_object(s, &ball, mg, -1), 0);
        cr_assert_geq(scene_add_object(s, &quad, mp, -1), 0);
        cr_assert_geq(scene_add_object(s, &box, ms, -1), 0);
        cr_assert_geq(scene_add_object(s, &turned, ms, xt), 0);
        cr_assert_geq(scene_add_object(s, &can, ms, -1), 0);
    }
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
}

/* Eight shadow rays from points scattered round the copies' objects
 * (neighbours, for most packets) towards a light at l. */
static ray8 shadow_packet(rng *g, int i, int copies, vec3 l)
{
    ray8 p;
    float spread = i % 3 == 0 ? 12.0f : 0.6f;
    vec3 c = v3(uniform(g, -12.0f, 30.0f * (float)(copies - 1) + 12.0f), uniform(g, -12, 8),
                uniform(g, -8, 10));
    for (int k = 0; k < 8; k++) {
        vec3 o = v3_add(c, v3(uniform(g, -spread, spread), uniform(g, -spread, spread),
                              uniform(g, -spread, spread)));
        put(&p, k, o, v3_sub(l, o), 1e-3f, 1.0f);
    }
    return p;
}

/* scene_shadow_unblocked8's crossings of the rays of crosses are those
 * scene_shadow finds for each alone, to the bit and in the same order. */
static int same_crossings(const scene *s, const ray8 *p, int crosses, int i)
{
    scene_crossings got[8];
    int deep = scene_shadow_unblocked8(s, p, crosses, got), spheres = 0;
    for (int m = crosses; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray r = ray8_get(p, k);
        scene_crossings want;
        cr_assert_eq(deep >> k & 1, scene_shadow(s, &r, &want), "packet %d ray %d", i, k);
        if (deep >> k & 1)
            continue;
        cr_assert_eq(got[k].n, want.n, "packet %d ray %d", i, k);
        for (int j = 0; j < want.n; j++) {
            cr_assert_eq(got[k].hit[j].object, want.hit[j].object, "packet %d ray %d", i, k);
            const shape_hit *a = &got[k].hit[j].h, *b = &want.hit[j].h;
            cr_assert(memcmp(&a->t, &b->t, sizeof a->t) == 0 && a->part == b->part,
                      "packet %d ray %d crossing %d: t %a against %a", i, k, j, (double)a->t,
                      (double)b->t);
            spheres += s->objects[want.hit[j].object].shape.kind == SHAPE_SPHERE;
        }
    }
    return spheres;
}

/* Shadow rays that graze a glass sphere (both roots the same float: one
 * crossing, the second sought beyond it), cross it, start inside it or
 * stop inside it, eight at a time as one at a time. */
Test(packet, sphere_crossings_match_at_the_edges)
{
    if (accel_isa_force(ACCEL_AVX2) != ACCEL_AVX2)
        return;
    scene *s = scene_new();
    cr_assert_not_null(s);
    material glass = material_default();
    glass.transmit = 0.8f;
    int mat = scene_add_material(s, &glass);
    shape ball = shape_sphere(v3s(0.0f), 1.0f);
    cr_assert_geq(scene_add_object(s, &ball, mat, -1), 0);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    ray8 p;
    put(&p, 0, v3(-5, 1, 0), v3(1, 0, 0), 0.0f, 1e3f);  /* tangent: roots 5 and 5 */
    put(&p, 1, v3(-5, 0, 1), v3(10, 0, 0), 0.0f, 1.0f); /* tangent, a segment */
    put(&p, 2, v3(-5, 0.5f, 0), v3(1, 0, 0), 0.0f, 1e3f);
    put(&p, 3, v3(0, 0, 0), v3(0, 3, 0), 0.0f, 1.0f);   /* from inside */
    put(&p, 4, v3(0, -3, 0), v3(0, 3, 0), 0.0f, 1.0f);  /* stops inside */
    put(&p, 5, v3(0, 1, 0), v3(0, 1, 0), 0.0f, 1e3f);   /* from the surface, outwards */
    put(&p, 6, v3(0, 1, 0), v3(0, -1, 0), 0.0f, 1e3f);  /* from the surface, through */
    put(&p, 7, v3(3, 3, 3), v3(1, 1, 1), 0.0f, 1e3f);   /* away */
    int spheres = same_crossings(s, &p, 0xff, 0);
    scene_crossings one;
    ray graze = ray8_get(&p, 0);
    cr_assert(!scene_shadow(s, &graze, &one));
    cr_expect_eq(one.n, 1, "a grazing ray crosses once");
    cr_expect_geq(spheres, 6);
    scene_free(s);
    accel_isa_force(ACCEL_AUTO);
}

/* Shape sh alone in a scene, met by the rays of packet p together on
 * every path that tests it eight at a time: each hit must be the one
 * shape_intersect finds, distance and part to the bit. Returns the rays
 * that hit it, with shape_intersect's hits in one[k]. */
static int alone_in_packets(const shape *sh, const ray8 *p, shape_hit one[8])
{
    int hits = 0;
    for (int k = 0; k < 8; k++) {
        ray r = ray8_get(p, k);
        one[k] = (shape_hit){0};
        hits |= shape_intersect(sh, &r, &one[k]) << k;
    }
    scene *s = scene_new();
    cr_assert_not_null(s);
    material mt = material_default();
    cr_assert_geq(scene_add_object(s, sh, scene_add_material(s, &mt), -1), 0);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    for (int path = ACCEL_AVX2; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene_hit h8[8];
        cr_assert_eq(scene_intersect8(s, p, 0xff, h8), hits, "path %d", path);
        for (int m = hits; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            cr_assert(h8[k].h.t == one[k].t && h8[k].h.part == one[k].part,
                      "path %d ray %d: t %.9g part %d, want t %.9g part %d", path, k,
                      (double)h8[k].h.t, h8[k].h.part, (double)one[k].t, one[k].part);
        }
    }
    accel_isa_force(ACCEL_AUTO);
    scene_free(s);
    return hits;
}

/* A box's hits eight at a time, on every path that tests them so: rays
 * parallel to two slabs (inside one, outside another, on a boundary),
 * through a corner and along an edge (the entry distances of two or three
 * slabs tie; the earlier axis names the face), from inside, and past
 * their entry (tmin beyond it): the distance and face box_intersect
 * finds, to the bit. */
Test(packet, box_hits_match_at_the_edges)
{
    const vec3 lo = v3(-1.0f, -2.0f, -3.0f), hi = v3(2.0f, 1.0f, 0.5f);
    ray8 p;
    put(&p, 0, v3(0.5f, 0.0f, -9.0f), v3(0, 0, 1), 0.0f, INFINITY);     /* enters face 4 */
    put(&p, 1, v3(2.5f, 0.0f, -9.0f), v3(0, 0, 1), 0.0f, INFINITY);     /* outside x: misses */
    put(&p, 2, v3(0.0f, 0.0f, 0.0f), v3(1.0f, 0.5f, 0.25f), 0.0f, 1e3f); /* from inside */
    put(&p, 3, v3(-2.0f, -3.0f, -4.0f), v3(1, 1, 1), 0.0f, 1e3f);      /* a corner: face 0 */
    put(&p, 4, v3(-2.0f, -3.0f, -1.0f), v3(1, 1, 0), 0.0f, 1e3f);      /* an edge: face 0 */
    put(&p, 5, v3(-1.0f, 1.0f, 9.0f), v3(-0.0f, 0, -1), 0.0f, INFINITY); /* on x = lo, y = hi */
    put(&p, 6, v3(5.0f, 4.0f, 4.0f), v3(-1.0f, -1.25f, -1.5f), 0.0f, 1e3f);
    put(&p, 7, v3(0.5f, 0.0f, -9.0f), v3(0, 0, 1), 7.0f, INFINITY);     /* past the entry */
    const int want[8] = {4, -1, 1, 0, 0, 5, -2, 5}; /* -2: whichever box_intersect says */
    shape box = shape_box(lo, hi);
    shape_hit one[8];
    int hits = alone_in_packets(&box, &p, one);
    for (int k = 0; k < 8; k++) {
        cr_assert_eq(hits >> k & 1, want[k] != -1, "ray %d", k);
        cr_assert(want[k] < 0 || one[k].part == want[k], "ray %d: face %d", k, one[k].part);
    }
}

/* A cylinder's hits eight at a time, capped and open, as
 * cylinder_intersect finds them: rays along its axis (no side), across
 * it (no caps), grazing its side, through a cap's rim, from inside, past
 * the first of their hits, and up into the lower cap. */
Test(packet, cylinder_hits_match_at_the_edges)
{
    const vec3 base = v3(1.0f, -2.0f, 0.5f);
    ray8 p;
    put(&p, 0, v3(1.5f, 9.0f, 0.5f), v3(0, -1, 0), 0.0f, INFINITY);   /* down the axis: cap 2 */
    put(&p, 1, v3(-9.0f, -2.0f, 0.5f), v3(1, 0, 0), 0.0f, INFINITY);  /* across its foot */
    put(&p, 2, v3(-9.0f, 0.0f, 2.5f), v3(1, 0, 0), 0.0f, INFINITY);   /* grazing: one root */
    put(&p, 3, v3(3.0f, 5.0f, 0.5f), v3(0, -1, 0), 0.0f, INFINITY);   /* the rim of cap 2 */
    put(&p, 4, v3(1.0f, -1.0f, 0.5f), v3(0.3f, 1.0f, -0.2f), 0.0f, 1e3f); /* from inside */
    put(&p, 5, v3(1.0f, -9.0f, 0.5f), v3(0.01f, 1, 0), 8.0f, INFINITY); /* past cap 1 */
    put(&p, 6, v3(9.0f, 9.0f, 9.0f), v3(1, 1, 1), 0.0f, 1e3f);        /* away */
    put(&p, 7, v3(2.0f, -9.0f, 0.0f), v3(-0.1f, 1.0f, 0.2f), 0.0f, 1e3f); /* up: cap 1 */
    for (int capped = 0; capped < 2; capped++) {
        shape cyl = shape_cylinder(base, 2.0f, 3.0f, capped);
        shape_hit one[8];
        int hits = alone_in_packets(&cyl, &p, one), parts[3] = {0, 0, 0};
        for (int m = hits; m; m &= m - 1)
            parts[one[__builtin_ctz((unsigned)m)].part]++;
        /* the side, and both caps when there are caps */
        cr_assert(parts[0] > 0 && (parts[1] > 0) == capped && (parts[2] > 0) == capped,
                  "capped %d: parts %d %d %d", capped, parts[0], parts[1], parts[2]);
    }
}

/* scene_shadow8 tells each ray what scene_shadow tells it alone: blocked,
 * or not and crossing a transmitting object (or perhaps crossing one that
 * is not tested eight at a time), or clear; in a flat scene, a tree of one
 * node and a deeper tree, on every path that walks packets. The crossings
 * of those that may cross are found eight at a time, and are those that
 * scene_shadow finds. */
Test(packet, shadow_rays_match_one_ray_at_a_time)
{
    int walked = 0, counts[3] = {0, 0, 0}, spheres = 0;
    for (int path = ACCEL_AVX2; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        static const int sizes[] = {1, 3, 12};
        for (int z = 0; z < 3; z++) {
            scene *s = packet_scene(sizes[z]);
            add_casters(s, sizes[z]);
            rng g = rng_seed(31, 2);
            for (int i = 0; i < 4000; i++) {
                ray8 p = shadow_packet(&g, i, sizes[z], v3(10, 30, 40));
                int active = i % 5 == 0 ? 0x7b : 0xff, blocked, crosses;
                if (!scene_shadow8(s, &p, active, &blocked, &crosses))
                    continue;
                walked++;
                cr_assert_eq((blocked | crosses) & ~active, 0);
                for (int m = active; m; m &= m - 1) {
                    int k = __builtin_ctz((unsigned)m);
                    ray r = ray8_get(&p, k);
                    scene_crossings cross;
                    bool b = scene_shadow(s, &r, &cross);
                    int kind = b ? 0 : cross.n > 0 ? 1 : 2;
                    int got = blocked >> k & 1 ? 0 : crosses >> k & 1 ? 1 : 2;
                    /* a clear ray may be told to look for crossings (of a
                     * shape not tested eight at a time): it finds none */
                    cr_assert(got == kind || (got == 1 && kind == 2),
                              "%d copies, packet %d ray %d: %d for %d", sizes[z], i, k, got, kind);
                    counts[kind]++;
                }
                spheres += same_crossings(s, &p, crosses, i);
            }
            scene_free(s);
        }
    }
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() < ACCEL_AVX2)
        return;
    cr_assert_gt(walked, 1000);
    for (int kind = 0; kind < 3; kind++) /* blocked, crossing and clear rays all met */
        cr_assert_gt(counts[kind], 500, "kind %d: %d rays", kind, counts[kind]);
    cr_assert_gt(spheres, 500, "sphere crossings: %d", spheres);
}

/* An empty scene with the default material, *mat. */
static scene *bare(int *mat)
{
    scene *s = scene_new();
    cr_assert_not_null(s);
    material mt = material_default();
    *mat = scene_add_material(s, &mt);
    return s;
}

/* A scene of a ground plane at y = -2, of material *mat (the default). */
static scene *grounded(int *mat)
{
    scene *s = bare(mat);
    shape ground = shape_plane(v3(0, -2, 0), v3(0, 1, 0));
    cr_assert_geq(scene_add_object(s, &ground, *mat, -1), 0);
    return s;
}

/* A ground plane and a grid of turned tori (bench/tori.awk's row 8 in
 * small), some untransformed and one far larger, that camera packets meet
 * in many tori each, tested eight at a time by torus8_hit. */
static scene *torus_scene(void)
{
    int mat;
    scene *s = grounded(&mat);
    rng g = rng_seed(31, 2);
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 12; j++) {
            vec3 at = v3(-6.0f + (float)i, -6.0f + (float)j, -2.0f * (float)((i + j) % 3));
            if ((i + j) % 5 == 0) {
                shape t = shape_torus(at, 0.4f, 0.12f);
                cr_assert_geq(scene_add_object(s, &t, mat, -1), 0);
                continue;
            }
            xform rx = xform_rotate(v3(1, 0, 0), uniform(&g, 0, 180));
            xform ry = xform_rotate(v3(0, 1, 0), uniform(&g, 0, 360));
            xform tr = xform_translate(at), a = xform_then(&rx, &ry), b = xform_then(&a, &tr);
            shape t = shape_torus(v3s(0.0f), 0.32f, 0.1f);
            cr_assert_geq(scene_add_object(s, &t, mat, scene_add_xform(s, &b)), 0);
        }
    shape big = shape_torus(v3(0, 0, -8), 5.0f, 1.5f);
    cr_assert_geq(scene_add_object(s, &big, mat, -1), 0);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* Packets of camera rays from eye (half of them narrowed, so that many
 * rays meet each object), partly idle, against scene s: each ray's hit
 * is scene_intersect's to the bit. Returns how many hits were of kind. */
static int same_hits(scene *s, vec3 eye, int packets, shape_kind kind)
{
    int of_kind = 0;
    rng g = rng_seed(5, 8);
    for (int i = 0; i < packets; i++) {
        ray8 p = packet_of(&g, i, eye);
        for (int k = 0; k < 8 && i % 4 < 2; k++) {
            p.dx[k] = 0.1f * p.dx[k];
            p.dy[k] = 0.1f * p.dy[k];
        }
        of_kind += same_packet_hits(s, &p, i % 7 == 0 ? 0x5b : 0xff, i, kind);
    }
    return of_kind;
}

/* Camera packets into a grid of objects (made by make) on every path:
 * each ray's hit is scene_intersect's to the bit; more than 10,000 of
 * them on objects of the kind the grid is made of. */
static void same_hits_on_every_path(scene *(*make)(void), shape_kind kind)
{
    int many = 0;
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = make();
        many += same_hits(s, v3(0.3f, -0.2f, 9.0f), 6000, kind);
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
    cr_assert_gt(many, 10000);
}

/* The torus grid (torus8_hit). */
Test(packet, torus_hits_match_one_ray_at_a_time_on_every_path)
{
    same_hits_on_every_path(torus_scene, SHAPE_TORUS);
}

/* Shadow rays from behind a grid of objects (made by make) to a light in
 * front of it, in packets (the eight-lane test for three or more):
 * blocked as scene_shadow finds each ray alone, on every path. The
 * packets' centres lie within reach of the axis in x and y; each answer
 * must come up more than `each` times. */
static void same_shadows(scene *(*make)(void), uint64_t seed, uint64_t stream, float reach,
                         int each)
{
    int counts[2] = {0, 0}, walked = 0;
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = make();
        rng g = rng_seed(seed, stream);
        for (int i = 0; i < 3000; i++) {
            float spread = i % 3 == 0 ? 4.0f : 0.4f;
            vec3 c = v3(uniform(&g, -reach, reach), uniform(&g, -reach, reach),
                        uniform(&g, -10, -5));
            ray8 p;
            for (int k = 0; k < 8; k++) {
                vec3 o = v3_add(c, v3(uniform(&g, -spread, spread), uniform(&g, -spread, spread),
                                      uniform(&g, -spread, spread)));
                put(&p, k, o, v3_sub(v3(0.3f, -0.2f, 9.0f), o), 1e-3f, 1.0f);
            }
            int active = i % 5 == 0 ? 0x7b : 0xff, blocked = 0, crosses = 0;
            if (!scene_shadow8(s, &p, active, &blocked, &crosses))
                continue;
            walked++;
            cr_assert_eq(crosses, 0);
            for (int m = active; m; m &= m - 1) {
                int k = __builtin_ctz((unsigned)m);
                ray r = ray8_get(&p, k);
                scene_crossings cross;
                bool b = scene_shadow(s, &r, &cross);
                cr_assert_eq(blocked >> k & 1, b, "packet %d ray %d", i, k);
                counts[b]++;
            }
        }
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() < ACCEL_AVX2)
        return;
    cr_assert_gt(walked, 2000, "packets: %d", walked);
    cr_assert_gt(counts[0], each, "clear: %d", counts[0]);
    cr_assert_gt(counts[1], each, "blocked: %d", counts[1]);
}

/* The torus grid's shadows (torus8_occluded). */
Test(packet, torus_shadows_match_one_ray_at_a_time_on_every_path)
{
    same_shadows(torus_scene, 3, 9, 7.0f, 5000);
}

/* A grid of csg objects over a plane (bench/tori.awk's row 8 in small):
 * (box & sphere) - cylinder, shifted by the object's transform, some
 * turned too, some with a turned leaf, and every third with a torus for
 * its hole (asked ray by ray inside csg8_hit). */
static scene *csg_scene(void)
{
    int mat;
    scene *s = grounded(&mat);
    rng g = rng_seed(17, 4);
    for (int i = 0; i < 10; i++)
        for (int j = 0; j < 10; j++) {
            csg *c = calloc(1, sizeof *c);
            cr_assert_not_null(c);
            shape box = shape_box(v3s(-0.4f), v3s(0.4f)), ball = shape_sphere(v3s(0.0f), 0.54f);
            shape hole = (i + j) % 3 == 0 ? shape_torus(v3(0, 0.4f, 0), 0.3f, 0.12f)
                                          : shape_cylinder(v3(0, -1, 0), 0.2f, 2.0f, true);
            xform tilt = xform_rotate(v3(1, 0, 0), uniform(&g, 0, 90));
            int32_t both[2] = {csg_add_leaf(c, &box, NULL, mat),
                               csg_add_leaf(c, &ball, (i + j) % 4 == 1 ? &tilt : NULL, mat)};
            int32_t ops[2] = {csg_add_node(c, CSG_INTERSECTION, both, 2),
                              csg_add_leaf(c, &hole, (i + j) % 5 == 2 ? &tilt : NULL, mat)};
            csg_add_node(c, CSG_DIFFERENCE, ops, 2);
            csg_finish(c);
            cr_assert_geq(scene_add_csg(s, c), 0);
            vec3 at = v3(-5.0f + (float)i, -5.0f + (float)j, -2.0f * (float)((i + j) % 3));
            xform ry = xform_rotate(v3(0, 1, 0), uniform(&g, 0, 360)), tr = xform_translate(at);
            xform x = (i + j) % 2 ? xform_then(&ry, &tr) : tr;
            shape sh = shape_csg(c);
            cr_assert_geq(scene_add_object(s, &sh, -1, scene_add_xform(s, &x)), 0);
        }
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* Camera packets into the csg grid (csg8_hit for three or more rays):
 * each ray's hit is scene_intersect's to the bit, on every path. */
Test(packet, csg_hits_match_one_ray_at_a_time_on_every_path)
{
    same_hits_on_every_path(csg_scene, SHAPE_CSG);
}

/* The csg grid's shadows (csg8_occluded). */
Test(packet, csg_shadows_match_one_ray_at_a_time_on_every_path)
{
    same_shadows(csg_scene, 5, 1, 6.0f, 3000);
}

/* Spheres, boxes, quads and cylinders (open and capped), turned,
 * stretched and sheared (tested eight at a time in their own space) and
 * some as they are, over a plane. */
static scene *turned_scene(void)
{
    int mat;
    scene *s = grounded(&mat);
    rng g = rng_seed(7, 3);
    for (int i = 0; i < 10; i++)
        for (int j = 0; j < 10; j++) {
            vec3 at = v3(-5.0f + (float)i, -5.0f + (float)j, -2.0f * (float)((i + j) % 3));
            int kind = (i + 2 * j) % 4;
            vec3 c = (i + j) % 4 == 0 ? at : v3s(0.0f); /* as it is, moved by its coordinates */
            shape sh = kind == 0   ? shape_sphere(c, 0.35f)
                       : kind == 1 ? shape_box(v3_add(c, v3(-0.3f, -0.2f, -0.25f)),
                                               v3_add(c, v3(0.3f, 0.2f, 0.25f)))
                       : kind == 2 ? shape_quad(v3_add(c, v3(-0.4f, -0.4f, 0)), v3(0.8f, 0, 0),
                                                v3(0, 0.8f, 0))
                                   : shape_cylinder(v3_add(c, v3(0, -0.3f, 0)), 0.3f, 0.6f, j % 2);
            if ((i + j) % 4 == 0) {
                cr_assert_geq(scene_add_object(s, &sh, mat, -1), 0);
                continue;
            }
            xform sc = xform_scale(v3(uniform(&g, 0.6f, 1.4f), 1.0f, uniform(&g, 0.6f, 1.4f)));
            xform sk = xform_shear(uniform(&g, -0.4f, 0.4f), 0, 0, uniform(&g, -0.4f, 0.4f), 0, 0);
            xform ry = xform_rotate(v3(0.3f, 1, 0.2f), uniform(&g, 0, 360));
            xform tr = xform_translate(at);
            xform a = xform_then(&sc, &sk), b = xform_then(&a, &ry), all = xform_then(&b, &tr);
            cr_assert_geq(scene_add_object(s, &sh, mat, scene_add_xform(s, &all)), 0);
        }
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

Test(packet, turned_shapes_match_one_ray_at_a_time_on_every_path)
{
    int boxes = 0, cylinders = 0;
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = turned_scene();
        boxes += same_hits(s, v3(0.3f, -0.2f, 9.0f), 4000, SHAPE_BOX);
        cylinders += same_hits(s, v3(-0.4f, 0.3f, 9.0f), 4000, SHAPE_CYLINDER);
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
    cr_assert(boxes > 200 && cylinders > 2000, "hits: %d on boxes, %d on cylinders", boxes,
              cylinders);
}

/* packet_scene with its casters, lights of every kind and a camera
 * looking at it, to render. */
static scene *lit_packet_scene(int copies)
{
    scene *s = packet_scene(copies);
    add_casters(s, copies);
    light l = light_point(v3(10, 30, 40), v3s(0.9f), v3(1, 0, 0));
    light near = light_point(v3(-15, 10, 30), v3s(0.5f), v3(0.5f, 0.02f, 0.001f)); /* fading */
    light spot = light_spot(v3(-10, 25, 30), v3s(0.0f), 10.0f, 25.0f, v3s(0.6f), v3(1, 0, 0));
    light sun = light_directional(v3(0.3f, -1.0f, -0.4f), v3s(0.3f));
    light area = light_area(v3(5, 20, 20), v3(4, 0, 0), v3(0, 0, 4), 2, v3s(0.4f), v3(1, 0, 0));
    cr_assert_geq(scene_add_light(s, &l), 0);
    cr_assert_geq(scene_add_light(s, &near), 0);
    cr_assert_geq(scene_add_light(s, &spot), 0);
    cr_assert_geq(scene_add_light(s, &sun), 0);
    cr_assert_geq(scene_add_light(s, &area), 0);
    camera c = {.eye = v3(0.3f, -0.2f, 25.0f), .target = v3s(0.0f), .up = v3(0, 1, 0),
                .hfov = 60.0f, .projection = CAMERA_PERSPECTIVE};
    scene_set_camera(s, &c);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* The renderer traces camera rays eight at a time where scene_packets_pay
 * says so (a flat scene or a tree of one node holding a mesh, on the
 * eight-wide paths), and their first hits' shadow rays likewise, and one
 * at a time elsewhere: the films are the same bytes on every path, alpha
 * included, with lights of every kind and objects that let light
 * through. */
static void same_film_on_every_path(int copies)
{
    enum { W = 61, H = 37 }; /* rows that do not fill the last packet */
    glint_film first = {0};
    int packed = 0;
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = lit_packet_scene(copies);
        glint_error err = {0};
        packed += scene_packets_pay(s);
        glint_settings st;
        glint_scene_settings(s, &st, NULL);
        st.width = W, st.height = H, st.samples = 4, st.threads = 2, st.alpha = true;
        glint_film film = {0};
        cr_assert_eq(glint_render(s, &st, NULL, &film, NULL, &err), GLINT_OK, "%s", err.msg);
        cr_assert_not_null(film.alpha);
        if (!first.rgb) {
            first = film;
        } else {
            cr_expect_eq(memcmp(first.rgb, film.rgb, sizeof(float) * W * H * 3), 0,
                         "%d copies: %s", copies, accel_isa_name((accel_isa)path));
            cr_expect_eq(memcmp(first.alpha, film.alpha, sizeof(float) * W * H), 0,
                         "%d copies: %s", copies, accel_isa_name((accel_isa)path));
            glint_film_free(&film);
        }
        scene_free(s);
    }
    glint_film_free(&first);
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert_gt(packed, 0);
}

Test(packet, renders_are_byte_identical_with_and_without_packets)
{
    same_film_on_every_path(1); /* flat */
    same_film_on_every_path(3); /* a tree of one node */
}

/* A quad, and a mesh with a triangle in the quad's plane (and one above
 * it, so that rays from above enter the mesh's box first): rays straight
 * down hit both at the same distance. The lower object index wins, in a
 * one-ray walk that meets the mesh first and in a packet alike. */
Test(packet, equal_distances_go_to_the_lower_object)
{
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        int mat;
        scene *s = bare(&mat);
        xform id = xform_translate(v3s(0.0f)); /* transformed objects get leaves of their own */
        int x = scene_add_xform(s, &id);
        shape quad = shape_quad(v3(-2, -2, 0), v3(4, 0, 0), v3(0, 4, 0));
        cr_assert_eq(scene_add_object(s, &quad, mat, x), 0);
        vec3 *pos = malloc(sizeof *pos * 6);
        uint32_t(*tri)[3] = malloc(sizeof *tri * 2);
        cr_assert(pos && tri);
        pos[0] = v3(-4, -4, 0), pos[1] = v3(4, -4, 0), pos[2] = v3(0, 4, 0);
        pos[3] = v3(-4, -4, 5), pos[4] = v3(4, -4, 5), pos[5] = v3(0, 4, 5);
        for (int k = 0; k < 3; k++)
            tri[0][k] = (uint32_t)k, tri[1][k] = (uint32_t)(3 + k);
        pos[3].x = 20.0f, pos[4].x = 28.0f, pos[5].x = 24.0f; /* the upper one off to the side */
        mesh *m = mesh_take(pos, 6, tri, 2);
        cr_assert_geq(scene_add_mesh(s, m), 0);
        shape sh = shape_mesh(m);
        cr_assert_eq(scene_add_object(s, &sh, mat, x), 1);
        for (int k = 0; k < 3; k++) {
            shape ball = shape_sphere(v3(-30.0f - 5.0f * (float)k, 0, 0), 1.0f);
            cr_assert_geq(scene_add_object(s, &ball, mat, x), 0);
        }
        glint_error err = {0};
        cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
        if (s->bvh.width == 8) /* four-wide paths take two nodes for five leaves */
            cr_assert(!s->flat && s->bvh.nnodes == 1);
        ray8 p;
        for (int k = 0; k < 8; k++)
            put(&p, k, v3(-1.5f + 0.375f * (float)k, 0.25f * (float)(k % 3), 10.0f), v3(0, 0, -1),
                0.0f, INFINITY);
        scene_hit h8[8], h1;
        cr_assert_eq(scene_intersect8(s, &p, 0xff, h8), 0xff);
        for (int k = 0; k < 8; k++) {
            ray r = ray8_get(&p, k);
            cr_assert(scene_intersect(s, &r, &h1));
            cr_assert_eq(h1.h.t, 10.0f);
            cr_assert_eq(h1.object, 0, "%s, ray %d: object %d", accel_isa_name((accel_isa)path),
                         k, h1.object);
            cr_assert_eq(h8[k].object, 0);
            cr_assert_eq(h8[k].h.t, 10.0f);
        }
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
}

/* An object that meets rays exactly at their nearest hit so far (best[k],
 * held by a higher index) takes those hits, as scene_hit_object would:
 * turned (its rays in its own space, eight lanes at once) or not, a quad
 * and a torus, on every path. */
Test(packet, a_tie_at_the_nearest_hit_goes_to_the_lower_index)
{
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        int mat;
        scene *s = bare(&mat);
        xform turn = xform_rotate(v3(0.2f, 1, 0.1f), 30.0f);
        int x = scene_add_xform(s, &turn);
        shape quad = shape_quad(v3(-2, -2, 0), v3(4, 0, 0), v3(0, 4, 0));
        shape torus = shape_torus(v3s(0.0f), 1.0f, 0.6f);
        cr_assert_eq(scene_add_object(s, &quad, mat, x), 0);
        cr_assert_eq(scene_add_object(s, &quad, mat, -1), 1);
        cr_assert_eq(scene_add_object(s, &torus, mat, x), 2);
        cr_assert_eq(scene_add_object(s, &torus, mat, -1), 3);
        glint_error err = {0};
        cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
        ray8 p;
        for (int k = 0; k < 8; k++)
            put(&p, k, v3(-1.2f + 0.3f * (float)k, 0.1f * (float)k, 10.0f), v3(0.01f, 0, -1), 0.0f,
                INFINITY);
        for (int i = 0; i < 4; i++) {
            float best[8];
            scene_hit hit[8];
            for (int k = 0; k < 8; k++)
                best[k] = INFINITY, hit[k].object = -1;
            int first = scene_packet_object(s, i, &p, 0xff, best, hit);
            cr_assert_geq(__builtin_popcount((unsigned)first), 4, "object %d: %#x", i, first);
            for (int k = 0; k < 8; k++)
                hit[k] = (scene_hit){{.t = best[k]}, 7}; /* the same distances, held by 7 */
            int found = scene_packet_object(s, i, &p, first, best, hit);
            cr_assert_eq(found, first, "%s, object %d: %#x", accel_isa_name((accel_isa)path), i,
                         found);
            for (int m = found; m; m &= m - 1)
                cr_assert_eq(hit[__builtin_ctz((unsigned)m)].object, i);
        }
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
}

/* Progressive passes (the preview's way) trace camera rays in packets
 * too: passes of 1, then 4 samples resolve to the batch film, bit for bit. */
Test(packet, progressive_passes_end_at_the_batch_film)
{
    accel_isa_force(ACCEL_AUTO);
    scene *s = lit_packet_scene(3);
    glint_error err = {0};
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    st.width = 45, st.height = 30, st.samples = 4, st.threads = 2;
    glint_film batch = {0}, film = {0};
    cr_assert_eq(glint_render(s, &st, NULL, &batch, NULL, &err), GLINT_OK, "%s", err.msg);
    glint_accum a;
    cr_assert_eq(glint_accum_alloc(&a, st.width, st.height, &err), GLINT_OK);
    cr_assert_eq(glint_film_alloc(&film, st.width, st.height, &err), GLINT_OK);
    static const int passes[] = {1, 4};
    for (int i = 0; i < 2; i++) {
        cr_assert_eq(glint_render_pass(s, &st, passes[i], NULL, &a, NULL, &err), GLINT_OK, "%s",
                     err.msg);
        int least;
        cr_assert_eq(glint_accum_resolve(&a, NULL, &film, &least, &err), GLINT_OK);
        cr_assert_eq(least, passes[i]);
    }
    cr_expect_eq(memcmp(film.rgb, batch.rgb, sizeof(float) * 3 * 45 * 30), 0);
    glint_film_free(&film);
    glint_film_free(&batch);
    glint_accum_free(&a);
    scene_free(s);
}

/* Rays that cross the grid's shared edges, where two triangles give the
 * same distance and a box's entry distance can come out a unit in the last
 * place beyond it: seven lanes beside each such ray change the order in
 * which a packet meets the leaves, and every ray must still get the one-ray
 * hit (traverse.h: wide_reach). */
Test(packet, ties_across_leaves_do_not_depend_on_the_walk)
{
    for (int path = ACCEL_AVX2; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        mesh *m = grid_mesh(16);
        for (int c = 1; c < 16; c++)
            for (int j = 0; j < 16; j += 3)
                for (int a = 1; a < 64; a += 2)
                    for (int oz = 3; oz < 12; oz += 2) {
                        float dx = -(float)a / 64.0f, z = (float)oz, x = (float)c - dx * z;
                        ray8 p;
                        for (int k = 0; k < 8; k++)
                            put(&p, k, v3(x - 0.75f * (float)k, (float)j + 0.3f, z),
                                v3(dx, 0.0f, -1.0f), 0.0f, INFINITY);
                        shape_hit h8[8], h1;
                        int found = mesh_intersect8(m, &p, 0xff, h8);
                        for (int k = 0; k < 8; k++) {
                            ray r = ray8_get(&p, k);
                            bool hit = mesh_intersect(m, &r, &h1);
                            cr_assert_eq(found >> k & 1, hit);
                            if (hit)
                                expect_same_hit(&h8[k], &h1, c * 1000 + a, k);
                        }
                    }
        mesh_drop(m);
    }
    accel_isa_force(ACCEL_AUTO);
}

/* Two overlapping quads in one plane, objects 0 and 1 in leaves of their
 * own, in a tree of one node and a deeper one: where a ray meets both at
 * the same distance object 0 wins, in a packet whose other rays reach only
 * one of them too. */
Test(packet, coplanar_objects_tie_alike_in_any_tree)
{
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        for (int balls = 4; balls <= 40; balls += 36) {
            scene *s = scene_new();
            material mt = material_default();
            int mat = scene_add_material(s, &mt);
            xform id = xform_translate(v3s(0.0f)); /* leaves of their own */
            int x = scene_add_xform(s, &id);
            shape q0 = shape_quad(v3(-6, -2, 0), v3(8, 0, 0), v3(0, 4, 0));
            shape q1 = shape_quad(v3(-2, -2, 0), v3(8, 0, 0), v3(0, 4, 0));
            cr_assert_eq(scene_add_object(s, &q0, mat, x), 0);
            cr_assert_eq(scene_add_object(s, &q1, mat, x), 1);
            for (int k = 0; k < balls; k++) {
                shape ball = shape_sphere(v3(-30.0f - 5.0f * (float)k, 0, 0), 1.0f);
                cr_assert_geq(scene_add_object(s, &ball, mat, x), 0);
            }
            glint_error err = {0};
            cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
            rng g = rng_seed(5, 1);
            for (int i = 0; i < 4000; i++) {
                ray8 p;
                for (int k = 0; k < 8; k++) {
                    float ox = k == 0 ? uniform(&g, -1.5f, 0.5f)
                                      : (i & 1 ? -5.8f : 2.2f) + uniform(&g, 0.0f, 3.0f);
                    float oz = k == 0 ? uniform(&g, 5.0f, 10.0f) : uniform(&g, 0.5f, 1.5f);
                    put(&p, k, v3(ox, uniform(&g, -1, 1), oz),
                        v3(uniform(&g, 0, 0.05f), uniform(&g, 0, 0.05f), uniform(&g, -1.5f, -0.5f)),
                        0.0f, INFINITY);
                }
                scene_hit h8[8], h1;
                int found = scene_intersect8(s, &p, 0xff, h8);
                for (int k = 0; k < 8; k++) {
                    ray r = ray8_get(&p, k);
                    bool hit = scene_intersect(s, &r, &h1);
                    cr_assert_eq(found >> k & 1, hit);
                    if (hit)
                        cr_assert(h8[k].object == h1.object && h8[k].h.t == h1.h.t,
                                  "%s, packet %d ray %d: object %d t %.9g against %d t %.9g",
                                  accel_isa_name((accel_isa)path), i, k, h8[k].object, h8[k].h.t,
                                  h1.object, h1.h.t);
                }
            }
            scene_free(s);
        }
    }
    accel_isa_force(ACCEL_AUTO);
}

/* 10 x 10 x 2 balls and cubes (alternately) of radius 0.45 on a unit
 * lattice: a tree of three levels, whose boxes the rays below graze. */
static vec3 lattice_at(int i) { return v3((float)(i % 10), (float)(i / 100), (float)(-(i / 10 % 10))); }

static scene *ball_lattice(void)
{
    scene *s = scene_new();
    cr_assert_not_null(s);
    material mt = material_default();
    int mat = scene_add_material(s, &mt);
    for (int i = 0; i < 200; i++) {
        vec3 c = lattice_at(i), e = v3s(0.45f);
        shape b = i % 2 ? shape_box(v3_sub(c, e), v3_add(c, e)) : shape_sphere(c, 0.45f);
        cr_assert_geq(scene_add_object(s, &b, mat, -1), 0);
    }
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* Eight rays from origins up to `spread` apart, each at a ball's
 * silhouette or a cube's edge (give or take a float or two, so most go
 * by a box's edge or corner). */
static ray8 grazing_packet(rng *g, float spread)
{
    ray8 p;
    vec3 eye = v3(uniform(g, -3, 12), uniform(g, 3, 9), uniform(g, 4, 12));
    int first = (int)(rng_float(g) * 200.0f) % 200;
    for (int k = 0; k < 8; k++) {
        vec3 o = v3_add(eye, v3(uniform(g, -spread, spread), uniform(g, -spread, spread),
                                uniform(g, -spread, spread)));
        int b = k < 4 ? first : (first + k) % 200;
        vec3 c = lattice_at(b), to = v3_sub(c, o);
        float edge = 0.45f * (1.0f + uniform(g, -4e-7f, 4e-7f));
        vec3 at = v3_scale(v3_norm(v3_cross(to, v3(0.3f, 1.0f, 0.1f))), edge);
        if (b % 2) /* a cube: an edge, one coordinate anywhere along it */
            at = v3(k & 1 ? edge : -edge, k & 2 ? uniform(g, -edge, edge) : edge,
                    k & 2 ? -edge : uniform(g, -edge, edge));
        put(&p, k, o, v3_add(to, at), 1e-3f, INFINITY);
    }
    return p;
}

/* The eight-wide walks cull a node's children for the whole packet at
 * once before testing each ray (packet_cull, interval arithmetic over the
 * rays' origins and directions): a ray grazing a box must still reach
 * what it hits or what blocks it, whether the packet's rays share an
 * origin, spread a little (shadow rays from one surface) or a lot. */
Test(packet, culling_a_node_for_the_packet_keeps_every_box_a_ray_enters)
{
    int hits = 0, blocked_rays = 0;
    for (int path = ACCEL_AVX2; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = ball_lattice();
        cr_assert(!s->flat && s->bvh.nnodes > 8);
        rng g = rng_seed(17, 8);
        static const float spreads[] = {0.0f, 0.02f, 0.5f, 4.0f};
        for (int i = 0; i < 6000; i++) {
            ray8 p = grazing_packet(&g, spreads[i % 4]);
            int active = i % 9 == 0 ? 0xb7 : 0xff;
            hits += same_packet_hits(s, &p, active, i, SHAPE_SPHERE);
            int blocked, crosses;
            if (!scene_shadow8(s, &p, active, &blocked, &crosses))
                continue; /* the rays differ in their directions' signs */
            cr_assert_eq(crosses, 0);
            for (int k = 0; k < 8; k++) {
                ray r = ray8_get(&p, k);
                bool want = (active >> k & 1) && scene_occluded_opaque(s, &r);
                cr_assert_eq(blocked >> k & 1, want, "packet %d ray %d", i, k);
                blocked_rays += want;
            }
        }
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert(hits > 10000 && blocked_rays > 10000, "%d hits, %d blocked", hits, blocked_rays);
}

/* 24 balls and cubes of ball_lattice's kind (a tree of one node on the
 * eight-wide paths), a cube turned about its centre and a ground plane
 * (unless not with_ground). */
static scene *small_lattice(bool with_ground)
{
    scene *s = scene_new();
    cr_assert_not_null(s);
    material mt = material_default();
    int mat = scene_add_material(s, &mt);
    shape ground = shape_plane(v3(0, -0.6f, 0), v3(0, 1, 0));
    if (with_ground)
        cr_assert_geq(scene_add_object(s, &ground, mat, -1), 0);
    for (int i = 0; i < 24; i++) {
        vec3 c = lattice_at(i % 6 + i / 6 * 10), e = v3s(0.45f);
        shape b = i % 2 ? shape_box(v3_sub(c, e), v3_add(c, e)) : shape_sphere(c, 0.45f);
        cr_assert_geq(scene_add_object(s, &b, mat, -1), 0);
    }
    xform r = xform_rotate(v3(1.0f, 1.0f, 0.0f), 40.0f);
    xform t = xform_translate(v3(7.0f, 1.0f, -2.0f));
    xform rt = xform_then(&r, &t);
    shape cube = shape_box(v3s(-0.5f), v3s(0.5f));
    cr_assert_geq(scene_add_object(s, &cube, mat, scene_add_xform(s, &rt)), 0);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* Ray k of packet p against scene_intersect, when it is one of active:
 * found's bit k and the packet's hit h8[k] (scene_intersect8_among's)
 * agree with it, on path, in packet i. Returns whether the ray hits. */
static bool expect_among_hit(const scene *s, const ray8 *p, int active, int found,
                             const scene_hit h8[8], int path, int i, int k)
{
    ray r = ray8_get(p, k);
    scene_hit h1;
    bool hit = (active >> k & 1) && scene_intersect(s, &r, &h1);
    cr_assert_eq(found >> k & 1, hit, "%s, packet %d ray %d", accel_isa_name((accel_isa)path), i,
                 k);
    if (hit) {
        cr_assert_eq(h8[k].object, h1.object, "packet %d ray %d", i, k);
        expect_same_hit(&h8[k].h, &h1.h, i, k);
    }
    return hit;
}

/* A tile's camera rays are tested against the objects its cone may meet
 * (scene_cone_objects, scene_intersect8_among) and find scene_intersect's
 * hits to the bit: eight rays from one eye, at silhouettes and edges, and
 * the cone no wider than their directions, so that the grazing rays lie
 * on its sides. A narrow cone leaves objects out; a scene with more
 * objects than the list holds gives none. */
Test(packet, a_tile_cone_keeps_every_object_its_rays_hit)
{
    int hits = 0, left_out = 0;
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = small_lattice(true);
        int32_t list[32];
        rng g = rng_seed(23, 4);
        for (int i = 0; i < 6000; i++) {
            ray8 p = grazing_packet(&g, 0.0f);
            for (int k = 0; k < 8; k++)
                p.tmin[k] = 0.0f; /* a camera's rays start at the eye */
            if (i % 3 == 0) { /* rays to anywhere in the lattice's direction */
                for (int k = 0; k < 8; k++) {
                    p.dx[k] = 2.0f + uniform(&g, -6, 6) - p.ox[0];
                    p.dy[k] = uniform(&g, -3, 1) - p.oy[0];
                    p.dz[k] = -2.0f + uniform(&g, -3, 3) - p.oz[0];
                }
            } else if (i % 3 == 1) { /* one grazing ray: the cone is its direction */
                ray one = ray8_get(&p, i / 3 % 8);
                for (int k = 0; k < 8; k++)
                    put(&p, k, one.o, one.d, 0.0f, INFINITY);
            }
            vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
            for (int k = 0; k < 8; k++) {
                vec3 d = v3(p.dx[k], p.dy[k], p.dz[k]);
                lo = v3_min(lo, d);
                hi = v3_max(hi, d);
            }
            vec3 eye = v3(p.ox[0], p.oy[0], p.oz[0]);
            int n = scene_cone_objects(s, eye, lo, hi, list, 32, NULL);
            if (!s->flat && !(s->bvh.width == 8 && s->bvh.nnodes > 0)) {
                cr_assert_eq(n, -1, "%s: the path takes no packets", accel_isa_name((accel_isa)path));
                break;
            }
            cr_assert(n >= 0 && n <= s->bvh.nprims, "%d", n);
            left_out += s->bvh.nprims - n;
            int active = i % 7 == 0 ? 0x5d : 0xff;
            scene_hit h8[8];
            int found = scene_intersect8_among(s, &p, active, list, n, h8);
            for (int k = 0; k < 8; k++)
                hits += expect_among_hit(s, &p, active, found, h8, path, i, k);
        }
        scene_free(s);
        s = ball_lattice(); /* 200 objects */
        cr_assert_eq(
            scene_cone_objects(s, v3(0, 5, 8), v3(-1, -1, -1), v3(1, 1, -0.5f), list, 32, NULL), -1);
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert(hits > 20000 && left_out > 50000, "%d hits, %d objects left out", hits,
                  left_out);
}

/* Objects a list's packets test only where their rays may meet the
 * objects' boxes (turned ones, tori: scene_among8, scene_shadow_among8)
 * lose no hit and no shadow: rays aimed at points in and just around the
 * boxes, where turned boxes and tori touch them, find scene_intersect's
 * hits and scene_occluded_opaque's shadows. */
Test(packet, listed_costly_objects_keep_every_hit_near_their_boxes)
{
    int hits = 0;
    for (int path = ACCEL_AVX2; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = scene_new();
        material mt = material_default();
        int mat = scene_add_material(s, &mt);
        for (int i = 0; i < 6; i++) {
            vec3 at = v3(2.5f * (float)i - 6.0f, 0.0f, -4.0f);
            xform r = xform_rotate(v3(1.0f, 1.0f, (float)i), 15.0f + 25.0f * (float)i);
            xform t = xform_translate(at);
            xform rt = xform_then(&r, &t);
            shape sh =
                i % 2 ? shape_box(v3s(-0.7f), v3s(0.7f)) : shape_torus(v3s(0.0f), 0.7f, 0.3f);
            cr_assert_geq(scene_add_object(s, &sh, mat, scene_add_xform(s, &rt)), 0);
        }
        glint_error err = {0};
        cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
        int32_t list[6] = {0, 1, 2, 3, 4, 5};
        rng g = rng_seed(31, 2);
        for (int i = 0; i < 4000; i++) {
            aabb b = s->bounds[i % 6];
            vec3 eye = v3(uniform(&g, -3, 3), uniform(&g, 2, 6), uniform(&g, 4, 8));
            ray8 p;
            for (int k = 0; k < 8; k++) { /* a point of the box, or just outside it */
                vec3 at = v3(uniform(&g, b.lo.x - 0.05f, b.hi.x + 0.05f),
                             uniform(&g, b.lo.y - 0.05f, b.hi.y + 0.05f),
                             uniform(&g, b.lo.z - 0.05f, b.hi.z + 0.05f));
                put(&p, k, eye, v3_sub(at, eye), 0.0f, i % 5 ? INFINITY : 1.0f);
            }
            scene_hit h8[8];
            int found = scene_intersect8_among(s, &p, 0xff, list, 6, h8);
            int blocked = 0, crosses = 0;
            cr_assert(scene_shadow8_among(s, &p, 0xff, list, 6, &blocked, &crosses));
            for (int k = 0; k < 8; k++) {
                ray r = ray8_get(&p, k);
                cr_assert_eq(blocked >> k & 1, scene_occluded_opaque(s, &r),
                             "%s, packet %d ray %d: the shadow",
                             accel_isa_name((accel_isa)path), i, k);
                hits += expect_among_hit(s, &p, 0xff, found, h8, path, i, k);
            }
        }
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert_gt(hits, 10000, "%d hits", hits);
}

/* A listed object a packet's rays meet along the plane of one of its box's
 * faces, a direction's zero component on that face (0 times infinity in
 * the box test), keeps those rays, as the walk's box test does. */
Test(packet, a_listed_object_keeps_rays_along_its_boxs_face)
{
    for (int path = ACCEL_AVX2; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        for (int kind = 0; kind < 2; kind++) {
            scene *s = scene_new();
            material mt = material_default();
            int mat = scene_add_material(s, &mt);
            xform id = xform_identity();
            shape sh = kind ? shape_box(v3(1, -1, 0), v3(2, 1, 1))
                            : shape_triangle(v3(1, -1, 0), v3(1, 1, 0), v3(1, 0, 1));
            cr_assert_geq(scene_add_object(s, &sh, mat, kind ? scene_add_xform(s, &id) : -1), 0);
            glint_error err = {0};
            cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
            ray8 p;
            for (int k = 0; k < 8; k++) /* along z = 0, the box's lower face */
                put(&p, k, v3s(0.0f), v3(1.0f, 0.05f + 0.1f * (float)k, 0.0f), 0.0f, INFINITY);
            int32_t list[1] = {0};
            scene_hit h8[8], h1;
            int found = scene_intersect8_among(s, &p, 0xff, list, 1, h8), blocked = 0, crosses = 0;
            cr_assert(scene_shadow8_among(s, &p, 0xff, list, 1, &blocked, &crosses));
            int want = 0, shade = 0;
            for (int k = 0; k < 8; k++) {
                ray r = ray8_get(&p, k);
                want |= scene_intersect(s, &r, &h1) << k;
                shade |= scene_occluded_opaque(s, &r) << k;
            }
            cr_assert_eq(want, 0xff, "the rays meet the %s", kind ? "box" : "triangle");
            cr_assert_eq(found, want, "%s: %x against %x", kind ? "box" : "triangle", found, want);
            cr_assert_eq(blocked, shade, "%s: %x against %x", kind ? "box" : "triangle", blocked,
                         shade);
            scene_free(s);
        }
    }
    accel_isa_force(ACCEL_AUTO);
}

/* A plane's hits lie in the reach the tile's cone gives them, turned
 * planes' too, for cones that dip under the horizon by as little as
 * 1e-6: where the renderer's hits there may stray beyond the margin, the
 * reach is the whole space. */
Test(packet, a_planes_hits_lie_in_its_reach_near_the_horizon)
{
    rng g = rng_seed(7, 1);
    const vec3 normals[3] = {v3(0, 1, 0), v3(0.3f, 1.0f, 0.7f), v3(1, 1, 1)};
    int lists = 0, grazing = 0, hits = 0;
    for (int run = 0; run < 6; run++) {
        scene *s = scene_new();
        material mt = material_default();
        int mat = scene_add_material(s, &mt);
        shape pl = shape_plane(v3(0.2f, -0.1f, 0.3f), normals[run % 3]);
        shape ball = shape_sphere(v3(0, 5, -5), 0.5f);
        cr_assert_geq(scene_add_object(s, &pl, mat, -1), 0);
        cr_assert_geq(scene_add_object(s, &ball, mat, -1), 0);
        glint_error err = {0};
        cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
        const struct plane *sp = &s->objects[0].shape.plane;
        vec3 n = sp->normal;
        for (int i = 0; i < 20000; i++) {
            vec3 eye = v3_add(sp->point, v3(uniform(&g, -3, 3), 0.0f, uniform(&g, -3, 3)));
            eye = v3_madd(eye, n, uniform(&g, 1, 4));
            vec3 side = v3(uniform(&g, -1, 1), uniform(&g, -1, 1), uniform(&g, -1, 1));
            vec3 h = v3_norm(v3_cross(n, side)); /* along the plane */
            float dip = powf(10.0f, -uniform(&g, 1.0f, 6.0f)), w = run < 3 ? 0.3f * dip : 0.01f;
            vec3 d0 = v3_sub(h, v3_scale(n, dip + 3.0f * w));
            vec3 lo = v3_sub(d0, v3s(w)), hi = v3_add(d0, v3s(w));
            int32_t list[8];
            aabb reach;
            if (scene_cone_objects(s, eye, lo, hi, list, 8, &reach) < 0 ||
                aabb_is_unbounded(reach))
                continue;
            lists++;
            grazing += dip < 1e-3f;
            for (int k = 0; k < 16; k++) {
                vec3 d = k < 8 ? v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z)
                               : v3(uniform(&g, lo.x, hi.x), uniform(&g, lo.y, hi.y),
                                    uniform(&g, lo.z, hi.z));
                ray r = {.o = eye, .d = d, .tmin = 0.0f, .tmax = INFINITY};
                scene_hit hh;
                if (!scene_intersect(s, &r, &hh) || hh.object != 0)
                    continue;
                surface sf;
                vec3 at = ray_at(&r, hh.h.t);
                plane_surface(sp, at, &sf);
                for (int q = 0; q < 2; q++) {
                    vec3 x = q ? sf.p : at;
                    cr_assert(x.x >= reach.lo.x && x.y >= reach.lo.y && x.z >= reach.lo.z &&
                                  x.x <= reach.hi.x && x.y <= reach.hi.y && x.z <= reach.hi.z,
                              "run %d, cone %d (dip %g): a hit (%g %g %g) outside the reach "
                              "(%g %g %g .. %g %g %g)",
                              run, i, dip, x.x, x.y, x.z, reach.lo.x, reach.lo.y, reach.lo.z,
                              reach.hi.x, reach.hi.y, reach.hi.z);
                }
                hits++;
            }
        }
        scene_free(s);
    }
    cr_assert(lists > 20000 && grazing > 1000 && hits > 200000,
              "%d lists, %d of them grazing, %d hits", lists, grazing, hits);
}

/* The shadow rays from the hits of a tile's camera rays to a point light
 * are tested against the objects the light's cone through the hits' reach
 * may meet (scene_shadow_cone_objects, scene_shadow8_among): every hit
 * lies in the reach, and each ray is blocked where scene_occluded_opaque
 * says, leaving its hit by ray_offset along any normal. With a ground
 * plane, the reach holds the plane's hits where every direction of the
 * cone heads for it, and there is no list where one does not. */
Test(packet, a_light_cone_keeps_every_object_a_shadow_ray_meets)
{
    int blocked_rays = 0, free_rays = 0, left_out = 0, ground_lists = 0, ground_none = 0;
    for (int run = 0; run < 4; run++) {
        int path = ACCEL_AVX2 + run / 2;
        bool ground = run % 2;
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = small_lattice(ground);
        int32_t list[32], shadows[32];
        rng g = rng_seed(29, 6);
        for (int i = 0; i < 6000; i++) {
            ray8 p = grazing_packet(&g, 0.0f);
            if (i % 2) { /* one ray: a reach as small as a hit, and a cone as thin */
                ray one = ray8_get(&p, i / 2 % 8);
                for (int k = 0; k < 8; k++)
                    put(&p, k, one.o, one.d, 0.0f, INFINITY);
            } else if (ground && i % 4 == 2) { /* one ray up or level: the horizon in the cone */
                p.dy[i / 4 % 8] = i % 8 == 2 ? 0.0f : 0.3f;
            }
            vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
            for (int k = 0; k < 8; k++) {
                p.tmin[k] = 0.0f;
                vec3 d = v3(p.dx[k], p.dy[k], p.dz[k]);
                lo = v3_min(lo, d);
                hi = v3_max(hi, d);
            }
            aabb reach;
            int n = scene_cone_objects(s, v3(p.ox[0], p.oy[0], p.oz[0]), lo, hi, list, 32, &reach);
            cr_assert_geq(n, 0);
            vec3 light_at = v3(uniform(&g, -20, 30), uniform(&g, 2, 30), uniform(&g, -20, 20));
            int m = scene_shadow_cone_objects(s, reach, light_at, shadows, 32);
            if (ground) {
                bool down = true; /* every direction of the cone heads for the ground */
                for (int c = 0; c < 8; c++)
                    down &= (c & 2 ? hi.y : lo.y) < 0.0f;
                if (p.oy[0] <= -0.6f || !down) {
                    cr_assert_eq(m, -1, "packet %d: the cone meets the ground anywhere", i);
                    ground_none++;
                    continue;
                }
                ground_lists += m >= 0;
            }
            cr_assert(m >= 0 && m <= s->bvh.nprims, "%d", m);
            left_out += s->bvh.nprims - m;
            if (n > 0) /* segments to the light from the corners of the reach, as far */
                for (int c = 0; c < 8; c++) { /* out as a shadow ray's origin moves */
                    vec3 at = v3(c & 1 ? reach.hi.x : reach.lo.x, c & 2 ? reach.hi.y : reach.lo.y,
                                 c & 4 ? reach.hi.z : reach.lo.z);
                    vec3 out = v3(c & 1 ? 1.0f : -1.0f, c & 2 ? 1.0f : -1.0f, c & 4 ? 1.0f : -1.0f);
                    vec3 o = v3_madd(at, out, 0.999f * ray_epsilon(at));
                    ray r = {.o = o, .d = v3_sub(light_at, o), .tmin = 0.0f, .tmax = 1.0f};
                    for (int k = 0; k < s->nobjects; k++) {
                        ray lr = scene_object_ray(s, &s->objects[k], &r);
                        /* the unbounded ones are tested by every packet */
                        bool listed = aabb_is_unbounded(s->bounds[k]);
                        for (int q = 0; q < m; q++)
                            listed |= shadows[q] == k;
                        cr_assert(listed || !shape_occluded_inline(&s->objects[k].shape, &lr),
                                  "packet %d corner %d: object %d is met, not listed", i, c, k);
                    }
                }
            ray8 sr;
            int active = 0;
            for (int k = 0; k < 8; k++) {
                ray r = ray8_get(&p, k);
                scene_hit h;
                if (!scene_intersect(s, &r, &h))
                    continue;
                vec3 at = ray_at(&r, h.h.t);
                cr_assert(at.x >= reach.lo.x && at.y >= reach.lo.y && at.z >= reach.lo.z &&
                              at.x <= reach.hi.x && at.y <= reach.hi.y && at.z <= reach.hi.z,
                          "packet %d ray %d: its hit on object %d is outside the reach", i, k,
                          h.object);
                vec3 ng = v3_norm(v3(uniform(&g, -1, 1), uniform(&g, -1, 1), uniform(&g, -1, 1)));
                vec3 o = ray_offset(at, ng, v3_sub(light_at, at));
                put(&sr, k, o, v3_sub(light_at, o), 0.0f, 1.0f);
                active |= 1 << k;
            }
            if (!ray8_three_or_more(active))
                continue;
            ray8_fill(&sr, active);
            int blocked, crosses;
            cr_assert(scene_shadow8_among(s, &sr, active, shadows, m, &blocked, &crosses));
            cr_assert_eq(crosses, 0);
            for (int k = 0; k < 8; k++) {
                if (!(active >> k & 1))
                    continue;
                ray r = ray8_get(&sr, k);
                bool want = scene_occluded_opaque(s, &r);
                cr_assert_eq(blocked >> k & 1, want, "%s, packet %d ray %d",
                             accel_isa_name((accel_isa)path), i, k);
                blocked_rays += want;
                free_rays += !want;
            }
        }
        scene_free(s);
    }
    scene *s = small_lattice(true);
    int32_t list[32], shadows[32];
    aabb reach;
    cr_assert_geq(scene_cone_objects(s, v3(2, 5, 8), v3(-0.1f, -1, -1), v3(0.1f, -0.5f, -0.8f),
                                     list, 32, &reach),
                  0);
    cr_assert(reach.lo.y < -0.6f && reach.hi.y < 5.0f && reach.lo.z > -20.0f,
              "the ground's hits are bounded: y %g..%g, z %g..%g", reach.lo.y, reach.hi.y,
              reach.lo.z, reach.hi.z);
    cr_assert_geq(scene_shadow_cone_objects(s, reach, v3(0, 20, 0), shadows, 32), 0);
    cr_assert_geq(scene_cone_objects(s, v3(2, 5, 8), v3(-0.1f, -1, -1), v3(0.1f, 0.0f, -0.8f),
                                     list, 32, &reach),
                  0);
    cr_assert_eq(scene_shadow_cone_objects(s, reach, v3(0, 20, 0), shadows, 32), -1,
                 "a cone reaching the horizon meets the ground anywhere");
    scene_free(s);
    accel_isa_force(ACCEL_AUTO);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert(blocked_rays > 2000 && free_rays > 2000 && left_out > 10000 &&
                      ground_lists > 500 && ground_none > 500,
                  "%d blocked, %d not, %d objects left out, %d ground lists, %d cones without",
                  blocked_rays, free_rays, left_out, ground_lists, ground_none);
}

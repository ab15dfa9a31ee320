/* The scene's three queries (scene_intersect, scene_occluded_opaque,
 * scene_shadow) against brute force over every object, on scenes of every
 * size the walks treat differently: one object (a flat scene), a tree of
 * one node (up to a node's width of leaves), and deeper trees; with
 * spheres, quads, boxes and a cylinder, some turned or stretched by a
 * transform, some transmitting; on every SIMD path this CPU has. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include "accel/isa.h"
#include "core/rng.h"
#include "scene/scene.h"
#include "scene/scene_trace.h"

#define RAYS 3000

static float uniform(rng *g, float lo, float hi) { return lo + (hi - lo) * rng_float(g); }

static vec3 point_in(rng *g, float half)
{
    return v3(uniform(g, -half, half), uniform(g, -half, half), uniform(g, -half, half));
}

/* n objects scattered in a cube of side 20 (so that they overlap and
 * shadow one another); object k's kind and material follow from k. */
static scene *random_scene(int n, uint64_t seed)
{
    rng g = rng_seed(seed, 1);
    scene *s = scene_new();
    cr_assert_not_null(s);
    material opaque = material_default(), clear = material_default();
    clear.transmit = 0.6f;
    int mat[2] = {scene_add_material(s, &opaque), scene_add_material(s, &clear)};
    for (int k = 0; k < n; k++) {
        vec3 c = point_in(&g, 10.0f);
        float size = uniform(&g, 0.5f, 3.0f);
        shape sh;
        switch (k % 4) {
        case 0: sh = shape_sphere(c, size); break;
        case 1: sh = shape_quad(c, v3(size, 0.3f, 0.0f), v3(0.2f, 0.1f, size)); break;
        case 2: sh = shape_box(v3_sub(c, v3s(size)), v3_add(c, v3(size, 0.5f * size, size))); break;
        default: sh = shape_cylinder(c, size, 2.0f * size, true); break;
        }
        int x = -1;
        if (k % 3 == 2) { /* turned and stretched about the origin */
            xform r = xform_rotate(v3(1.0f, 2.0f, 0.5f), 10.0f * (float)k);
            xform st = xform_scale(v3(1.0f, 1.5f, 0.75f));
            xform t = xform_then(&st, &r);
            x = scene_add_xform(s, &t);
        }
        cr_assert_geq(scene_add_object(s, &sh, mat[k % 5 == 1], x), 0);
    }
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* Rays from outside and from inside the cloud, with and without a far
 * limit, some of them segments of finite length like shadow rays. */
static ray random_ray(rng *g, int i)
{
    vec3 o = i % 3 == 0 ? point_in(g, 8.0f) : v3_scale(v3_norm(point_in(g, 1.0f)), 40.0f);
    vec3 to = point_in(g, 12.0f);
    ray r = ray_make(o, v3_sub(to, o), i % 2 ? 1.0f : INFINITY);
    if (i % 5 == 0)
        r.d = v3_scale(r.d, 0.01f); /* t in other units */
    return r;
}

static bool brute_closest(const scene *s, const ray *r, scene_hit *best)
{
    float tmax = r->tmax;
    bool found = false;
    for (int i = 0; i < s->nobjects; i++) {
        shape_hit h;
        ray lr = scene_object_ray(s, &s->objects[i], r);
        lr.tmax = INFINITY;
        if (shape_intersect(&s->objects[i].shape, &lr, &h) && h.t < tmax) {
            tmax = h.t;
            *best = (scene_hit){h, i};
            found = true;
        }
    }
    return found;
}

static bool brute_blocked(const scene *s, const ray *r)
{
    for (int i = 0; i < s->nobjects; i++) {
        ray lr = scene_object_ray(s, &s->objects[i], r);
        if (!s->objects[i].transmits && shape_occluded(&s->objects[i].shape, &lr))
            return true;
    }
    return false;
}

/* Every crossing of a transmitting object, by the rule of scene.h. */
static int brute_crossings(const scene *s, const ray *r, float t[], int obj[])
{
    int n = 0;
    for (int i = 0; i < s->nobjects; i++) {
        if (!s->objects[i].transmits)
            continue;
        ray lr = scene_object_ray(s, &s->objects[i], r);
        shape_hit h;
        while (n < SCENE_SHADOW_MAX && shape_intersect(&s->objects[i].shape, &lr, &h)) {
            t[n] = h.t;
            obj[n++] = i;
            float next = h.t + ray_epsilon(ray_at(r, h.t)) / v3_len(r->d);
            lr.tmin = next > h.t ? next : nextafterf(h.t, INFINITY);
        }
    }
    return n;
}

static void check_closest(const scene *s, const ray *r, int n, int i)
{
    scene_hit got, want;
    bool hit = scene_intersect(s, r, &got), bhit = brute_closest(s, r, &want);
    cr_assert_eq(hit, bhit, "%d objects, ray %d: scene %s, brute force %s", n, i,
                 hit ? "hits" : "misses", bhit ? "hits" : "misses");
    if (!hit)
        return;
    cr_assert_eq(got.h.t, want.h.t, "%d objects, ray %d: t %.9g (object %d), brute force %.9g "
                 "(object %d)", n, i, got.h.t, got.object, want.h.t, want.object);
    if (got.object != want.object) { /* a tie: the other object must hit at the same t */
        shape_hit h;
        ray lr = scene_object_ray(s, &s->objects[got.object], r);
        cr_assert(shape_intersect(&s->objects[got.object].shape, &lr, &h) && h.t == got.h.t);
    }
}

static void check_shadow(const scene *s, const ray *r, int n, int i)
{
    bool blocked = brute_blocked(s, r);
    cr_assert_eq(scene_occluded_opaque(s, r), blocked, "%d objects, ray %d", n, i);
    scene_crossings c;
    float t[SCENE_SHADOW_MAX];
    int obj[SCENE_SHADOW_MAX];
    int m = brute_crossings(s, r, t, obj);
    bool walk = scene_shadow(s, r, &c);
    cr_assert_eq(walk, blocked || m == SCENE_SHADOW_MAX, "%d objects, ray %d", n, i);
    if (walk)
        return;
    cr_assert_eq(c.n, m, "%d objects, ray %d: %d crossings, brute force %d", n, i, c.n, m);
    for (int k = 0; k < m; k++) { /* every brute-force crossing is in the sorted list */
        int found = 0;
        for (int j = 0; j < c.n; j++)
            found += c.hit[j].h.t == t[k] && c.hit[j].object == obj[k];
        cr_assert_eq(found, 1, "%d objects, ray %d: crossing %d (t %.9g) missing", n, i, k, t[k]);
    }
    for (int j = 1; j < c.n; j++)
        cr_assert(c.hit[j - 1].h.t < c.hit[j].h.t ||
                  (c.hit[j - 1].h.t == c.hit[j].h.t && c.hit[j - 1].object < c.hit[j].object));
}

static void check_sizes(void (*check)(const scene *, const ray *, int, int))
{
    static const int sizes[] = {1, 2, 5, 9, 16, 33, 120};
    for (int p = ACCEL_SCALAR; p <= ACCEL_AVX512; p++) {
        if (accel_isa_force((accel_isa)p) != (accel_isa)p)
            continue; /* this CPU lacks it */
        for (size_t z = 0; z < sizeof sizes / sizeof *sizes; z++) {
            scene *s = random_scene(sizes[z], 1000u + (uint64_t)z);
            rng g = rng_seed(7u + (uint64_t)z, 2);
            for (int i = 0; i < RAYS; i++) {
                ray r = random_ray(&g, i);
                check(s, &r, sizes[z], i);
            }
            scene_free(s);
        }
    }
    accel_isa_force(ACCEL_AUTO);
}

Test(scene_query, closest_hit_matches_brute_force_at_every_size)
{
    check_sizes(check_closest);
}

Test(scene_query, shadow_queries_match_brute_force_at_every_size)
{
    check_sizes(check_shadow);
}

/* A scene of at least 4096 bounded objects (scene.c's BUNDLE_MIN) has a
 * tree of bundles: ranges of up to a node's width of objects are not
 * split, each object a lane of its own. Its queries match brute force on
 * every path, and on the eight-wide ones its nodes are fewer than
 * bundles of four make (this scene: 0.19 nodes an object with bundles of
 * eight, 0.24 with four). */
Test(scene_query, bundled_trees_match_brute_force)
{
    enum { N = 4200 };
    for (int p = ACCEL_SCALAR; p <= ACCEL_AVX512; p++) {
        if (accel_isa_force((accel_isa)p) != (accel_isa)p)
            continue;
        scene *s = random_scene(N, 2024);
        if (s->bvh.width == 8)
            cr_assert_lt(s->bvh.nnodes, N * 21 / 100, "%d nodes for %d objects", s->bvh.nnodes, N);
        rng g = rng_seed(99, 2);
        for (int i = 0; i < 400; i++) {
            ray r = random_ray(&g, i);
            check_closest(s, &r, N, i);
            check_shadow(s, &r, N, i);
        }
        scene_free(s);
    }
    accel_isa_force(ACCEL_AUTO);
}

/* The sizes above reach each of the walks: a flat scene, a tree of one
 * node of several leaves, and deeper trees. */
Test(scene_query, the_sizes_reach_every_walk)
{
    accel_isa_force(ACCEL_AUTO);
    scene *one = random_scene(1, 1000), *node = random_scene(9, 1003),
          *deep = random_scene(120, 1006);
    cr_assert(one->flat); /* the seeds are check_sizes' own */
    cr_assert(!node->flat);
    cr_assert_eq(node->bvh.nnodes, 1);
    cr_assert_gt(deep->bvh.nnodes, 1);
    scene_free(one);
    scene_free(node);
    scene_free(deep);
}

/* Room reserved for objects and their transforms is there: the adds that
 * follow move neither array, and a second, smaller reserve changes
 * nothing. */
Test(scene, reserve_objects_makes_room_for_the_adds)
{
    scene *s = scene_new();
    cr_assert_not_null(s);
    cr_assert(scene_add_xform(s, &(xform){mat4_identity(), mat4_identity()}) == 0);
    cr_assert(scene_reserve_objects(s, 500));
    cr_assert_geq(s->cap_objects, 500);
    cr_assert_geq(s->cap_xforms, 501);
    const object *objects = s->objects;
    const xform *xforms = s->xforms;
    cr_assert(scene_reserve_objects(s, 10));
    cr_assert(scene_reserve_objects(s, 0));
    cr_assert_eq(s->objects, objects);
    for (int k = 0; k < 500; k++) {
        xform x = xform_translate(v3((float)k, 0.0f, 0.0f));
        shape sh = shape_sphere(v3(0.0f, 0.0f, 0.0f), 1.0f);
        int xi = scene_add_xform(s, &x);
        cr_assert_eq(xi, k + 1);
        cr_assert_eq(scene_add_object(s, &sh, 0, xi), k);
    }
    cr_assert_eq(s->objects, objects, "the reserved objects were moved");
    cr_assert_eq(s->xforms, xforms, "the reserved transforms were moved");
    cr_assert_eq(s->objects[499].xform, 500);
    cr_assert_eq(s->xforms[500].fwd.m[0][3], 499.0f);
    scene_free(s);
}

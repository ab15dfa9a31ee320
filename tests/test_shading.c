/* shade_prepare's short ways (trace/shading.h and shading.c: an unturned
 * sphere, an unturned plane and a torus turned by a fixed transform, all
 * untextured) against the general way they stand in for: scene_surface,
 * the material's colour times the surface's, and facing. The shading
 * point must be the same to the bit, from outside and from inside, so that
 * a short way can never change a picture. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/mat4.h"
#include "core/rng.h"
#include "geom/shape.h"
#include "scene/scene.h"
#include "shade/material.h"
#include "trace/shading.h"
#include "shape_check.h"

/* The general way's shading point of a hit of r. */
static shade_point general(const scene *s, const ray *r, const scene_hit *hit)
{
    const material *m = scene_hit_material(s, hit);
    surface sf;
    scene_surface(s, r, hit, &sf);
    shade_point sp;
    facing(&sp, m, v3_norm(r->d), sf.p, sf.n, sf.ng, v3_mul(m->color, sf.color));
    return sp;
}

static bool same_v3(vec3 a, vec3 b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Rays from around the object and from inside its bounds (for a plane,
 * the box aim), aimed at random points of them; every hit's shade_prepare
 * against general. Returns the hits from inside (the normals turned
 * round). */
static int expect_same_points(const char *name, shape sh, const xform *x, const aabb *aim,
                              uint64_t seed)
{
    scene *s = one_object(sh, x);
    aabb b = aim ? *aim : s->bounds[0];
    vec3 c = aabb_center(b);
    float R = 2.0f * v3_len(aabb_extent(b)) + 1.0f;
    rng g = rng_seed(seed, 5);
    trace_ctx ctx = {.scene = s};
    int hits = 0, inside = 0;
    for (int i = 0; i < 20000; i++) {
        vec3 o = i % 2 ? v3_madd(c, rng_unit_dir(&g), R) : rand_in_box(&g, b);
        ray r = ray_make(o, v3_sub(rand_in_box(&g, b), o), INFINITY);
        scene_hit hit;
        if (!scene_intersect(s, &r, &hit))
            continue;
        shade_point got, want = general(s, &r, &hit);
        shade_prepare(&ctx, &r, &hit, &got);
        cr_assert(same_v3(got.p, want.p) && same_v3(got.n, want.n) && same_v3(got.ng, want.ng) &&
                      same_v3(got.d, want.d) && same_v3(got.base, want.base) &&
                      got.inside == want.inside && got.m == want.m,
                  "%s, ray %d: shade_prepare gives p (%.9g %.9g %.9g) n (%.9g %.9g %.9g), the "
                  "general way p (%.9g %.9g %.9g) n (%.9g %.9g %.9g)",
                  name, i, (double)got.p.x, (double)got.p.y, (double)got.p.z, (double)got.n.x,
                  (double)got.n.y, (double)got.n.z, (double)want.p.x, (double)want.p.y,
                  (double)want.p.z, (double)want.n.x, (double)want.n.y, (double)want.n.z);
        hits++;
        inside += got.inside;
    }
    cr_assert_gt(hits, 4000, "%s: only %d hits", name, hits);
    scene_free(s);
    return inside;
}

Test(shading, turned_torus_point_is_the_general_ones)
{
    xform a = xform_rotate(v3(1, 0, 0), 117.0f), b = xform_rotate(v3(0, 1, 0), 109.0f);
    xform c = xform_translate(v3(-4.5f, 0.42f, 3.5f)), ab = xform_then(&a, &b);
    xform x = xform_then(&ab, &c);
    int inside =
        expect_same_points("turned torus", shape_torus(v3(0, 0, 0), 0.32f, 0.1f), &x, NULL, 1);
    cr_assert_gt(inside, 100, "only %d hits from inside the tube", inside);
    /* a spindle torus (minor radius past the major), turned and scaled */
    a = xform_scale(v3(1.5f, 0.5f, 2.0f));
    b = xform_rotate(v3(0, 0, 1), 30.0f);
    x = xform_then(&a, &b);
    expect_same_points("turned spindle torus", shape_torus(v3(1, 2, 3), 0.5f, 0.8f), &x, NULL, 2);
}

Test(shading, plane_and_sphere_points_are_the_general_ones)
{
    aabb near = {v3(-4, -5, -2), v3(5, 3, 6)};
    int inside = expect_same_points(
        "plane", shape_plane(v3(0.5f, -1, 2), v3_norm(v3(0.3f, 0.9f, 0.1f))), NULL, &near, 3);
    cr_assert_gt(inside, 100, "only %d hits from below the plane", inside);
    expect_same_points("sphere", shape_sphere(v3(1, -2, 0.5f), 1.7f), NULL, NULL, 4);
    /* a turned plane and sphere take the general way: the same again */
    xform x = xform_rotate(v3(0, 1, 1), 40.0f);
    expect_same_points("turned plane", shape_plane(v3(0, 0, 0), v3(0, 1, 0)), &x, &near, 5);
    expect_same_points("turned sphere", shape_sphere(v3(0, 1, 0), 1.0f), &x, NULL, 6);
}

/* Constructive solid geometry (geom/csg.h) against a point-membership
 * oracle that shares nothing with it: each solid's inside is decided by its
 * own inequality (|p - c| < r, the torus's quartic < 0, a point behind
 * every face, ...) at the point carried into the solid's space, and the
 * tree is evaluated on those answers.
 *
 * - Random trees three levels deep of random solids, each maybe moved,
 *   turned, scaled and sheared: on random points the tree's membership is
 *   what the oracle says (csg_contains), and on random rays (many starting
 *   inside) the first hit is the first place along the ray where the
 *   oracle's membership changes, found by stepping and bisection; the hit's
 *   normal points out of the result (against the ray when it enters).
 * - Identities: a - a is empty, a & a is a, the union of solids apart is
 *   the solids.
 * - Materials and normals: a hole shows the subtracted solid's material,
 *   its normal turned into the hole.
 * - A mesh operand (crossed twice where a ray meets an edge), and one
 *   whose crossings along a ray outnumber what a solid reports at once.
 * - A glass lens made as the intersection of two spheres focuses parallel
 *   rays where the thick-lens formula says.
 * - Eight rays at once (csg8.h) against one at a time, to the bit: trees
 *   of convex leaves, of every solid, and with a mesh leaf that needs
 *   several rounds of crossings; and a tree past the table (its nodes
 *   evaluated) against the tabled tree it holds. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "accel/isa.h"
#include "core/array.h"
#include "geom/csg.h"
#include "geom/mesh.h"
#include "geom/polyhedron.h"
#include "shade/optics.h"
#include "shape_check.h"

/* ---- the oracle ---------------------------------------------------------- */

static bool inside_local(const shape *s, vec3 p)
{
    switch (s->kind) {
    case SHAPE_SPHERE:
        return v3_len2(v3_sub(p, s->sphere.center)) < s->sphere.radius * s->sphere.radius;
    case SHAPE_BOX:
        return p.x > s->box.lo.x && p.y > s->box.lo.y && p.z > s->box.lo.z &&
               p.x < s->box.hi.x && p.y < s->box.hi.y && p.z < s->box.hi.z;
    case SHAPE_CYLINDER: {
        vec3 q = v3_sub(p, s->cylinder.base);
        return q.y > 0 && q.y < s->cylinder.height &&
               q.x * q.x + q.z * q.z < s->cylinder.radius * s->cylinder.radius;
    }
    case SHAPE_CONE: {
        const struct cone *c = &s->cone;
        vec3 q = v3_sub(p, c->base);
        float r = c->radius + (c->top_radius - c->radius) * q.y / c->height;
        return q.y > 0 && q.y < c->height && q.x * q.x + q.z * q.z < r * r;
    }
    case SHAPE_TORUS: {
        vec3 q = v3_sub(p, s->torus.center);
        double rho = hypot(q.x, q.z) - s->torus.major;
        return rho * rho + (double)q.y * q.y < (double)s->torus.minor * s->torus.minor;
    }
    case SHAPE_POLYHEDRON:
        for (int f = 0; f < s->polyhedron->nfaces; f++)
            if (v3_dot(s->polyhedron->faces[f].n, p) >= s->polyhedron->faces[f].d)
                return false;
        return true;
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_TRIANGLE:
    case SHAPE_DISK:
    case SHAPE_MESH:
    case SHAPE_CSG:
    case SHAPE_COUNT:
        cr_assert_fail("no oracle for shape %d", s->kind);
    }
    return false;
}

static bool member(const csg *c, vec3 p)
{
    bool in[CSG_MAX_LEAVES];
    for (int i = 0; i < c->nleaves; i++) {
        const csg_leaf *l = &c->leaves[i];
        in[i] = inside_local(&l->shape, l->moved ? mat4_point(&l->x.inv, p) : p);
    }
    return csg_contains(c, in);
}

/* ---- random trees -------------------------------------------------------- */

typedef struct owned {
    polyhedron *poly[CSG_MAX_LEAVES];
    int n;
} owned;

static vec3 rand_vec(rng *g, float lo, float hi)
{
    return v3(lo + (hi - lo) * rng_float(g), lo + (hi - lo) * rng_float(g),
              lo + (hi - lo) * rng_float(g));
}

/* A solid of the first `kinds` of: sphere, box, cylinder (the kinds csg8
 * spans), cone, torus, polyhedron. */
static shape random_solid(rng *g, owned *own, unsigned kinds)
{
    vec3 c = rand_vec(g, -0.8f, 0.8f);
    float r = 0.4f + 0.8f * rng_float(g);
    switch (rng_u32(g) % kinds) {
    case 0:
        return shape_sphere(c, r);
    case 1:
        return shape_box(v3_sub(c, rand_vec(g, 0.2f, 1)), v3_add(c, rand_vec(g, 0.2f, 1)));
    case 2:
        return shape_cylinder(v3(c.x, c.y - r, c.z), 0.3f + 0.5f * rng_float(g), 2 * r, true);
    case 3:
        return shape_cone(v3(c.x, c.y - r, c.z), r, rng_float(g) < 0.5f ? 0 : 0.3f * r, 2 * r,
                          true);
    case 4:
        return shape_torus(c, r, r * (0.2f + 0.5f * rng_float(g)));
    default: {
        polyhedron *p = malloc(sizeof *p);
        poly_error why;
        cr_assert(polyhedron_preset(p, (poly_preset)(rng_u32(g) % POLY_PRESET_COUNT), c, r, &why));
        own->poly[own->n++] = p;
        return shape_polyhedron(p);
    }
    }
}

static xform random_xform(rng *g)
{
    xform r = xform_rotate(rng_unit_dir(g), 360 * rng_float(g));
    xform s = xform_scale(rand_vec(g, 0.6f, 1.4f));
    xform sh = xform_shear(0.4f * rng_float(g) - 0.2f, 0, 0, 0.4f * rng_float(g) - 0.2f, 0, 0);
    xform t = xform_then(&s, &sh);
    return xform_then(&t, &r);
}

static int32_t random_tree(csg *c, rng *g, owned *own, int depth)
{
    if (depth == 0 || (depth < 3 && rng_float(g) < 0.35f)) {
        shape s = random_solid(g, own, 6);
        xform x = random_xform(g);
        return csg_add_leaf(c, &s, rng_float(g) < 0.5f ? &x : NULL, c->nleaves);
    }
    int32_t kids[3];
    int n = 2 + (int)(rng_u32(g) % 2);
    for (int i = 0; i < n; i++)
        kids[i] = random_tree(c, g, own, depth - 1);
    return csg_add_node(c, (csg_op)(rng_u32(g) % CSG_OP_COUNT), kids, n);
}

static void free_owned(owned *own)
{
    for (int i = 0; i < own->n; i++) {
        polyhedron_free(own->poly[i]);
        free(own->poly[i]);
    }
    own->n = 0;
}

/* ---- the first change of membership along a ray --------------------------- */

static bool member_at(const csg *c, const ray *r, double t)
{
    return member(c, v3((float)(r->o.x + t * r->d.x), (float)(r->o.y + t * r->d.y),
                        (float)(r->o.z + t * r->d.z)));
}

/* The first t > t0 where membership differs from that just after t0, by
 * steps of h up to t1 and bisection; -1 when none is seen. */
static double first_change(const csg *c, const ray *r, double t0, double t1, double h)
{
    bool m0 = member_at(c, r, t0 + 1e-7);
    for (double a = t0 + 1e-7; a < t1; a += h) {
        double b = fmin(a + h, t1);
        if (member_at(c, r, b) == m0)
            continue;
        for (int i = 0; i < 60; i++) {
            double m = 0.5 * (a + b);
            if (member_at(c, r, m) == m0)
                a = m;
            else
                b = m;
        }
        return b;
    }
    return -1;
}

typedef struct csg_tally {
    int rays, hits, agree, thin;
} csg_tally;

/* The csg's first hit on r against the oracle. A hit before the oracle's
 * first change is fine only where membership really changes across it (a
 * feature thinner than the step). */
static void check_ray(const csg *c, ray r, csg_tally *tl, const char *what)
{
    shape s = shape_csg(c);
    shape_hit h;
    bool hit = shape_intersect(&s, &r, &h);
    cr_assert_eq(shape_occluded(&s, &r), hit, "%s: occluded disagrees", what);
    double len = v3_len(r.d), h_step = 0.003 / len;
    /* Membership changes only inside the bounds: step across them alone. */
    double t0 = 0, t1 = INFINITY;
    const float o[3] = {r.o.x, r.o.y, r.o.z}, d[3] = {r.d.x, r.d.y, r.d.z};
    const float lo[3] = {c->bounds.lo.x - 0.01f, c->bounds.lo.y - 0.01f, c->bounds.lo.z - 0.01f};
    const float hi[3] = {c->bounds.hi.x + 0.01f, c->bounds.hi.y + 0.01f, c->bounds.hi.z + 0.01f};
    for (int a = 0; a < 3; a++) {
        double ta = (lo[a] - o[a]) / (double)d[a], tb = (hi[a] - o[a]) / (double)d[a];
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    }
    double want = t0 < t1 ? first_change(c, &r, t0, t1, h_step) : -1;
    tl->rays++;
    tl->hits += hit;
    if (!hit) {
        cr_assert_lt(want, 0, "%s: the csg misses, but membership changes at t %g", what, want);
        tl->agree++;
        return;
    }
    double tol = 2e-4 / len;
    if (want >= 0 && fabs(h.t - want) <= tol) {
        tl->agree++;
    } else {
        cr_assert(want < 0 || h.t < want, "%s: hit at t %.7g, membership first changes at %.7g",
                  what, (double)h.t, want);
        /* A feature thinner than the step (a corner clipped by the ray over
         * 1e-5, say): membership must change across the hit at some scale. */
        bool changes = false;
        for (double e = 1e-4 / len; e > 1e-7 / len && !changes; e *= 0.1)
            changes = member_at(c, &r, h.t - e) != member_at(c, &r, h.t + e);
        cr_assert(changes, "%s: hit at t %.7g where membership does not change (first change "
                  "%.7g)", what, (double)h.t, want);
        tl->thin++;
    }
    /* The normal faces out of the result: against the ray where it enters. */
    surface sf;
    shape_surface(&s, &r, &h, &sf);
    bool entering = !member_at(c, &r, h.t - 1e-4 / len);
    float dn = v3_dot(sf.n, v3_norm(r.d));
    if (fabsf(dn) > 1e-2f)
        cr_assert_eq(dn < 0, entering, "%s: normal (%g %g %g) at t %g, entering %d", what,
                     (double)sf.n.x, (double)sf.n.y, (double)sf.n.z, (double)h.t, entering);
}

#if defined(__SANITIZE_ADDRESS__)
#define CSG_TREES 30 /* the sanitizers run some ten times slower */
#else
#define CSG_TREES 150
#endif

Test(csg, random_trees_agree_with_the_membership_oracle, .timeout = 300)
{
    rng g = rng_seed(99, 1);
    csg_tally tl = {0};
    int points = 0, inside = 0, tabled = 0;
    for (int tree = 0; tree < CSG_TREES; tree++) {
        csg c = {0};
        owned own = {.n = 0};
        random_tree(&c, &g, &own, 3);
        csg_finish(&c);
        tabled += c.nleaves <= CSG_TABLE_LEAVES;
        char what[64];
        for (int i = 0; i < 200; i++) {
            /* Points: csg_contains is the oracle's own evaluation, so this
             * checks the bounds: nothing inside lies outside them. */
            vec3 p = rand_vec(&g, -2.5f, 2.5f);
            bool m = member(&c, p);
            inside += m;
            points++;
            if (m)
                cr_assert(p.x >= c.bounds.lo.x && p.y >= c.bounds.lo.y && p.z >= c.bounds.lo.z &&
                              p.x <= c.bounds.hi.x && p.y <= c.bounds.hi.y && p.z <= c.bounds.hi.z,
                          "tree %d: a point inside lies outside the bounds", tree);
            /* Rays from anywhere around (many start inside operands or the
             * result), half aimed into the bounds, lengths not 1. */
            vec3 o = rand_vec(&g, -2.5f, 2.5f);
            vec3 d = i % 2 ? v3_sub(rand_in_box(&g, c.bounds), o) : rng_unit_dir(&g);
            d = v3_scale(v3_norm(d), 0.5f + rng_float(&g));
            snprintf(what, sizeof what, "tree %d ray %d", tree, i);
            check_ray(&c, ray_make(o, d, INFINITY), &tl, what);
        }
        csg_free(&c);
        free_owned(&own);
    }
    cr_log_info("csg: %d points (%d inside); %d rays, %d hits, %d agree, %d thin features",
                points, inside, tl.rays, tl.hits, tl.agree, tl.thin);
    cr_expect_gt(tl.hits, tl.rays / 8, "not vacuous");
    cr_expect_gt(inside, points / 200, "not vacuous");
    cr_expect_leq(tl.thin, tl.rays / 100);
    /* Both ways to the tree's answer are taken: its table and its nodes. */
    cr_expect_gt(tabled, CSG_TREES / 10, "%d of %d trees have a table", tabled, CSG_TREES);
    cr_expect_lt(tabled, CSG_TREES - CSG_TREES / 10, "%d of %d trees have a table", tabled,
                 CSG_TREES);
}

/* A small tree's table (csg_finish) holds the nodes' answer for every set
 * of leaves a point can be inside. */
Test(csg, table_is_the_tree_evaluated)
{
    rng g = rng_seed(7, 3);
    int checked = 0;
    for (int tree = 0; tree < 200; tree++) {
        csg c = {0};
        owned own = {.n = 0};
        random_tree(&c, &g, &own, 3);
        csg_finish(&c);
        if (c.nleaves <= CSG_TABLE_LEAVES) {
            for (unsigned st = 0; st < 1u << c.nleaves; st++) {
                bool in[CSG_TABLE_LEAVES];
                for (int i = 0; i < c.nleaves; i++)
                    in[i] = st >> i & 1;
                bool bit = c.table[st >> 6] >> (st & 63) & 1;
                cr_assert_eq(bit, csg_contains(&c, in), "tree %d, leaves inside %#x", tree, st);
            }
            checked++;
        } else {
            cr_assert(!c.table[0] && !c.table[1] && !c.table[2] && !c.table[3],
                      "tree %d: %d leaves, no table", tree, c.nleaves);
        }
        csg_free(&c);
        free_owned(&own);
    }
    cr_expect_gt(checked, 40);
}

/* ---- identities ----------------------------------------------------------- */

static csg two(shape a, shape b, csg_op op, const xform *xb)
{
    csg c = {0};
    int32_t k[2] = {csg_add_leaf(&c, &a, NULL, 0), csg_add_leaf(&c, &b, xb, 1)};
    csg_add_node(&c, op, k, 2);
    csg_finish(&c);
    return c;
}

static shape solids(int i, polyhedron **poly)
{
    switch (i) {
    case 0:
        return shape_sphere(v3(0.1f, 0, 0), 1);
    case 1:
        return shape_box(v3(-1, -0.5f, -0.8f), v3(0.9f, 1, 0.7f));
    case 2:
        return shape_cylinder(v3(0, -1, 0), 0.8f, 2, true);
    case 3:
        return shape_cone(v3(0, -1, 0), 1, 0.2f, 2, true);
    case 4:
        return shape_torus(v3(0, 0, 0), 0.9f, 0.35f);
    default: {
        *poly = malloc(sizeof **poly);
        poly_error why;
        cr_assert(polyhedron_preset(*poly, POLY_DODECAHEDRON, v3(0, 0.1f, 0), 1.1f, &why));
        return shape_polyhedron(*poly);
    }
    }
}

Test(csg, a_minus_a_is_empty_and_a_and_a_is_a)
{
    for (int k = 0; k < 6; k++) {
        polyhedron *poly = NULL;
        shape a = solids(k, &poly);
        csg diff = two(a, a, CSG_DIFFERENCE, NULL), both = two(a, a, CSG_INTERSECTION, NULL),
            uni = two(a, a, CSG_UNION, NULL);
        shape sd = shape_csg(&diff), sb = shape_csg(&both), su = shape_csg(&uni);
        rng g = rng_seed(7, (uint64_t)k);
        int hits = 0;
        for (int i = 0; i < 5000; i++) {
            vec3 o = rand_vec(&g, -2, 2);
            ray r = ray_make(o, v3_sub(rand_vec(&g, -0.7f, 0.7f), o), INFINITY);
            shape_hit h, ha, hb, hu;
            cr_assert_not(shape_intersect(&sd, &r, &h), "solid %d: a - a hit at t %g", k,
                          (double)h.t);
            bool in_a = shape_intersect(&a, &r, &ha);
            cr_assert_eq(shape_intersect(&sb, &r, &hb), in_a, "solid %d ray %d: a & a", k, i);
            cr_assert_eq(shape_intersect(&su, &r, &hu), in_a, "solid %d ray %d: a | a", k, i);
            if (!in_a)
                continue;
            hits++;
            ASSERT_NEAR(hb.t, ha.t, 1e-6 * (1 + ha.t));
            ASSERT_NEAR(hu.t, ha.t, 1e-6 * (1 + ha.t));
            surface s1, s2;
            shape_surface(&a, &r, &ha, &s1);
            shape_surface(&sb, &r, &hb, &s2);
            ASSERT_V3_NEAR(s2.n, s1.n.x, s1.n.y, s1.n.z, 1e-5);
        }
        cr_assert_gt(hits, 500);
        csg_free(&diff);
        csg_free(&both);
        csg_free(&uni);
        if (poly) {
            polyhedron_free(poly);
            free(poly);
        }
    }
}

Test(csg, union_of_solids_apart_is_the_solids)
{
    shape a = shape_torus(v3(-2, 0, 0), 0.8f, 0.3f), b = shape_sphere(v3(2, 0.2f, 0), 1);
    xform x = xform_rotate(v3(0, 0, 1), 30);
    csg u = two(a, b, CSG_UNION, &x);
    shape su = shape_csg(&u);
    scene *sb = one_object(b, &x);
    rng g = rng_seed(3, 3);
    for (int i = 0; i < 20000; i++) {
        vec3 o = rand_vec(&g, -4, 4);
        ray r = ray_make(o, v3_sub(rand_vec(&g, -3, 3), o), INFINITY);
        shape_hit h, ha;
        scene_hit hb;
        bool ia = shape_intersect(&a, &r, &ha), ib = scene_intersect(sb, &r, &hb);
        bool iu = shape_intersect(&su, &r, &h);
        cr_assert_eq(iu, ia || ib, "ray %d", i);
        if (iu)
            ASSERT_NEAR(h.t, fminf(ia ? ha.t : INFINITY, ib ? hb.h.t : INFINITY), 1e-5);
    }
    /* The union's bound is both; an intersection's the overlap, a
     * difference's the first operand's. */
    ASSERT_V3_NEAR(u.bounds.lo, -3.1, -0.3, -1.1, 1e-5);
    csg i2 = two(shape_box(v3(0, 0, 0), v3(2, 2, 2)), shape_box(v3(1, -1, 1), v3(3, 1, 3)),
                 CSG_INTERSECTION, NULL);
    ASSERT_V3_NEAR(i2.bounds.lo, 1, 0, 1, 0);
    ASSERT_V3_NEAR(i2.bounds.hi, 2, 1, 2, 0);
    csg d2 = two(shape_box(v3(0, 0, 0), v3(2, 2, 2)), shape_box(v3(1, -1, 1), v3(3, 1, 3)),
                 CSG_DIFFERENCE, NULL);
    ASSERT_V3_NEAR(d2.bounds.hi, 2, 2, 2, 0);
    csg_free(&u);
    csg_free(&i2);
    csg_free(&d2);
    scene_free(sb);
}

/* ---- materials and normals in a scene -------------------------------------- */

/* A box minus a sphere in a scene: looking into the hole, the surface is
 * the sphere's (material 1), its normal pointing into the hole; the
 * box's own faces keep material 0. */
Test(csg, a_hole_shows_the_subtracted_material_turned_inwards)
{
    scene *s = scene_new();
    material m = material_default();
    scene_add_material(s, &m);
    scene_add_material(s, &m);
    csg *c = calloc(1, sizeof *c);
    shape box = shape_box(v3(-1, -1, -1), v3(1, 1, 1)), ball = shape_sphere(v3(0, 0, 1), 0.6f);
    int32_t k[2] = {csg_add_leaf(c, &box, NULL, 0), csg_add_leaf(c, &ball, NULL, 1)};
    csg_add_node(c, CSG_DIFFERENCE, k, 2);
    csg_finish(c);
    cr_assert_geq(scene_add_csg(s, c), 0);
    shape sh = shape_csg(c);
    xform x = xform_translate(v3(0, 0, -5));
    cr_assert_geq(scene_add_object(s, &sh, -1, scene_add_xform(s, &x)), 0);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    ray r = ray_make(v3(0.1f, 0, 0), v3(0, 0, -1), INFINITY);
    scene_hit h;
    cr_assert(scene_intersect(s, &r, &h));
    ASSERT_NEAR(h.h.t, 4 + sqrt(0.35), 1e-5); /* the bottom of the hole, 0.1 off its axis */
    cr_assert_eq(scene_hit_material(s, &h), &s->materials[1]);
    surface sf;
    scene_surface(s, &r, &h, &sf);
    vec3 into = v3_norm(v3_sub(v3(0, 0, -4), sf.p));
    ASSERT_V3_NEAR(sf.n, into.x, into.y, into.z, 1e-5);
    r = ray_make(v3(0.8f, 0.8f, 0), v3(0, 0, -1), INFINITY);
    cr_assert(scene_intersect(s, &r, &h));
    ASSERT_NEAR(h.h.t, 4, 1e-5);
    cr_assert_eq(scene_hit_material(s, &h), &s->materials[0]);
    scene_surface(s, &r, &h, &sf);
    ASSERT_V3_NEAR(sf.n, 0, 0, 1, 1e-6);
    scene_free(s);
}

/* ---- meshes as operands ------------------------------------------------------ */

/* A mesh of n unit cubes [-1, 1]^3 moved 3 apart along x, triangulated. */
static mesh *cubes(int n)
{
    polyhedron cube;
    poly_error why;
    cr_assert(polyhedron_preset(&cube, POLY_CUBE, v3(0, 0, 0), sqrtf(3), &why));
    mesh *m = calloc(1, sizeof *m);
    m->nverts = 8 * n;
    m->ntris = cube.ntris * n;
    m->pos = malloc(sizeof *m->pos * (size_t)m->nverts);
    m->tri = malloc(sizeof *m->tri * (size_t)m->ntris);
    for (int k = 0; k < n; k++) {
        for (int i = 0; i < 8; i++)
            m->pos[8 * k + i] = v3_add(cube.verts[i], v3(3.0f * k, 0, 0));
        for (int t = 0; t < cube.ntris; t++)
            for (int j = 0; j < 3; j++)
                m->tri[k * cube.ntris + t][j] = cube.tri[t][j] + 8u * (unsigned)k;
    }
    polyhedron_free(&cube);
    glint_error err = {0};
    cr_assert_eq(mesh_init(m, "cubes", 0, NULL, &err), GLINT_OK, "%s", err.msg);
    return m;
}

/* Five cubes in a row give ten crossings along the row, more than a solid
 * reports at once: intersected with a slab round the last cube, the hit is
 * the last cube's face. Rays through the cubes' diagonals (where two
 * triangles report the same crossing) agree with the box oracle. */
Test(csg, mesh_operands_and_many_crossings)
{
    mesh *m = cubes(5);
    shape sm = shape_mesh(m);
    csg c = two(sm, shape_box(v3(10.5f, -2, -2), v3(14, 2, 2)), CSG_INTERSECTION, NULL);
    shape s = shape_csg(&c);
    shape_hit h;
    ray r = ray_make(v3(-5, 0.25f, 0.1f), v3(1, 0, 0), INFINITY);
    cr_assert(shape_intersect(&s, &r, &h));
    ASSERT_NEAR(h.t, 16, 1e-5); /* x = 11, the fifth cube's near face */
    r = ray_make(v3(-5, 0, 0), v3(1, 0, 0), INFINITY); /* along edges and diagonals */
    cr_assert(shape_intersect(&s, &r, &h));
    ASSERT_NEAR(h.t, 16, 1e-5);
    /* A mesh cube minus a sphere: the oracle is the box minus the ball. */
    csg d = two(sm, shape_sphere(v3(0, 0, 1), 0.7f), CSG_DIFFERENCE, NULL);
    shape sd = shape_csg(&d);
    rng g = rng_seed(11, 1);
    for (int i = 0; i < 20000; i++) {
        /* Through the diagonal of a face (where the face's two triangles
         * meet) from anywhere, or from inside out through an edge. */
        float u = 1.8f * rng_float(&g) - 0.9f, side = rng_float(&g) < 0.5f ? -1.0f : 1.0f;
        float at[3];
        int k = (int)(rng_u32(&g) % 3);
        vec3 o;
        if (i % 2) {
            at[k] = side, at[(k + 1) % 3] = u, at[(k + 2) % 3] = rng_float(&g) < 0.5f ? u : -u;
            o = rand_vec(&g, -2, 2);
        } else {
            at[k] = side, at[(k + 2) % 3] = u;
            at[(k + 1) % 3] = rng_float(&g) < 0.5f ? -1.0f : 1.0f;
            o = rand_vec(&g, -0.95f, 0.95f);
        }
        vec3 aim = v3(at[0], at[1], at[2]);
        ray q = ray_make(o, v3_sub(aim, o), INFINITY);
        bool hit = shape_intersect(&sd, &q, &h);
        double want = -1;
        for (double t = 1e-6; t < 8; t += 5e-4) {
            vec3 p = ray_at(&q, (float)t);
            bool in = fabsf(p.x) < 1 && fabsf(p.y) < 1 && fabsf(p.z) < 1 &&
                      v3_len2(v3_sub(p, v3(0, 0, 1))) >= 0.49f;
            vec3 p0 = ray_at(&q, 1e-6f);
            bool in0 = fabsf(p0.x) < 1 && fabsf(p0.y) < 1 && fabsf(p0.z) < 1 &&
                       v3_len2(v3_sub(p0, v3(0, 0, 1))) >= 0.49f;
            if (in != in0) {
                want = t;
                break;
            }
        }
        cr_assert_eq(hit, want >= 0, "ray %d (o %.9g %.9g %.9g d %.9g %.9g %.9g): hit %d, "
                     "membership change at %g", i, (double)q.o.x, (double)q.o.y, (double)q.o.z,
                     (double)q.d.x, (double)q.d.y, (double)q.d.z, hit, want);
        if (hit)
            cr_assert(fabs(h.t - want) < 2e-3, "ray %d: t %g, oracle %g", i, (double)h.t, want);
    }
    csg_free(&c);
    csg_free(&d);
    mesh_free(m);
    free(m);
}

/* ---- a glass lens ----------------------------------------------------------- */

/* A biconvex lens, the intersection of two spheres of radius R whose
 * centres are 2R - d apart (thickness d), ior n, axis z. Rays parallel to
 * the axis at small heights are refracted in and out (as whitted_trace
 * does: the side from the geometric normal, Snell's law) and must cross the
 * axis at the back focal distance of the thick-lens formula:
 *   1/f = (n - 1) (2/R - (n - 1) d / (n R^2)),  BFD = f (1 - (n - 1) d / (n R)). */
Test(csg, glass_lens_focuses_like_a_lens)
{
    const float R = 5, d = 1, n = 1.5f;
    csg c = two(shape_sphere(v3(0, 0, R - d / 2), R), shape_sphere(v3(0, 0, -(R - d / 2)), R),
                CSG_INTERSECTION, NULL);
    scene *s = scene_new();
    material glass = material_default();
    glass.transmit = 1;
    glass.ior = n;
    scene_add_material(s, &glass);
    c.leaves[1].material = 0;
    csg *owned_c = malloc(sizeof *owned_c);
    *owned_c = c;
    scene_add_csg(s, owned_c);
    shape sh = shape_csg(owned_c);
    scene_add_object(s, &sh, -1, -1);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    double f = 1 / ((n - 1) * (2 / R - (n - 1) * d / (n * R * R)));
    double bfd = f * (1 - (n - 1) * d / (n * R));
    for (int i = 1; i <= 5; i++) {
        float y = 0.02f * (float)i;
        ray r = ray_make(v3(0, y, 10), v3(0, 0, -1), INFINITY);
        for (int k = 0; k < 2; k++) {
            scene_hit h;
            cr_assert(scene_intersect(s, &r, &h), "height %g crossing %d", (double)y, k);
            surface sf;
            scene_surface(s, &r, &h, &sf);
            bool inside = v3_dot(r.d, sf.ng) > 0;
            cr_assert_eq(inside, k == 1, "the first crossing enters, the second leaves");
            vec3 nn = inside ? v3_neg(sf.n) : sf.n, t = v3s(0);
            cr_assert(optics_refract(r.d, nn, inside ? n : 1 / n, &t));
            r = ray_make(ray_offset(sf.p, inside ? v3_neg(sf.ng) : sf.ng, t), t, INFINITY);
        }
        /* Where it meets the axis (y = 0), measured from the back surface at z = -d/2. */
        double tz = -r.o.y / r.d.y, z = r.o.z + tz * r.d.z;
        ASSERT_NEAR(-d / 2 - z, bfd, 0.01 * bfd);
    }
    scene_free(s);
}

/* ---- eight rays at once (csg8.h) ------------------------------------------ */

/* A random tree of solids of the first `kinds` of random_solid, half of
 * them moved (turned, stretched, sheared and shifted), about one in four
 * a copy of an earlier leaf (operands that share a surface, crossed at
 * the same t). */
static int32_t packet_tree(csg *c, rng *g, owned *own, int depth, unsigned kinds)
{
    if (depth == 0 || (depth < 3 && rng_float(g) < 0.35f)) {
        if (c->nleaves > 0 && rng_float(g) < 0.25f) {
            csg_leaf l = c->leaves[rng_u32(g) % (unsigned)c->nleaves];
            return csg_add_leaf(c, &l.shape, l.moved ? &l.x : NULL, c->nleaves);
        }
        shape s = random_solid(g, own, kinds);
        xform x = random_xform(g), t = xform_translate(rand_vec(g, -0.5f, 0.5f));
        x = xform_then(&x, &t);
        return csg_add_leaf(c, &s, rng_float(g) < 0.5f ? &x : NULL, c->nleaves);
    }
    int32_t kids[3];
    int n = 2 + (int)(rng_u32(g) % 2);
    for (int i = 0; i < n; i++)
        kids[i] = packet_tree(c, g, own, depth - 1, kinds);
    return csg_add_node(c, (csg_op)(rng_u32(g) % CSG_OP_COUNT), kids, n);
}

/* One ray of a packet: from one point into the bounds (coherent), from
 * inside the bounds (inside operands), along an axis from a leaf's
 * bounds' coordinates (grazing a box's faces, direction 0 on two axes), or
 * anywhere; ranges from 0 or a little more, some of them short. */
static ray packet_ray(rng *g, const csg *c, int i, int k, vec3 eye)
{
    vec3 o, d;
    switch (i % 4) {
    case 0:
        o = v3_add(eye, rand_vec(g, -0.05f, 0.05f));
        d = v3_sub(rand_in_box(g, c->bounds), o);
        break;
    case 1:
        o = rand_in_box(g, c->bounds);
        d = rng_unit_dir(g);
        break;
    case 2: {
        aabb b = c->leaves[rng_u32(g) % (unsigned)c->nleaves].bounds;
        float at[3][3] = {{b.lo.x, b.hi.x, 0.5f * (b.lo.x + b.hi.x)},
                          {b.lo.y, b.hi.y, 0.5f * (b.lo.y + b.hi.y)},
                          {b.lo.z, b.hi.z, 0.5f * (b.lo.z + b.hi.z)}};
        float q[3], e[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++)
            q[a] = at[a][rng_u32(g) % 3];
        int axis = (int)(rng_u32(g) % 3);
        e[axis] = k % 2 ? 1.0f : -1.0f;
        q[axis] = -3.0f * e[axis];
        o = v3(q[0], q[1], q[2]);
        d = v3(e[0], e[1], e[2]);
        break;
    }
    default:
        o = rand_vec(g, -2.5f, 2.5f);
        d = rng_unit_dir(g);
        break;
    }
    d = v3_scale(d, (0.5f + rng_float(g)) / fmaxf(v3_len(d), 1e-6f));
    ray r = ray_make(o, d, k % 3 == 0 ? 0.5f + 3.0f * rng_float(g) : INFINITY);
    r.tmin = i % 3 == 0 ? 0.0f : 1e-3f * rng_float(g);
    return r;
}

typedef int (*csg8_hit_fn)(const csg *, const ray8 *, int, shape_hit *);
typedef int (*csg8_occluded_fn)(const csg *, const ray8 *, int);

/* The eight-wide kernels this CPU runs: how many, into hit and occluded. */
static int csg8_kernels(csg8_hit_fn hit[2], csg8_occluded_fn occluded[2])
{
    int n = 0;
#if defined(GLINT_WIDE_KERNELS)
    if (accel_isa_best() >= ACCEL_AVX2)
        hit[n] = csg8_hit_avx2, occluded[n++] = csg8_occluded_avx2;
    if (accel_isa_best() >= ACCEL_AVX512)
        hit[n] = csg8_hit_avx512, occluded[n++] = csg8_occluded_avx512;
#endif
    (void)hit, (void)occluded;
    return n;
}

typedef struct csg8_tally {
    int rays, hits, blocked, fallback; /* fallback: hits on a leaf not spanned at once */
} csg8_tally;

/* Packet p (rays of active; the idle lanes hold NaN) on every kernel
 * against csg_intersect and shape_occluded one ray at a time: the same
 * rays hit and blocked, the same hits to the bit. */
static void csg8_same(const csg *c, const ray8 *p, int active, csg8_tally *tl, const char *what)
{
    csg8_hit_fn hit[2];
    csg8_occluded_fn occluded[2];
    int kernels = csg8_kernels(hit, occluded);
    shape sh = shape_csg(c);
    for (int q = 0; q < kernels; q++) {
        shape_hit h[8];
        memset(h, 0xa5, sizeof h);
        int found = hit[q](c, p, active, h), blocked = occluded[q](c, p, active);
        cr_assert_eq(found & ~active, 0, "%s: an idle lane hit", what);
        for (int k = 0; k < 8; k++) {
            if (!(active >> k & 1))
                continue;
            ray r = ray8_get(p, k);
            shape_hit want = {0};
            bool w = csg_intersect(c, &r, &want);
            cr_assert_eq(found >> k & 1, w, "%s kernel %d ray %d: hit %d", what, q, k, w);
            cr_assert_eq(blocked >> k & 1, shape_occluded(&sh, &r), "%s kernel %d ray %d", what,
                         q, k);
            tl->rays++;
            tl->blocked += blocked >> k & 1;
            if (!w)
                continue;
            cr_assert(!memcmp(&h[k], &want, sizeof want),
                      "%s kernel %d ray %d: t %a part %d leaf %d, one ray: t %a part %d leaf %d",
                      what, q, k, (double)h[k].t, h[k].part, h[k].leaf, (double)want.t, want.part,
                      want.leaf);
            shape_kind kind = c->leaves[want.leaf].shape.kind;
            tl->hits++;
            tl->fallback += kind != SHAPE_SPHERE && kind != SHAPE_BOX && kind != SHAPE_CYLINDER;
        }
    }
}

/* Random trees of the first `kinds` solids against packets of every kind
 * of packet_ray, some partly idle. */
static csg8_tally csg8_trees(unsigned kinds, uint64_t seed, int trees)
{
    rng g = rng_seed(seed, 4);
    csg8_tally tl = {0};
    for (int tree = 0; tree < trees; tree++) {
        csg c = {0};
        owned own = {.n = 0};
        packet_tree(&c, &g, &own, 3, kinds);
        csg_finish(&c);
        for (int i = 0; i < 40; i++) {
            ray8 p;
            vec3 eye = rand_vec(&g, -3.0f, 3.0f);
            int active = i % 5 == 0 ? 0x5b : i % 7 == 0 ? 0x80 : 0xff;
            for (int k = 0; k < 8; k++) {
                ray r = packet_ray(&g, &c, i, k, eye);
                if (!(active >> k & 1))
                    r.o = r.d = v3s(NAN);
                ray8_put(&p, k, &r);
            }
            char what[64];
            snprintf(what, sizeof what, "tree %d packet %d", tree, i);
            csg8_same(&c, &p, active, &tl, what);
        }
        csg_free(&c);
        free_owned(&own);
    }
    return tl;
}

/* Trees of spheres, boxes and cylinders, whose spans csg8 finds for the
 * eight rays at once. */
Test(csg, eight_rays_match_one_at_a_time_for_convex_leaves)
{
    csg8_tally tl = csg8_trees(3, 11, CSG_TREES);
    if (accel_isa_best() < ACCEL_AVX2)
        return;
    cr_log_info("csg8: %d rays, %d hits, %d blocked", tl.rays, tl.hits, tl.blocked);
    cr_assert_gt(tl.hits, tl.rays / 8, "not vacuous: %d hits of %d rays", tl.hits, tl.rays);
    cr_assert_eq(tl.blocked, tl.hits);
}

/* Trees with cones, tori and polyhedra too, which each ray asks for
 * their crossings (shape_crossings) in the first round as in every other. */
Test(csg, eight_rays_match_one_at_a_time_with_other_leaves)
{
    csg8_tally tl = csg8_trees(6, 12, CSG_TREES);
    if (accel_isa_best() < ACCEL_AVX2)
        return;
    cr_log_info("csg8: %d rays, %d hits (%d on other leaves)", tl.rays, tl.hits, tl.fallback);
    cr_assert_gt(tl.hits, tl.rays / 8, "not vacuous: %d hits of %d rays", tl.hits, tl.rays);
    cr_assert_gt(tl.fallback, tl.hits / 4, "other leaves hit: %d of %d", tl.fallback, tl.hits);
}

/* Rays no render makes, taken at once as one at a time all the same: one
 * starting before 0 (tmin -0.5), whose crossings at t = 0 are a box's
 * exit at -0 and another's entry at +0, the second the one that changes
 * the answer (the hit's t is its own +0); and one whose tmax is NaN,
 * which one ray at a time never stops at. */
Test(csg, eight_rays_match_one_at_a_time_at_signed_zeros_and_a_nan_tmax)
{
    csg c = {0};
    shape x = shape_box(v3(0, -5, 0), v3(1, 5, 1)), y = shape_box(v3(-5, 0, 0), v3(5, 1, 1)),
          z = shape_box(v3(10, 10, 10), v3(11, 11, 11));
    /* leaves 0, 1, 2 in that order (one call a statement: the calls in an
     * initializer list may run in any order) */
    int32_t lx = csg_add_leaf(&c, &x, NULL, 0), ly = csg_add_leaf(&c, &y, NULL, 1);
    int32_t lz = csg_add_leaf(&c, &z, NULL, 2);
    int32_t xz[2] = {lx, lz};
    int32_t u[2] = {ly, csg_add_node(&c, CSG_INTERSECTION, xz, 2)}; /* y | (x & z) */
    csg_add_node(&c, CSG_UNION, u, 2);
    csg_finish(&c);
    ray8 p;
    for (int k = 0; k < 8; k++) {
        ray r = ray_make(v3(0, 0, 0.5f), v3(-1, 1, 0), k < 4 ? INFINITY : NAN);
        r.tmin = k < 4 ? -0.5f : 0.0f;
        if (k >= 4)
            r.o = v3(0.5f, -3, 0.5f), r.d = v3(0, 1, 0);
        ray8_put(&p, k, &r);
    }
    csg8_tally tl = {0};
    csg8_same(&c, &p, 0xff, &tl, "signed zeros and NaN");
    ray one = ray8_get(&p, 0);
    shape_hit h;
    cr_assert(csg_intersect(&c, &one, &h));
    cr_assert(h.t == 0.0f && !signbit(h.t) && h.leaf == 1, "t %a leaf %d", (double)h.t, h.leaf);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert_eq(tl.hits, 8 * csg8_kernels((csg8_hit_fn[2]){0}, (csg8_occluded_fn[2]){0}));
    csg_free(&c);
}

/* A ray of a packet along a row of cubes laid along x up to the origin
 * (rows_tree): from before the row, or from inside one of its cubes,
 * nearly along +x; some through the middle of the faces (where a face's
 * two triangles meet), some ranges short. */
static ray row_ray(rng *g, int i, int k)
{
    float y = 1.2f * (2 * rng_float(g) - 1), z = 1.2f * (2 * rng_float(g) - 1);
    if (k % 4 == 0)
        y = z = 0;
    vec3 o = v3(i % 2 ? -16.0f : -12.0f + 3.0f * (float)(rng_u32(g) % 4), y, z);
    vec3 d = v3_norm(v3(1, 0.02f * (2 * rng_float(g) - 1), 0.02f * (2 * rng_float(g) - 1)));
    ray r = ray_make(o, v3_scale(d, 0.5f + rng_float(g)), k % 3 == 0 ? 10 + 20 * rng_float(g)
                                                                      : INFINITY);
    r.tmin = i % 3 == 0 ? 0.0f : 1e-3f * rng_float(g);
    return r;
}

/* Leaf 0 is a row of five mesh cubes along x, the last round the origin,
 * operand of a random tree of the other solids round the origin: a ray
 * along the row crosses the mesh ten times, more than a leaf reports at
 * once, before it reaches the rest. */
static int32_t rows_tree(csg *c, rng *g, owned *own, const mesh *row)
{
    shape s = shape_mesh(row);
    xform x = xform_translate(v3(-12, 0, 0));
    int32_t kids[2] = {csg_add_leaf(c, &s, &x, 0), packet_tree(c, g, own, 2, 6)};
    /* Intersections most often: they are hit past the first round. */
    csg_op op = rng_u32(g) % 3 ? CSG_INTERSECTION : (csg_op)(rng_u32(g) % CSG_OP_COUNT);
    return csg_add_node(c, op, kids, 2);
}

/* Whether the hit h on r lies past the crossings the row (leaf 0, the
 * one leaf with more than it reports at once) reports from r's start:
 * found in a later round than the first. */
static bool past_first_round(const csg *c, const ray *r, const shape_hit *h)
{
    const csg_leaf *l = &c->leaves[0];
    ray lr = mat4_ray(&l->x.inv, r);
    lr.time = 0;
    crossing x[CSG_LEAF_CROSSINGS];
    bool more;
    int n = shape_crossings(&l->shape, &lr, x, CSG_LEAF_CROSSINGS, &more);
    return more && h->t > x[n - 1].h.t;
}

/* Trees with a mesh leaf that needs several rounds of crossings: the
 * packet's first round reads the other leaves' spans from csg8.h and
 * asks the mesh, its later rounds ask every leaf, and each ray's hit is
 * the one ray's to the bit. */
Test(csg, eight_rays_match_one_at_a_time_over_several_rounds)
{
    mesh *row = cubes(5);
    rng g = rng_seed(13, 4);
    csg8_tally tl = {0};
    int later = 0;
    for (int tree = 0; tree < 40; tree++) {
        csg c = {0};
        owned own = {.n = 0};
        rows_tree(&c, &g, &own, row);
        csg_finish(&c);
        for (int i = 0; i < 40; i++) {
            ray8 p;
            int active = i % 5 == 0 ? 0x6d : 0xff;
            for (int k = 0; k < 8; k++) {
                ray r = row_ray(&g, i, k);
                if (!(active >> k & 1))
                    r.o = r.d = v3s(NAN);
                ray8_put(&p, k, &r);
                shape_hit h;
                if (active >> k & 1 && csg_intersect(&c, &r, &h))
                    later += past_first_round(&c, &r, &h);
            }
            char what[64];
            snprintf(what, sizeof what, "tree %d packet %d", tree, i);
            csg8_same(&c, &p, active, &tl, what);
        }
        csg_free(&c);
        free_owned(&own);
    }
    mesh_free(row);
    free(row);
    cr_log_info("csg8 over rounds: %d rays, %d hits, %d after the first round", tl.rays,
                tl.hits, later);
    cr_assert_gt(later, 200, "hits found in a later round: %d", later);
    if (accel_isa_best() >= ACCEL_AVX2)
        cr_assert_gt(tl.hits, tl.rays / 8, "not vacuous: %d hits of %d rays", tl.hits, tl.rays);
}

/* A tree of at most CSG_TABLE_LEAVES leaves, whose answers come from its
 * table, and the same tree less nine small balls far away, which takes
 * it past the table (its nodes are evaluated) without changing the solid:
 * every ray's hit is the same to the bit, one ray at a time and eight. */
Test(csg, trees_past_the_table_classify_as_their_tabled_core)
{
    rng g = rng_seed(14, 4);
    csg8_tally tl = {0};
    int trees = 0, rays = 0, hits = 0;
    while (trees < 60) {
        csg a = {0}, b = {0};
        owned own_a = {.n = 0}, own_b = {.n = 0};
        rng same = g;
        packet_tree(&a, &g, &own_a, 3, 6);
        int32_t kids[10] = {packet_tree(&b, &same, &own_b, 3, 6)};
        for (int i = 1; i < 10; i++) {
            shape ball = shape_sphere(v3(40.0f + 3.0f * (float)i, 40, 40), 1);
            kids[i] = csg_add_leaf(&b, &ball, NULL, b.nleaves);
        }
        csg_add_node(&b, CSG_DIFFERENCE, kids, 10);
        csg_finish(&a);
        csg_finish(&b);
        cr_assert_gt(b.nleaves, CSG_TABLE_LEAVES);
        if (a.nleaves <= CSG_TABLE_LEAVES) {
            trees++;
            for (int i = 0; i < 40; i++) {
                ray8 p;
                vec3 eye = rand_vec(&g, -3.0f, 3.0f);
                for (int k = 0; k < 8; k++) {
                    ray r = packet_ray(&g, &a, i, k, eye);
                    ray8_put(&p, k, &r);
                    shape_hit ha = {0}, hb = {0};
                    bool wa = csg_intersect(&a, &r, &ha), wb = csg_intersect(&b, &r, &hb);
                    cr_assert_eq(wa, wb, "tree %d ray %d: hit %d, past the table %d", trees,
                                 8 * i + k, wa, wb);
                    cr_assert(!memcmp(&ha, &hb, sizeof ha), "tree %d ray %d: t %a leaf %d, "
                              "past the table t %a leaf %d", trees, 8 * i + k, (double)ha.t,
                              ha.leaf, (double)hb.t, hb.leaf);
                    rays++;
                    hits += wa;
                }
                csg8_same(&b, &p, 0xff, &tl, "past the table");
            }
        }
        csg_free(&a);
        csg_free(&b);
        free_owned(&own_a);
        free_owned(&own_b);
    }
    cr_log_info("tabled cores: %d rays, %d hits", rays, hits);
    cr_assert_gt(hits, rays / 8, "not vacuous: %d hits of %d rays", hits, rays);
}

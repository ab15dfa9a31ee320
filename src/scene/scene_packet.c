/* scene_intersect8: eight rays' nearest hits at once. The unbounded
 * objects and a flat scene's one leaf are tested object by object; on the
 * eight-wide paths a deeper tree is walked by the eight rays together
 * (scene_walk8, when their directions' signs agree), each leaf's objects
 * tested against the rays that enter it. An object is tested against the
 * rays at once where it can be: a mesh in one walk of its tree
 * (mesh_intersect8), a sphere, quad, plane or box in one test
 * (shape8_hit), a torus's setup in one (torus8_hit) and its roots ray by
 * ray, a csg's leaves' bounds and convex spans in one (csg8_hit) and its
 * classification ray by ray; any other ray by ray. Otherwise each ray goes
 * through scene_intersect. Either way every ray gets the hit
 * scene_intersect gives it, to the bit.
 *
 * scene_shadow8 walks eight shadow rays the same way, asking each object
 * the question scene_shadow asks it: whether an opaque one blocks a ray,
 * whether a transmitting one is crossed (a shape not tested eight at once
 * is left to the crossings' search). scene_shadow_unblocked8 then finds
 * the crossings of the rays nothing blocks, eight at a time. */
#include <string.h>
#include "geom/csg.h"
#include "geom/mesh.h"
#include "scene_packet8.h"

/* Object i's hits h[k] for the rays of `any`, kept by scene_hit_object's
 * rule; returns the rays whose hit it is now. */
static int keep8(int i, int any, const shape_hit h[8], float best[8], scene_hit hit[8])
{
    int found = 0;
    for (int m = any; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        if (h[k].t < best[k] || (h[k].t == best[k] && i < hit[k].object)) {
            best[k] = h[k].t;
            hit[k] = (scene_hit){h[k], i};
            found |= 1 << k;
        }
    }
    return found;
}

/* shape8_hit on the scene's path; -1 where it has none. */
static int shape8_on_path(const scene *s, const shape *sh, const ray8 *r, const float *best,
                          int active, shape_hits8 *out, int *nearer)
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return shape8_hit_avx512(sh, r, best, active, out, nearer);
    if (s->bvh.isa == ACCEL_AVX2)
        return shape8_hit_avx2(sh, r, best, active, out, nearer);
#endif
    (void)s, (void)sh, (void)r, (void)best, (void)active, (void)out, (void)nearer;
    return -1;
}

/* torus8_hit on the scene's path; -1 where it has none. */
static int torus8_on_path(const scene *s, const struct torus *t, const ray8 *r, int active,
                          shape_hit h[8])
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return torus8_hit_avx512(t, r, active, h);
    if (s->bvh.isa == ACCEL_AVX2)
        return torus8_hit_avx2(t, r, active, h);
#endif
    (void)s, (void)t, (void)r, (void)active, (void)h;
    return -1;
}

/* torus8_occluded on the scene's path; -1 where it has none. */
static int torus8_occluded_on_path(const scene *s, const struct torus *t, const ray8 *r,
                                   int active)
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return torus8_occluded_avx512(t, r, active);
    if (s->bvh.isa == ACCEL_AVX2)
        return torus8_occluded_avx2(t, r, active);
#endif
    (void)s, (void)t, (void)r, (void)active;
    return -1;
}

/* csg8_hit on the scene's path; -1 where it has none. */
static int csg8_on_path(const scene *s, const struct csg *c, const ray8 *r, int active,
                        shape_hit h[8])
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return csg8_hit_avx512(c, r, active, h);
    if (s->bvh.isa == ACCEL_AVX2)
        return csg8_hit_avx2(c, r, active, h);
#endif
    (void)s, (void)c, (void)r, (void)active, (void)h;
    return -1;
}

/* csg8_occluded on the scene's path; -1 where it has none. */
static int csg8_occluded_on_path(const scene *s, const struct csg *c, const ray8 *r, int active)
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return csg8_occluded_avx512(c, r, active);
    if (s->bvh.isa == ACCEL_AVX2)
        return csg8_occluded_avx2(c, r, active);
#endif
    (void)s, (void)c, (void)r, (void)active;
    return -1;
}

/* The rays of active in object o's space, each searched up to best[k] (as
 * scene_hit_object searches them; best NULL: as far as it goes already);
 * idle lanes repeat an active ray. */
static void object_rays(const scene *s, const object *o, const ray8 *r, int active,
                        const float *best, ray8 *lr)
{
#if defined(GLINT_WIDE_KERNELS)
    const mat4 *inv = o->xform >= 0 ? &s->xforms[o->xform].inv : NULL;
    if (s->bvh.isa == ACCEL_AVX512) {
        scene_object_rays8_avx512(inv, r, active, best, lr);
        return;
    }
    if (s->bvh.isa == ACCEL_AVX2) {
        scene_object_rays8_avx2(inv, r, active, best, lr);
        return;
    }
#endif
    ray in[8];
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        if (best)
            one.tmax = next_up(best[k]);
        in[k] = scene_object_ray(s, o, &one);
    }
    ray8_pack(lr, in, active);
}

/* Whether object o is tested against three or more of a packet's rays at
 * once (in its own space when it is turned): a mesh in one walk of its
 * tree, a torus's setup in one test, a csg's bounds and spans in one
 * (csg8_hit), the shapes of shape_tests_eight in one test. A moving one
 * is not: its rays differ in their transforms. */
static bool tests_eight(const object *o)
{
    shape_kind k = o->shape.kind;
    return !o->moving &&
           (k == SHAPE_MESH || k == SHAPE_TORUS || k == SHAPE_CSG || shape_tests_eight(k));
}

/* The test of a mesh, torus or csg against the rays of active (in its
 * space, each up to its best): the rays hit, with their hits in h; -1
 * where the path has no such test. */
static int packet_solid(const scene *s, const shape *sh, const ray8 *q, int active,
                        shape_hit h[8])
{
    if (sh->kind == SHAPE_MESH)
        return mesh_intersect8(sh->mesh, q, active, h);
    if (sh->kind == SHAPE_CSG)
        return csg8_on_path(s, sh->csg, q, active, h);
    return torus8_on_path(s, &sh->torus, q, active, h);
}

/* Whether a packet's rays of `active` meet object o together rather than
 * ray by ray: three or more, or any number for a torus, whose packet test
 * also searches its lanes' roots together (geom/torus8.h), which one ray's
 * test at a time does not make up for. */
static bool packet_worth(const object *o, int active)
{
    return ray8_three_or_more(active) || o->shape.kind == SHAPE_TORUS;
}

/* Object i against the rays of active, each searched up to best[k]: at
 * once where tests_eight and packet_worth say so, else ray by ray. */
int scene_packet_object(const scene *s, int i, const ray8 *r, int active, float best[8],
                        scene_hit hit[8])
{
    const object *o = &s->objects[i];
    int found = 0;
    if (packet_worth(o, active) && tests_eight(o)) {
        shape_kind kind = o->shape.kind;
        ray8 lr;
        const ray8 *q = r;
        if (!shape_tests_eight(kind) || o->xform >= 0) {
            object_rays(s, o, r, active, best, &lr);
            q = &lr;
        }
        if (shape_tests_eight(kind)) {
            shape_hits8 h;
            int nearer = 0, any = shape8_on_path(s, &o->shape, q, best, active, &h, &nearer);
            if (any >= 0)
                return keep_hits8(i, any, nearer, &h, best, hit);
        } else {
            shape_hit h[8];
            int any = packet_solid(s, &o->shape, q, active, h);
            if (any >= 0)
                return keep8(i, any, h, best, hit);
        }
    }
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        if (scene_hit_object(s, i, &one, one.tmin, &best[k], &hit[k]))
            found |= 1 << k;
    }
    return found;
}

/* scene_walk8 on the scene's path, culling nodes' children for the whole
 * packet in a tree of more than one node; -1 where the path has none. */
static int walk8(const scene *s, const ray8 *r, int active, float best[8], scene_hit hit[8])
{
#if defined(GLINT_WIDE_KERNELS)
    bool deep = s->bvh.nnodes > 1;
    if (s->bvh.isa == ACCEL_AVX512)
        return (deep ? scene_walk8_culled_avx512 : scene_walk8_avx512)(s, r, active, best, hit);
    if (s->bvh.isa == ACCEL_AVX2)
        return (deep ? scene_walk8_culled_avx2 : scene_walk8_avx2)(s, r, active, best, hit);
#endif
    (void)s, (void)r, (void)active, (void)best, (void)hit;
    return -1;
}

static bool eight_wide(accel_isa isa) { return isa == ACCEL_AVX2 || isa == ACCEL_AVX512; }

/* Whether object o can be tested against a packet's rays at once. */
static bool packs(const scene *s, const object *o)
{
    if (o->shape.kind == SHAPE_MESH)
        return !o->moving && eight_wide(o->shape.mesh->bvh.isa);
    return !o->moving && shape_tests_eight(o->shape.kind) && eight_wide(s->bvh.isa);
}

bool scene_packets_pay(const scene *s)
{
    if (!s->flat)
        return eight_wide(s->bvh.isa) && s->bvh.width == 8;
    uint32_t first, n = scene_flat_leaf(s, &first);
    for (uint32_t i = 0; i < n; i++)
        if (packs(s, &s->objects[s->bvh.prims[first + i]]))
            return true;
    return false;
}

/* Each ray of active on its own. */
static int one_by_one(const scene *s, const ray8 *r, int active, scene_hit *hit)
{
    int found = 0;
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        if (scene_intersect(s, &one, &hit[k]))
            found |= 1 << k;
    }
    return found;
}

void scene_shadow8_object(const scene *s, int i, const ray8 *r, int active, int *blocked,
                          int *crosses)
{
    if (!active)
        return;
    const object *o = &s->objects[i];
    int met = -1;
    shape_kind kind = o->shape.kind;
    if (packet_worth(o, active) && !o->moving &&
        (kind == SHAPE_TORUS || kind == SHAPE_CSG || shape_tests_eight(kind))) {
        ray8 lr;
        const ray8 *q = r;
        if (o->xform >= 0) {
            object_rays(s, o, r, active, NULL, &lr);
            q = &lr;
        }
        met = kind == SHAPE_TORUS ? torus8_occluded_on_path(s, &o->shape.torus, q, active)
              : kind == SHAPE_CSG ? csg8_occluded_on_path(s, o->shape.csg, q, active)
                                  : shape8_on_path(s, &o->shape, q, NULL, active, NULL, NULL);
    }
    if (met < 0 && o->transmits) { /* crossed or not: the crossings' search will say */
        *crosses |= active;
        return;
    }
    if (met < 0) { /* as scene_shadow_object asks it, ray by ray */
        met = 0;
        for (int m = active; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ray one = ray8_get(r, k), lr = scene_object_ray(s, o, &one);
            if (shape_occluded_inline(&o->shape, &lr))
                met |= 1 << k;
        }
    }
    *(o->transmits ? crosses : blocked) |= met;
}

/* sphere8_crossings on the scene's path; false where it has none. */
static bool sphere_crossings8(const scene *s, const struct sphere *sp, const ray8 *r, int active,
                              float t[2][8], int took[2])
{
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512) {
        sphere8_crossings_avx512(sp, r, active, t, took);
        return true;
    }
    if (s->bvh.isa == ACCEL_AVX2) {
        sphere8_crossings_avx2(sp, r, active, t, took);
        return true;
    }
#endif
    (void)s, (void)sp, (void)r, (void)active, (void)t, (void)took;
    return false;
}

/* Transmitting object i's crossings of the shadow rays of lanes (not yet
 * blocked: *blocked), added to out[k] as scene_shadow_object adds them;
 * a ray with more than fit joins *blocked. */
static void crossings8_object(const scene *s, int i, const ray8 *r, int lanes,
                              scene_crossings out[8], int *blocked)
{
    const object *o = &s->objects[i];
    float t[2][8];
    int took[2];
    if (o->shape.kind == SHAPE_SPHERE && o->xform < 0 &&
        sphere_crossings8(s, &o->shape.sphere, r, lanes, t, took)) {
        for (int j = 0; j < 2; j++)
            for (int m = took[j]; m; m &= m - 1) {
                int k = __builtin_ctz((unsigned)m);
                if (out[k].n == SCENE_SHADOW_MAX)
                    *blocked |= 1 << k;
                else
                    out[k].hit[out[k].n++] = (scene_hit){{.t = t[j][k]}, i};
            }
        return;
    }
    for (int m = lanes; m; m &= m - 1) { /* ray by ray */
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        vec3 inv = v3(1.0f / one.d.x, 1.0f / one.d.y, 1.0f / one.d.z);
        scene_shadow_ctx c = {s, &one, v3_len(one.d), &out[k]};
        if (scene_bounds_met(s, i, &one, inv) && scene_shadow_object(&c, i))
            *blocked |= 1 << k;
    }
}

int scene_shadow_one_crossed8(const scene *s, const ray8 *r, int lanes, int32_t obj[8],
                              int count[8])
{
    if (s->ncrossed < 0)
        return lanes;
    int seen = 0, more = 0;
    for (int i = 0; i < s->ncrossed; i++) {
        const object *o = &s->objects[s->crossed[i]];
        float t[2][8];
        int took[2];
        if (!(o->shape.kind == SHAPE_SPHERE && o->xform < 0 &&
              sphere_crossings8(s, &o->shape.sphere, r, lanes, t, took)))
            return lanes;
        int met = took[0] | took[1];
        more |= met & seen;
        for (int m = met & ~seen; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            obj[k] = s->crossed[i];
            count[k] = (took[0] >> k & 1) + (took[1] >> k & 1);
        }
        seen |= met;
    }
    for (int m = lanes & ~seen; m; m &= m - 1)
        count[__builtin_ctz((unsigned)m)] = 0;
    return more;
}

int scene_shadow_unblocked8(const scene *s, const ray8 *r, int lanes, scene_crossings out[8])
{
    int blocked = 0;
    if (s->ncrossed < 0) {
        for (int m = lanes; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ray one = ray8_get(r, k);
            blocked |= scene_shadow(s, &one, &out[k]) << k;
        }
        return blocked;
    }
    for (int m = lanes; m; m &= m - 1)
        out[__builtin_ctz((unsigned)m)].n = 0;
    for (int i = 0; i < s->ncrossed && (lanes & ~blocked); i++)
        crossings8_object(s, s->crossed[i], r, lanes & ~blocked, out, &blocked);
    for (int m = lanes & ~blocked; m; m &= m - 1)
        scene_sort_crossings(&out[__builtin_ctz((unsigned)m)]);
    return blocked;
}

/* scene_shadow_walk8 on the scene's path, culling as walk8 does; false
 * where the path has none. */
static bool shadow_walk8(const scene *s, const ray8 *r, int active, int *blocked, int *crosses)
{
#if defined(GLINT_WIDE_KERNELS)
    bool deep = s->bvh.nnodes > 1;
    if (s->bvh.isa == ACCEL_AVX512)
        return (deep ? scene_shadow_walk8_culled_avx512
                     : scene_shadow_walk8_avx512)(s, r, active, blocked, crosses);
    if (s->bvh.isa == ACCEL_AVX2)
        return (deep ? scene_shadow_walk8_culled_avx2
                     : scene_shadow_walk8_avx2)(s, r, active, blocked, crosses);
#endif
    (void)s, (void)r, (void)active, (void)blocked, (void)crosses;
    return false;
}

/* The n objects of list against the shadow rays of active not yet
 * blocked, as scene_shadow8 asks them. */
static void shadow8_objects(const scene *s, const int32_t *list, int n, const ray8 *r,
                            int active, int *blocked, int *crosses)
{
    for (int i = 0; i < n; i++)
        scene_shadow8_object(s, list[i], r, active & ~*blocked, blocked, crosses);
}

bool scene_shadow8(const scene *s, const ray8 *r, int active, int *blocked, int *crosses)
{
    *blocked = *crosses = 0;
    if (!s->flat && !(eight_wide(s->bvh.isa) && s->bvh.width == 8))
        return false;
    shadow8_objects(s, s->unbounded, s->nunbounded, r, active, blocked, crosses);
    if (s->flat) {
        uint32_t first, n = scene_flat_leaf(s, &first);
        shadow8_objects(s, s->bvh.prims + first, (int)n, r, active, blocked, crosses);
    } else if ((active & ~*blocked) && !shadow_walk8(s, r, active & ~*blocked, blocked, crosses)) {
        return false;
    }
    *crosses &= ~*blocked;
    return true;
}

bool scene_shadow8_among(const scene *s, const ray8 *r, int active, const int32_t *list, int n,
                         int *blocked, int *crosses)
{
    *blocked = *crosses = 0;
    if (!s->flat && !(eight_wide(s->bvh.isa) && s->bvh.width == 8))
        return false;
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        scene_shadow_among8_avx512(s, r, active, list, n, blocked, crosses);
    else if (s->bvh.isa == ACCEL_AVX2)
        scene_shadow_among8_avx2(s, r, active, list, n, blocked, crosses);
    else
#endif
    {
        shadow8_objects(s, s->unbounded, s->nunbounded, r, active, blocked, crosses);
        shadow8_objects(s, list, n, r, active, blocked, crosses);
    }
    *crosses &= ~*blocked;
    return true;
}

/* The rays of active, whose directions' signs differ, after the objects
 * outside the tree (found): those of each octant that has three or more
 * walk the tree together, the others go one by one. */
static int walk8_by_octant(const scene *s, const ray8 *r, int active, int found, float best[8],
                           scene_hit hit[8])
{
    int octant[8], alone = active, result = 0;
    for (int m = active; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m); /* the signs packet_make compares */
        octant[k] = (1.0f / r->dx[k] < 0.0f) | (1.0f / r->dy[k] < 0.0f) << 1 |
                    (1.0f / r->dz[k] < 0.0f) << 2;
    }
    for (int m = active; m;) {
        int first = octant[__builtin_ctz((unsigned)m)], group = 0;
        for (int g = m; g; g &= g - 1) {
            int k = __builtin_ctz((unsigned)g);
            group |= (octant[k] == first) << k;
        }
        m &= ~group;
        int walked = ray8_three_or_more(group) ? walk8(s, r, group, best, hit) : -1;
        if (walked >= 0) {
            alone &= ~group;
            result |= (found & group) | walked;
        }
    }
    return result | one_by_one(s, r, alone, hit);
}

/* The n objects of list against the rays of active, each searched up to
 * best[k] (scene_packet_object); returns the rays whose nearest hit one
 * of them now is. */
static int packet_objects(const scene *s, const int32_t *list, int n, const ray8 *r, int active,
                          float best[8], scene_hit *hit)
{
    int found = 0;
    for (int i = 0; i < n; i++)
        found |= scene_packet_object(s, list[i], r, active, best, hit);
    return found;
}

/* A packet's search before its first object: each ray up to its limit,
 * no hit yet. */
static void packet_begin(const ray8 *r, float best[8], scene_hit *hit)
{
    memcpy(best, r->tmax, sizeof(float) * 8);
    for (int k = 0; k < 8; k++)
        hit[k].object = -1;
}

int scene_intersect8(const scene *s, const ray8 *r, int active, scene_hit *hit)
{
    if (!active)
        return 0;
    if (!s->flat && !eight_wide(s->bvh.isa))
        return one_by_one(s, r, active, hit);
    float best[8];
    packet_begin(r, best, hit);
    int found = packet_objects(s, s->unbounded, s->nunbounded, r, active, best, hit);
    if (s->flat) {
        uint32_t first, n = scene_flat_leaf(s, &first);
        return found | packet_objects(s, s->bvh.prims + first, (int)n, r, active, best, hit);
    }
    int walked = walk8(s, r, active, best, hit);
    if (walked < 0 && eight_wide(s->bvh.isa) && s->bvh.width == 8 && s->bvh.nnodes > 0)
        return walk8_by_octant(s, r, active, found, best, hit);
    return walked < 0 ? one_by_one(s, r, active, hit) : found | walked;
}

int scene_intersect8_among(const scene *s, const ray8 *r, int active, const int32_t *list,
                           int n, scene_hit *hit)
{
    if (!active)
        return 0;
#if defined(GLINT_WIDE_KERNELS)
    if (s->bvh.isa == ACCEL_AVX512)
        return scene_among8_avx512(s, r, active, list, n, hit);
    if (s->bvh.isa == ACCEL_AVX2)
        return scene_among8_avx2(s, r, active, list, n, hit);
#endif
    float best[8];
    packet_begin(r, best, hit);
    return packet_objects(s, s->unbounded, s->nunbounded, r, active, best, hit) |
           packet_objects(s, list, n, r, active, best, hit);
}

/* Rays that spread go one by one through a mesh or a tree deeper than one
 * node: a walk shared by eight of them visits the union of their nodes,
 * and each ray's own near-to-far order spares it the far leaves. */
int scene_intersect8_spread(const scene *s, const ray8 *r, int active, scene_hit *hit)
{
    if (s->nmeshes > 0 || (!s->flat && s->bvh.nnodes > 1))
        return one_by_one(s, r, active, hit);
    return scene_intersect8(s, r, active, hit);
}

/* mesh_packet: eight coherent rays through an eight-wide tree at once
 * (packet_walk, which the scene's walk of its own tree shares:
 * scene_trace.h), and against a mesh's triangles (mesh_intersect8), for
 * the eight-wide paths (accel/isa.h): each node's children and each leaf's
 * triangles are fetched once for the eight, and each test runs on all of
 * them in one AVX register, one lane per ray.
 *
 * The rays must agree in the signs of their directions (so that each node
 * is tested against the same near planes) and, for triangles, in the axes
 * of the watertight test (kx, ky, kz of tri4.h); a packet that does not is
 * traced one ray at a time. Primary rays of neighbouring pixels almost
 * always do.
 *
 * Every ray gets the hit the one-ray kernel gives it, to the bit: the box
 * and triangle tests are the same operations in the same order, each
 * block's triangles are tested against the distance reached when the block
 * began, a child is visited up to wide_reach of the nearest hit as in
 * wide_traverse, and of two hits at the same distance the lower triangle
 * index wins, whatever the order in which they are found (mesh_trace.h
 * applies the same rule). */
#ifndef GLINT_GEOM_MESH_PACKET_H
#define GLINT_GEOM_MESH_PACKET_H

#include <immintrin.h>
#include <string.h>
#include "geom/mesh_trace.h"

/* A subtree still to visit, the distances at which the rays in mask enter
 * it. */
typedef struct packet_entry {
    __m256 tn;
    int32_t child;
    uint32_t count;
    uint32_t mask;
} packet_entry;

/* The packet as the tests want it, one lane per ray. The triangle test's
 * values are worked out at the first leaf (packet_tri_make). */
typedef struct packet8 {
    const ray8 *r;
    __m256 ox, oy, oz, ix, iy, iz, tmin;
    int nx, ny, nz;
    /* The whole packet's bounds, for packet_cull: per axis the origin that
     * enters a box last (near) and leaves it first (far) and the least and
     * greatest inverse direction, and the least tmin, each in every lane.
     * bounded is false when a ray's values are not all finite. */
    bool bounded;
    int near[3]; /* the rows of a node's boxes (bvh8_node) nearer the rays */
    __m256 on[3], of[3], ilo[3], ihi[3], tlo;
    bool tri_ready;
    __m256 qox, qoy, qoz, sx, sy, sz; /* tri4_ray's per-ray values */
    int kx, ky, kz;
} packet8;

/* What the rays have found so far. */
typedef struct packet_best {
    __m256 t, b1, b2;
    __m256i id; /* -1: nothing yet */
} packet_best;

/* next_up (vec3.h) lane by lane: positive finite lanes step up a unit,
 * negative ones (-inf too) a unit towards zero, zeros become the least
 * denormal, +inf and NaN stay. */
static inline __m256 packet_next_up(__m256 x)
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_castsi256_ps(_mm256_set1_epi32(1));
    __m256 up = _mm256_and_ps(_mm256_cmp_ps(x, zero, _CMP_GT_OQ),
                              _mm256_cmp_ps(x, _mm256_set1_ps(INFINITY), _CMP_LT_OQ));
    __m256 down = _mm256_cmp_ps(x, zero, _CMP_LT_OQ);
    __m256i step = _mm256_sub_epi32(_mm256_castps_si256(_mm256_and_ps(up, one)),
                                    _mm256_castps_si256(_mm256_and_ps(down, one)));
    __m256 y = _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(x), step));
    return _mm256_blendv_ps(y, _mm256_set1_ps(0x1p-149f), _mm256_cmp_ps(x, zero, _CMP_EQ_OQ));
}

/* The lanes of mask (bit k: lane k) as an all-ones or all-zeros lane. */
static inline __m256 packet_lanes(int mask)
{
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    __m256i in = _mm256_and_si256(_mm256_set1_epi32(mask), bit);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(in, bit));
}

static inline float packet_hmin(__m256 v)
{
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    m = _mm_min_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}

static inline float packet_hmax(__m256 v)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}

/* The children of node n that some ray of the packet may enter, one bit
 * each, found for all of them at once by interval arithmetic over the
 * packet's bounds (Boulos et al., "Geometric and Arithmetic Culling
 * Methods for Entire Ray Packets", 2006): each child's nearest possible
 * entry and furthest possible exit. Rounding to nearest is monotonic, so
 * each bound is as far out as any ray's own rounded distance, and a child
 * a ray enters in packet_node's test is never culled: the culled ones are
 * those no ray would enter, and the walk is the same, only cheaper (on
 * row 8 of the benchmark, 37 box tests a packet were made for 6 children
 * entered). reach is a bound on the rays' reaches; a NaN lets all pass. */
__attribute__((always_inline)) static inline int packet_cull(const bvh8_node *n, const packet8 *p,
                                                             float reach)
{
    if (!p->bounded)
        return 0xff;
    __m256 lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        __m256 dn = _mm256_sub_ps(_mm256_load_ps(n->box[p->near[a]]), p->on[a]);
        __m256 df = _mm256_sub_ps(_mm256_load_ps(n->box[p->near[a] ^ 1]), p->of[a]);
        lo[a] = _mm256_min_ps(_mm256_mul_ps(dn, p->ilo[a]), _mm256_mul_ps(dn, p->ihi[a]));
        hi[a] = _mm256_max_ps(_mm256_mul_ps(df, p->ilo[a]), _mm256_mul_ps(df, p->ihi[a]));
    }
    __m256 vn = _mm256_max_ps(_mm256_max_ps(lo[0], lo[1]), _mm256_max_ps(lo[2], p->tlo));
    __m256 vf = _mm256_min_ps(_mm256_min_ps(hi[0], hi[1]), hi[2]);
    vf = _mm256_min_ps(_mm256_mul_ps(vf, _mm256_set1_ps(WIDE_FAR_SCALE)), _mm256_set1_ps(reach));
    return _mm256_movemask_ps(_mm256_cmp_ps(vn, vf, _CMP_NGT_UQ));
}

/* Child k of node n against the rays of `active` (act, their lanes);
 * when some enter it, its entry goes into out[0 .. m] by key (the first
 * distance at which any of them enters; ties keep child order). Returns
 * the new count. */
__attribute__((always_inline)) static inline int packet_child(const bvh8_node *n, const packet8 *p,
                                                              int k, __m256 tmax, __m256 act,
                                                              float key[8], packet_entry out[8],
                                                              int m)
{
    const __m256 scale = _mm256_set1_ps(WIDE_FAR_SCALE), inf = _mm256_set1_ps(INFINITY);
    __m256 t0x = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&n->box[0 + p->nx][k]), p->ox), p->ix);
    __m256 t1x = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&n->box[1 - p->nx][k]), p->ox), p->ix);
    __m256 t0y = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&n->box[2 + p->ny][k]), p->oy), p->iy);
    __m256 t1y = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&n->box[3 - p->ny][k]), p->oy), p->iy);
    __m256 t0z = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&n->box[4 + p->nz][k]), p->oz), p->iz);
    __m256 t1z = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&n->box[5 - p->nz][k]), p->oz), p->iz);
    __m256 vn = _mm256_max_ps(_mm256_max_ps(t0x, t0y), _mm256_max_ps(t0z, p->tmin));
    __m256 vf = _mm256_min_ps(_mm256_min_ps(t1x, t1y), _mm256_min_ps(t1z, inf));
    vf = _mm256_min_ps(_mm256_mul_ps(vf, scale), tmax);
    __m256 in = _mm256_and_ps(_mm256_cmp_ps(vn, vf, _CMP_LE_OQ), act); /* idle rays: out */
    int mask = _mm256_movemask_ps(in);
    if (!mask)
        return m;
    __m256 tn = _mm256_blendv_ps(inf, vn, in);
    float kk = packet_hmin(tn);
    int j = m++;
    for (; j > 0 && key[j - 1] > kk; j--) {
        key[j] = key[j - 1];
        out[j] = out[j - 1];
    }
    key[j] = kk;
    out[j] = (packet_entry){tn, n->child[k], n->count[k], (uint32_t)mask};
    return m;
}

/* The children of node n the rays of `active` enter; returns how many,
 * with their entries in out, nearest first (by the first distance at which
 * any of the rays enters). With the packet's bounds (p->bounded), only the
 * children packet_cull leaves are tested ray by ray; without, every child
 * in turn (a loop the compiler unrolls: a tree of one node, where culling
 * costs more than it saves, keeps that). */
__attribute__((always_inline)) static inline int packet_node(const bvh8_node *n, const packet8 *p,
                                                             __m256 tmax, int active,
                                                             packet_entry out[8], bool cull)
{
    float key[8];
    int m = 0;
    const __m256 act = packet_lanes(active);
    if (cull && p->bounded) {
        for (int left = packet_cull(n, p, packet_hmax(tmax)); left; left &= left - 1) {
            int k = __builtin_ctz((unsigned)left);
            if (n->count[k] == 0 && n->child[k] < 0)
                break; /* empty lanes come last */
            m = packet_child(n, p, k, tmax, act, key, out, m);
        }
        return m;
    }
    for (int k = 0; k < 8; k++) {
        if (n->count[k] == 0 && n->child[k] < 0)
            break;
        m = packet_child(n, p, k, tmax, act, key, out, m);
    }
    return m;
}

/* The rays of `active` against triangle k of block b, tested against lim
 * (each ray's distance when the block began, made inclusive); returns the
 * rays hit, with t, b1 and b2 per ray. */
__attribute__((always_inline)) static inline int packet_tri(const packet8 *p, const tri4 *b, int k,
                                                            __m256 lim, int active, __m256 *t,
                                                            __m256 *b1, __m256 *b2)
{
    __m256 ex[3], ey[3], ez[3];
    for (int c = 0; c < 3; c++) {
        __m256 az = _mm256_sub_ps(_mm256_broadcast_ss(&b->p[c][p->kz][k]), p->qoz);
        ex[c] = _mm256_sub_ps(_mm256_sub_ps(_mm256_broadcast_ss(&b->p[c][p->kx][k]), p->qox),
                              _mm256_mul_ps(p->sx, az));
        ey[c] = _mm256_sub_ps(_mm256_sub_ps(_mm256_broadcast_ss(&b->p[c][p->ky][k]), p->qoy),
                              _mm256_mul_ps(p->sy, az));
        ez[c] = _mm256_mul_ps(p->sz, az);
    }
    int on_edge;
    int mask = tri8_solve(ex, ey, ez, active, p->tmin, lim, &on_edge, t, b1, b2);
    if (on_edge) { /* rare: those rays one at a time, in double precision */
        float tv[8], b1v[8], b2v[8], lv[8], tmin[8];
        _mm256_storeu_ps(tv, *t);
        _mm256_storeu_ps(b1v, *b1);
        _mm256_storeu_ps(b2v, *b2);
        _mm256_storeu_ps(lv, lim);
        _mm256_storeu_ps(tmin, p->tmin);
        for (int r = 0; r < 8; r++) {
            if (!(on_edge >> r & 1))
                continue;
            ray one = ray8_get(p->r, r);
            tri4_ray q = tri4_ray_make(&one);
            tri_ray tr = tri4_scalar_ray(&q);
            if (tri_intersect(&tr, tri4_corner(b, 0, k), tri4_corner(b, 1, k), tri4_corner(b, 2, k),
                              tmin[r], lv[r], &tv[r], &b1v[r], &b2v[r]))
                mask |= 1 << r;
        }
        *t = _mm256_loadu_ps(tv);
        *b1 = _mm256_loadu_ps(b1v);
        *b2 = _mm256_loadu_ps(b2v);
    }
    return mask;
}

/* The hits of mask kept where they are nearer than the best so far, or
 * as near with a lower triangle index. */
__attribute__((always_inline)) static inline void packet_keep(packet_best *best, int mask, __m256 t,
                                                              __m256 b1, __m256 b2, int32_t id)
{
    __m256i idv = _mm256_set1_epi32(id);
    __m256 nearer = _mm256_cmp_ps(t, best->t, _CMP_LT_OQ);
    __m256 tie = _mm256_and_ps(_mm256_cmp_ps(t, best->t, _CMP_EQ_OQ),
                               _mm256_castsi256_ps(_mm256_cmpgt_epi32(best->id, idv)));
    int keep = _mm256_movemask_ps(_mm256_or_ps(nearer, tie)) & mask;
    if (!keep)
        return;
    __m256 sel = packet_lanes(keep);
    best->t = _mm256_blendv_ps(best->t, t, sel);
    best->b1 = _mm256_blendv_ps(best->b1, b1, sel);
    best->b2 = _mm256_blendv_ps(best->b2, b2, sel);
    best->id = _mm256_castps_si256(
        _mm256_blendv_ps(_mm256_castsi256_ps(best->id), _mm256_castsi256_ps(idv), sel));
}

/* A leaf's triangles against the rays of active. */
__attribute__((always_inline)) static inline void packet_leaf(const mesh *m, const packet8 *p,
                                                              uint32_t first, uint32_t count,
                                                              int active, packet_best *best)
{
    const tri4 *blk = &m->blocks[first];
    for (uint32_t j = 0; j < count; j += 4, blk++) {
        __m256 lim = packet_next_up(best->t);
        for (int k = 0; k < 4 && blk->id[k] >= 0; k++) {
            __m256 t = _mm256_setzero_ps(), b1 = t, b2 = t;
            int mask = packet_tri(p, blk, k, lim, active, &t, &b1, &b2);
            if (mask)
                packet_keep(best, mask, t, b1, b2, blk->id[k]);
        }
    }
}

/* Whether the lanes of active agree in c: all set or all clear. */
static inline bool packet_same(__m256 c, int active, bool *set)
{
    int m = _mm256_movemask_ps(c) & active;
    *set = m != 0;
    return m == 0 || m == active;
}

/* The least and the greatest of v's lanes, each in every lane: three
 * steps of swapping halves, pairs and neighbours, with no broadcast. */
static inline __m256 packet_all_min(__m256 v)
{
    v = _mm256_min_ps(v, _mm256_permute2f128_ps(v, v, 1));
    v = _mm256_min_ps(v, _mm256_shuffle_ps(v, v, 0x4e));
    return _mm256_min_ps(v, _mm256_shuffle_ps(v, v, 0xb1));
}

static inline __m256 packet_all_max(__m256 v)
{
    v = _mm256_max_ps(v, _mm256_permute2f128_ps(v, v, 1));
    v = _mm256_max_ps(v, _mm256_shuffle_ps(v, v, 0x4e));
    return _mm256_max_ps(v, _mm256_shuffle_ps(v, v, 0xb1));
}

/* packet_cull's bounds of the rays of active, their directions' signs
 * set: idle lanes take the first active ray's values so they add
 * nothing. Left unbounded when a ray's origin is not finite or the
 * inverse of its direction is zero or not finite, where a bound could be
 * NaN. */
static inline void packet_bound(packet8 *p, int active)
{
    const __m256 sign = _mm256_set1_ps(-0.0f), inf = _mm256_set1_ps(INFINITY);
    const __m256i first = _mm256_set1_epi32(__builtin_ctz((unsigned)active));
    const __m256 idle = packet_lanes(~active & 0xff), zero = _mm256_setzero_ps();
    __m256 o[3] = {p->ox, p->oy, p->oz}, i[3] = {p->ix, p->iy, p->iz}, bad = zero;
    const int neg[3] = {p->nx, p->ny, p->nz};
    for (int a = 0; a < 3; a++) {
        o[a] = _mm256_blendv_ps(o[a], _mm256_permutevar8x32_ps(o[a], first), idle);
        i[a] = _mm256_blendv_ps(i[a], _mm256_permutevar8x32_ps(i[a], first), idle);
        __m256 ai = _mm256_andnot_ps(sign, i[a]);
        bad = _mm256_or_ps(bad, _mm256_cmp_ps(_mm256_andnot_ps(sign, o[a]), inf, _CMP_NLT_UQ));
        bad = _mm256_or_ps(bad, _mm256_cmp_ps(ai, inf, _CMP_NLT_UQ));
        bad = _mm256_or_ps(bad, _mm256_cmp_ps(ai, zero, _CMP_NGT_UQ));
        __m256 olo = packet_all_min(o[a]), ohi = packet_all_max(o[a]);
        p->near[a] = 2 * a + neg[a];
        p->on[a] = neg[a] ? olo : ohi;
        p->of[a] = neg[a] ? ohi : olo;
        p->ilo[a] = packet_all_min(i[a]);
        p->ihi[a] = packet_all_max(i[a]);
    }
    __m256 t = _mm256_blendv_ps(p->tmin, _mm256_permutevar8x32_ps(p->tmin, first), idle);
    p->tlo = packet_all_min(t);
    p->bounded = _mm256_movemask_ps(bad) == 0;
}

/* The rays' values for the box tests, as wide_ray_make works them out;
 * false when the rays of active differ in the signs of their directions.
 * The packet is left without its bounds (packet_bound adds them). */
static inline bool packet_make(packet8 *p, const ray8 *r, int active)
{
    p->r = r;
    p->tri_ready = false;
    const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
    p->ox = _mm256_loadu_ps(r->ox), p->oy = _mm256_loadu_ps(r->oy), p->oz = _mm256_loadu_ps(r->oz);
    p->ix = _mm256_div_ps(one, _mm256_loadu_ps(r->dx));
    p->iy = _mm256_div_ps(one, _mm256_loadu_ps(r->dy));
    p->iz = _mm256_div_ps(one, _mm256_loadu_ps(r->dz));
    p->tmin = _mm256_loadu_ps(r->tmin);
    bool nx, ny, nz; /* all three worked out (each sets its sign), hence & */
    int same = (int)packet_same(_mm256_cmp_ps(p->ix, zero, _CMP_LT_OQ), active, &nx) &
               (int)packet_same(_mm256_cmp_ps(p->iy, zero, _CMP_LT_OQ), active, &ny) &
               (int)packet_same(_mm256_cmp_ps(p->iz, zero, _CMP_LT_OQ), active, &nz);
    p->nx = nx, p->ny = ny, p->nz = nz;
    p->bounded = false;
    return same;
}

/* The same for the triangle tests, as tri4_ray_make works them out, at
 * the first leaf; false when the rays differ in their axes. */
static inline bool packet_tri_make(packet8 *p, int active)
{
    const ray8 *r = p->r;
    ray first = ray8_get(r, __builtin_ctz((unsigned)active));
    tri4_ray q = tri4_ray_make(&first);
    p->kx = q.kx, p->ky = q.ky, p->kz = q.kz;
    const __m256 sign = _mm256_set1_ps(-0.0f);
    __m256 d[3] = {_mm256_loadu_ps(r->dx), _mm256_loadu_ps(r->dy), _mm256_loadu_ps(r->dz)};
    __m256 o[3] = {p->ox, p->oy, p->oz};
    __m256 ad[3];
    for (int a = 0; a < 3; a++)
        ad[a] = _mm256_andnot_ps(sign, d[a]);
    /* tri4_ray_make's choice of kz, lane by lane */
    __m256 x_over_y = _mm256_cmp_ps(ad[0], ad[1], _CMP_GT_OQ);
    __m256 is_x = _mm256_and_ps(x_over_y, _mm256_cmp_ps(ad[0], ad[2], _CMP_GT_OQ));
    __m256 is_y = _mm256_andnot_ps(x_over_y, _mm256_cmp_ps(ad[1], ad[2], _CMP_GT_OQ));
    __m256 is_kz = q.kz == 0 ? is_x : q.kz == 1 ? is_y : _mm256_or_ps(is_x, is_y);
    bool all, neg;
    if (!packet_same(is_kz, active, &all) || all != (q.kz != 2))
        return false;
    if (!packet_same(_mm256_cmp_ps(d[q.kz], _mm256_setzero_ps(), _CMP_LT_OQ), active, &neg))
        return false;
    p->sx = _mm256_div_ps(d[q.kx], d[q.kz]);
    p->sy = _mm256_div_ps(d[q.ky], d[q.kz]);
    p->sz = _mm256_div_ps(_mm256_set1_ps(1.0f), d[q.kz]);
    p->qox = o[q.kx], p->qoy = o[q.ky], p->qoz = o[q.kz];
    p->tri_ready = true;
    return true;
}

/* A leaf of the tree packet_walk walks: the rays of `rays` against the
 * leaf's count primitives from first, lowering their lanes of *tmax to the
 * hits found. False abandons the walk (the rays then go one at a time). */
typedef bool (*packet_leaf_fn)(void *ctx, uint32_t first, uint32_t count, int rays,
                               __m256 *tmax);

/* The rays of active through an eight-wide tree, each child entered by
 * any of them visited with those that enter it, nearest first (by the
 * nearest of them); an entry is dropped for the rays whose nearest hit so
 * far (*tmax) lies before it by more than wide_reach allows, as in
 * wide_traverse. cull, a constant at each call: whether nodes' children
 * are culled for the whole packet first (packet_bound must have been
 * called); a walk made without it is compiled without the culling.
 * Returns false when a leaf abandons it. */
__attribute__((always_inline)) static inline bool packet_walk(const bvhw *b, const packet8 *p,
                                                              int active, __m256 *tmax,
                                                              packet_leaf_fn leaf, void *ctx,
                                                              bool cull)
{
    packet_entry stack[WIDE_STACK(8)];
    int sp = 0;
    packet_entry cur = {_mm256_setzero_ps(), 0, 0, (uint32_t)active};
    for (;;) {
        if (cur.child >= 0) {
            packet_entry kids[8];
            __m256 reach = _mm256_mul_ps(*tmax, _mm256_set1_ps(WIDE_TIE_SCALE)); /* wide_reach */
            int nk = packet_node(&b->n8[cur.child], p, reach, (int)cur.mask, kids, cull);
            if (nk > 0) {
                for (int i = nk - 1; i > 0; i--)
                    stack[sp++] = kids[i];
                cur = kids[0];
                continue;
            }
        } else if (!leaf(ctx, (uint32_t)(-1 - cur.child), cur.count, (int)cur.mask, tmax)) {
            return false;
        }
        for (;;) { /* the next entry some ray still enters before its nearest hit */
            if (sp == 0)
                return true;
            cur = stack[--sp];
            __m256 reach = _mm256_mul_ps(*tmax, _mm256_set1_ps(WIDE_TIE_SCALE));
            cur.mask &= (uint32_t)_mm256_movemask_ps(_mm256_cmp_ps(cur.tn, reach, _CMP_LE_OQ));
            if (cur.mask)
                break;
        }
    }
}

typedef struct packet_mesh_ctx {
    const mesh *m;
    packet8 *p;
    int active;
    packet_best best;
} packet_mesh_ctx;

__attribute__((always_inline)) static inline bool packet_mesh_leaf(void *ctx, uint32_t first,
                                                                   uint32_t count, int rays,
                                                                   __m256 *tmax)
{
    packet_mesh_ctx *c = ctx;
    if (!c->p->tri_ready && !packet_tri_make(c->p, c->active))
        return false;
    packet_leaf(c->m, c->p, first, count, rays, &c->best);
    *tmax = c->best.t;
    return true;
}

/* The packet's nearest hits: returns the rays that hit, with hit[k] for
 * each of them; -1 when the rays are not coherent (packet_make). */
__attribute__((always_inline)) static inline int packet_closest(const mesh *m, const ray8 *r,
                                                                int active, shape_hit hit[8])
{
    const bvhw *b = &m->bvh;
    if (b->nnodes == 0 || !active)
        return 0;
    packet8 p;
    if (!packet_make(&p, r, active))
        return -1;
    packet_bound(&p, active);
    packet_mesh_ctx c = {m, &p, active,
                         {_mm256_loadu_ps(r->tmax), _mm256_setzero_ps(), _mm256_setzero_ps(),
                          _mm256_set1_epi32(-1)}};
    __m256 tmax = c.best.t;
    if (!packet_walk(b, &p, active, &tmax, packet_mesh_leaf, &c, true))
        return -1;
    float t[8], b1[8], b2[8];
    int32_t id[8];
    _mm256_storeu_ps(t, c.best.t);
    _mm256_storeu_ps(b1, c.best.b1);
    _mm256_storeu_ps(b2, c.best.b2);
    _mm256_storeu_si256((__m256i *)id, c.best.id);
    int found = 0;
    for (int k = 0; k < 8; k++)
        if ((active >> k & 1) && id[k] >= 0) {
            hit[k] = (shape_hit){.t = t[k], .part = id[k], .b1 = b1[k], .b2 = b2[k]};
            found |= 1 << k;
        }
    return found;
}

/* Defines mesh_intersect8_<isa>. */
#define MESH_PACKET_KERNELS(isa)                                                               \
    int mesh_intersect8_##isa(const mesh *m, const ray8 *r, int active, shape_hit hit[8])      \
    {                                                                                          \
        return packet_closest(m, r, active, hit);                                              \
    }

#endif

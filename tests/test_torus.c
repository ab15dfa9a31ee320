/* The torus against a slow, independent reference: 10^6 random rays from
 * everywhere that matters (near, far at 10^4 x the torus's size, inside
 * the tube, grazing the surface, leaving the surface as secondary rays
 * do), each answered by torus_intersect and by a reference that shares no
 * code with it: Sturm sequences in long double isolate every real root of
 * the ray's quartic (written about the ray's point nearest the centre, not
 * about the box entry), and bisection on the implicit function itself
 * (not the polynomial) pins each crossing down.
 *
 * They must agree on hit or miss and on t (to 1e-6 of the distance plus
 * 1e-6 of the torus's size) on every ray except the ill-conditioned ones,
 * where the reference itself finds two roots within 1e-4 of the size of
 * each other (a ray within a hair of tangent) or a root within 1e-4 of the
 * origin (a ray starting on the surface): there either answer is right,
 * and those rays are counted and bounded instead. Every hit point, once
 * torus_surface has put it on the surface, lies within 1e-5 of the size of
 * the true surface. Also: the roots finder's own tests, known hits, normals
 * and (u, v), crossings against the reference's roots; and the eight-lane
 * kernels (torus8_hit_<isa>, torus8_occluded_<isa>) against the one-ray
 * functions, to the bit, on random packets. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "accel/isa.h"
#include "core/ray.h"
#include "core/rng.h"
#include "core/roots.h"
#include "geom/shape.h"
#include "near.h"

/* ---- the reference ------------------------------------------------------- */

typedef long double ld;

typedef struct lpoly {
    ld c[5];
    int deg; /* -1: the zero polynomial */
} lpoly;

static ld leval(const lpoly *p, ld x)
{
    ld v = 0;
    for (int i = p->deg; i >= 0; i--)
        v = v * x + p->c[i];
    return v;
}

static void trim(lpoly *p, ld scale)
{
    while (p->deg >= 0 && fabsl(p->c[p->deg]) <= 1e-15L * scale)
        p->deg--;
}

/* -(a mod b) */
static lpoly neg_rem(lpoly a, const lpoly *b)
{
    ld scale = 0;
    for (int i = 0; i <= a.deg; i++)
        scale = fmaxl(scale, fabsl(a.c[i]));
    while (a.deg >= b->deg && a.deg >= 0) {
        ld q = a.c[a.deg] / b->c[b->deg];
        int s = a.deg - b->deg;
        for (int i = 0; i <= b->deg; i++)
            a.c[i + s] -= q * b->c[i];
        a.c[a.deg] = 0;
        a.deg--;
        trim(&a, scale);
    }
    for (int i = 0; i <= a.deg; i++)
        a.c[i] = -a.c[i];
    return a;
}

typedef struct sturm {
    lpoly p[6];
    int n;
} sturm;

static sturm sturm_make(const ld c[5])
{
    sturm s = {.n = 2};
    memcpy(s.p[0].c, c, sizeof s.p[0].c);
    s.p[0].deg = 4;
    for (int i = 1; i <= 4; i++)
        s.p[1].c[i - 1] = i * c[i];
    s.p[1].deg = 3;
    while (s.n < 6 && s.p[s.n - 1].deg > 0) {
        s.p[s.n] = neg_rem(s.p[s.n - 2], &s.p[s.n - 1]);
        if (s.p[s.n].deg < 0)
            break;
        s.n++;
    }
    return s;
}

static int sign_changes(const sturm *s, ld x)
{
    int n = 0, last = 0;
    for (int i = 0; i < s->n; i++) {
        ld v = leval(&s->p[i], x);
        int sg = v > 0 ? 1 : v < 0 ? -1 : 0;
        if (sg && last && sg != last)
            n++;
        if (sg)
            last = sg;
    }
    return n;
}

typedef struct refray {
    ld o[3], d[3]; /* d unit */
    ld R2, r2;
} refray;

/* The implicit function at the ray's point t, straight from the point. */
static ld ref_f(const refray *q, ld t)
{
    ld p[3] = {q->o[0] + t * q->d[0], q->o[1] + t * q->d[1], q->o[2] + t * q->d[2]};
    ld s = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + q->R2 - q->r2;
    return s * s - 4 * q->R2 * (p[0] * p[0] + p[2] * p[2]);
}

typedef struct refroots {
    ld t[8];
    int n;
    bool close; /* two roots (crossing or touching) within the tolerance */
} refroots;

static void isolate(const sturm *s, const refray *q, ld t0, ld a, ld b, int va, int vb, int depth,
                    refroots *out)
{
    int n = va - vb;
    if (n <= 0)
        return;
    if (n >= 2 && depth < 70) {
        ld m = 0.5L * (a + b);
        int vm = sign_changes(s, m - t0);
        isolate(s, q, t0, a, m, va, vm, depth + 1, out);
        isolate(s, q, t0, m, b, vm, vb, depth + 1, out);
        return;
    }
    if (n >= 2)
        out->close = true;
    ld fa = ref_f(q, a), fb = ref_f(q, b);
    if ((fa < 0) == (fb < 0))
        return; /* touching: no crossing */
    /* The Illinois variant of regula falsi (Dowell and Jarratt 1971): the
     * bracket always holds the crossing, and it converges superlinearly. */
    ld m = a, prev = b;
    for (int i = 0, side = 0; i < 200 && fabsl(m - prev) > 1e-13L * (1 + fabsl(m)); i++) {
        prev = m;
        m = (fa * b - fb * a) / (fa - fb);
        if (!(m > a && m < b))
            m = 0.5L * (a + b);
        ld fm = ref_f(q, m);
        if (fm == 0)
            break;
        if ((fm < 0) == (fb < 0)) {
            b = m, fb = fm;
            if (side == -1)
                fa *= 0.5L;
            side = -1;
        } else {
            a = m, fa = fm;
            if (side == 1)
                fb *= 0.5L;
            side = 1;
        }
    }
    a = b = m;
    if (out->n < 8)
        out->t[out->n++] = 0.5L * (a + b);
}

/* Every crossing of the line with the torus (centre at the origin) inside
 * its bounding sphere, in order. */
static refroots reference(const refray *q)
{
    refroots out = {.n = 0, .close = false};
    ld R = sqrtl(q->R2), r = sqrtl(q->r2);
    ld t0 = -(q->o[0] * q->d[0] + q->o[1] * q->d[1] + q->o[2] * q->d[2]);
    ld p[3] = {q->o[0] + t0 * q->d[0], q->o[1] + t0 * q->d[1], q->o[2] + t0 * q->d[2]};
    ld pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2], rad = (R + r) * 1.001L;
    if (pp >= rad * rad)
        return out;
    ld half = sqrtl(rad * rad - pp);
    /* The quartic in s = t - t0 about p. */
    ld b = p[0] * q->d[0] + p[1] * q->d[1] + p[2] * q->d[2];
    ld beta = pp + q->R2 - q->r2, k = 4 * q->R2;
    ld c[5] = {beta * beta - k * (p[0] * p[0] + p[2] * p[2]),
               4 * b * beta - 2 * k * (p[0] * q->d[0] + p[2] * q->d[2]),
               4 * b * b + 2 * beta - k * (q->d[0] * q->d[0] + q->d[2] * q->d[2]), 4 * b, 1};
    sturm s = sturm_make(c);
    isolate(&s, q, t0, t0 - half, t0 + half, sign_changes(&s, -half), sign_changes(&s, half), 0,
            &out);
    return out;
}

/* ---- the comparison ------------------------------------------------------- */

typedef struct tally {
    long rays, hits, agree, ill, self_hits;
} tally;

/* One ray: torus_intersect against the reference's first crossing after
 * tmin = 0. */
static void compare(const struct torus *tor, ray r, tally *tl, long id)
{
    shape s = {.kind = SHAPE_TORUS, .torus = *tor};
    double size = tor->major + tor->minor;
    refray q = {.R2 = (ld)tor->major * tor->major, .r2 = (ld)tor->minor * tor->minor};
    ld len = sqrtl((ld)r.d.x * r.d.x + (ld)r.d.y * r.d.y + (ld)r.d.z * r.d.z);
    const float o[3] = {r.o.x, r.o.y, r.o.z}, d[3] = {r.d.x, r.d.y, r.d.z};
    const float c[3] = {tor->center.x, tor->center.y, tor->center.z};
    for (int a = 0; a < 3; a++) {
        q.o[a] = (ld)o[a] - c[a];
        q.d[a] = d[a] / len;
    }
    refroots ref = reference(&q);
    ld want = -1; /* arc length to the first crossing after the origin */
    bool ill = ref.close;
    for (int i = 0; i < ref.n; i++) {
        if (fabsl(ref.t[i]) < 1e-4L * size)
            ill = true;
        if (i > 0 && ref.t[i] - ref.t[i - 1] < 1e-4L * size)
            ill = true;
        if (want < 0 && ref.t[i] > 0)
            want = ref.t[i];
    }
    shape_hit h;
    bool hit = shape_intersect(&s, &r, &h);
    tl->rays++;
    tl->hits += hit;
    ld got = hit ? h.t * len : -1;
    bool same = hit == (want >= 0) &&
                (!hit || fabsl(got - want) <= 1e-6L * (fabsl(want) + size));
    if (same) {
        tl->agree++;
    } else if (ill) {
        tl->ill++;
    } else {
        cr_assert_fail("ray %ld (o %.9g %.9g %.9g, d %.9g %.9g %.9g; R %g r %g): glint %s t %.12Lg, "
                       "reference %s t %.12Lg",
                       id, (double)o[0], (double)o[1], (double)o[2], (double)d[0], (double)d[1],
                       (double)d[2], (double)tor->major, (double)tor->minor, hit ? "hits at" : "misses",
                       got, want >= 0 ? "hits at" : "misses", want);
    }
    if (!hit)
        return;
    if (h.t * len < 1e-3 * size && want > 1e-3L * size)
        tl->self_hits++;
    surface sf;
    shape_surface(&s, &r, &h, &sf);
    ld p[3] = {(ld)sf.p.x - c[0], (ld)sf.p.y - c[1], (ld)sf.p.z - c[2]};
    ld rho = sqrtl(p[0] * p[0] + p[2] * p[2]);
    ld dist = fabsl(sqrtl((rho - tor->major) * (rho - tor->major) + p[1] * p[1]) - tor->minor);
    cr_assert_leq(dist, 1e-5L * size + 1e-7L * sqrtl(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + 1),
                  "ray %ld: the hit point is %Lg off the surface", id, dist);
}

static vec3 surface_point(const struct torus *t, float theta, float phi, vec3 *n)
{
    *n = v3(cosf(phi) * sinf(theta), sinf(phi), cosf(phi) * cosf(theta));
    float w = t->major + t->minor * cosf(phi);
    return v3_add(t->center, v3(w * sinf(theta), t->minor * sinf(phi), w * cosf(theta)));
}

/* A ray of class k (0 near, 1 far, 2 inside, 3 grazing, 4 leaving the
 * surface). */
static ray random_ray(rng *g, const struct torus *t, int k)
{
    float size = t->major + t->minor, tau = 2.0f * (float)M_PI;
    vec3 n, p = surface_point(t, tau * rng_float(g), tau * rng_float(g), &n);
    vec3 aim = v3_add(t->center, v3((2 * rng_float(g) - 1) * size, (2 * rng_float(g) - 1) * t->minor,
                                    (2 * rng_float(g) - 1) * size));
    vec3 o, d;
    switch (k) {
    case 0:
        o = v3_madd(t->center, rng_unit_dir(g), size * (1.2f + 4.0f * rng_float(g)));
        d = v3_sub(aim, o);
        break;
    case 1:
        o = v3_madd(t->center, rng_unit_dir(g), size * 1e4f);
        d = v3_norm(v3_sub(aim, o));
        break;
    case 2: {
        vec3 m = surface_point(t, tau * rng_float(g), tau * rng_float(g), &n);
        o = v3_madd(m, n, -t->minor * 0.98f * rng_float(g));
        d = rng_unit_dir(g);
        break;
    }
    case 3: {
        vec3 tang = v3_norm(v3_cross(n, rng_unit_dir(g)));
        p = v3_madd(p, n, t->minor * 1e-3f * (2 * rng_float(g) - 1));
        o = v3_madd(p, tang, -3.0f * size * (0.2f + rng_float(g)));
        d = tang;
        break;
    }
    default: {
        d = rng_unit_dir(g);
        float e = 1e-4f * (1.0f + v3_max_abs(p));
        o = v3_madd(p, n, v3_dot(n, d) >= 0 ? e : -e);
        break;
    }
    }
    return ray_make(o, d, INFINITY);
}

/* 10^6 rays in the optimised build; a tenth of them under the sanitizers,
 * which run the same code some ten times slower. */
#if defined(__SANITIZE_ADDRESS__)
#define TORUS_RAYS 100000
#else
#define TORUS_RAYS 1000000
#endif

Test(torus, agrees_with_a_slow_reference_on_a_million_rays, .timeout = 600)
{
    rng g = rng_seed(2024, 9);
    tally tl = {0};
    for (long i = 0; i < TORUS_RAYS; i++) {
        float major = 0.5f + 2.5f * rng_float(&g);
        struct torus t = {v3(8 * rng_float(&g) - 4, 8 * rng_float(&g) - 4, 8 * rng_float(&g) - 4),
                          major, major * (0.05f + 0.9f * rng_float(&g))};
        int k = (int)(i % 5);
        compare(&t, random_ray(&g, &t, k), &tl, i);
    }
    cr_log_info("torus: %ld rays, %ld hits, %ld agree, %ld ill-conditioned, %ld self-hits",
                tl.rays, tl.hits, tl.agree, tl.ill, tl.self_hits);
    cr_expect_gt(tl.hits, tl.rays / 3, "not vacuous: many rays hit");
    cr_expect_leq(tl.ill, tl.rays / 1000, "at most 0.1%% of rays are too close to call");
    cr_expect_eq(tl.self_hits, 0, "no ray leaving the surface meets it again at once");
}

/* ---- the eight-lane kernels against the one-ray path ---------------------- */

/* torus8_hit_<isa> and torus8_occluded_<isa> (torus8.h: the setup and the
 * start of the root search in vector registers, t8_first_root) against
 * torus_intersect and torus_occluded, lane by lane and to the bit, on
 * every eight-wide path this CPU runs: random tori (thin, ordinary, fat,
 * and with the tube wider than the ring, R < r; small and large; near the
 * origin and far from it), packets of rays of every kind below in random
 * lanes with a random active mask, and ranges that cut just before, at and
 * just after the ray's first crossing at either end. */

typedef int (*torus8_hit_fn)(const struct torus *, const ray8 *, int, shape_hit *);
typedef int (*torus8_occluded_fn)(const struct torus *, const ray8 *, int);

/* The eight-wide kernels this CPU runs: how many, into the arrays. */
static int torus8_kernels(torus8_hit_fn hit[2], torus8_occluded_fn occluded[2],
                          const char *name[2])
{
    int n = 0;
#if defined(GLINT_WIDE_KERNELS)
    if (accel_isa_best() >= ACCEL_AVX2)
        hit[n] = torus8_hit_avx2, occluded[n] = torus8_occluded_avx2, name[n++] = "avx2";
    if (accel_isa_best() >= ACCEL_AVX512)
        hit[n] = torus8_hit_avx512, occluded[n] = torus8_occluded_avx512, name[n++] = "avx512";
#endif
    (void)hit, (void)occluded, (void)name;
    return n;
}

static float uni(rng *g, float lo, float hi) { return lo + (hi - lo) * rng_float(g); }

/* 10^lo .. 10^hi, uniform in the exponent */
static float decades(rng *g, float lo, float hi) { return powf(10.0f, uni(g, lo, hi)); }

static struct torus stress_torus(rng *g)
{
    float major = decades(g, -1.5f, 1.3f), ratio;
    switch (rng_u32(g) % 5) {
    case 0: /* thin */
        ratio = decades(g, -3.0f, -1.3f);
        break;
    case 1: /* fat: the hole almost or just closed (a horn torus, R = r, which a ray
             * down the axis touches at the centre with a root of order four) */
        ratio = rng_u32(g) % 4 == 0 ? 1.0f : uni(g, 0.9f, 1.0f);
        break;
    case 2: /* the tube wider than the ring (R < r): no hole */
        ratio = uni(g, 1.0f, 4.0f);
        break;
    default:
        ratio = uni(g, 0.05f, 0.9f);
        break;
    }
    float spread = rng_u32(g) % 8 == 0 ? 500.0f : 4.0f;
    vec3 c = rng_u32(g) % 8 == 0 ? v3s(0.0f)
                                  : v3(uni(g, -spread, spread), uni(g, -spread, spread),
                                       uni(g, -spread, spread));
    return (struct torus){c, major, major * ratio};
}

/* A ray of class k at torus t, before its range is set (tmin 0, tmax
 * infinite). */
static ray stress_ray(rng *g, const struct torus *t, int k)
{
    float R = t->major, r = t->minor, size = R + r, tau = 2.0f * (float)M_PI;
    vec3 n, p = surface_point(t, tau * rng_float(g), tau * rng_float(g), &n);
    vec3 aim = v3_add(t->center, v3(uni(g, -size, size), uni(g, -r, r), uni(g, -size, size)));
    vec3 o, d;
    switch (k) {
    case 0: /* from near by, at the box */
        o = v3_madd(t->center, rng_unit_dir(g), size * uni(g, 1.05f, 5.0f));
        d = v3_sub(aim, o);
        break;
    case 1: /* from far away */
        o = v3_madd(t->center, rng_unit_dir(g), size * decades(g, 2.0f, 5.0f));
        d = v3_norm(v3_sub(aim, o));
        break;
    case 2: { /* from inside the tube */
        vec3 m = surface_point(t, tau * rng_float(g), tau * rng_float(g), &n);
        o = v3_madd(m, n, -r * uni(g, 0.0f, 0.999f));
        d = rng_unit_dir(g);
        break;
    }
    case 3: { /* grazing: along a tangent, a hair inside, on or outside */
        vec3 tang = v3_norm(v3_cross(n, rng_unit_dir(g)));
        static const float off[4] = {1e-3f, 1e-5f, 1e-7f, 0.0f};
        p = v3_madd(p, n, r * off[rng_u32(g) % 4] * (rng_u32(g) % 2 ? 1.0f : -1.0f));
        o = v3_madd(p, tang, -size * uni(g, 0.1f, 3.0f));
        d = tang;
        break;
    }
    case 4: { /* leaving the surface, as secondary rays do */
        d = rng_unit_dir(g);
        o = ray_offset(p, n, d);
        break;
    }
    case 5: { /* parallel to the axis: down it, through the tube, or past it */
        float rho = rng_u32(g) % 3 == 0 ? 0.0f : uni(g, 0.0f, 1.2f * size);
        float phi = tau * rng_float(g), side = rng_u32(g) % 2 ? 1.0f : -1.0f;
        o = v3_add(t->center,
                   v3(rho * sinf(phi), side * size * uni(g, 1.1f, 3.0f), rho * cosf(phi)));
        d = v3(0.0f, -side, 0.0f);
        if (rng_u32(g) % 4 == 0) /* nearly */
            d = v3_add(d, v3(1e-4f * uni(g, -1, 1), 0.0f, 1e-4f * uni(g, -1, 1)));
        break;
    }
    case 6: { /* one or two components of the direction zero */
        o = v3_madd(t->center, rng_unit_dir(g), size * uni(g, 0.5f, 4.0f));
        d = v3_sub(aim, o);
        int zero = 1 + (int)(rng_u32(g) % 6); /* bits: the axes made 0 */
        if (zero & 1)
            d.x = rng_u32(g) % 2 ? 0.0f : -0.0f;
        if (zero & 2)
            d.y = rng_u32(g) % 2 ? 0.0f : -0.0f;
        if (zero & 4)
            d.z = rng_u32(g) % 2 ? 0.0f : -0.0f;
        if (v3_is_zero(d))
            d.y = 1.0f;
        break;
    }
    default: { /* in the torus's plane or beside it, dy 0 */
        float y = rng_u32(g) % 4 == 0 ? 0.0f : r * uni(g, -1.1f, 1.1f);
        o = v3_madd(t->center, v3_norm(v3(uni(g, -1, 1), 0.0f, uni(g, -1, 1))),
                    size * uni(g, 0.0f, 3.0f));
        o.y = t->center.y + y;
        d = v3_sub(aim, o);
        d.y = 0.0f;
        if (v3_is_zero(d))
            d.x = 1.0f;
        break;
    }
    }
    if (rng_u32(g) % 3 == 0) /* not unit length */
        d = v3_scale(d, decades(g, -2.0f, 2.0f));
    return ray_make(o, d, INFINITY);
}

/* Its range: (0, inf) as it is, or one that cuts near the first crossing
 * after the ray's start (found by torus_intersect), or an arbitrary one. */
static void stress_range(rng *g, const struct torus *t, ray *r)
{
    shape_hit h;
    float first = torus_intersect(t, r, &h) ? h.t : -1.0f;
    float far = 4.0f * (v3_len(v3_sub(r->o, t->center)) + t->major + t->minor) /
                fmaxf(v3_len(r->d), 1e-30f);
    switch (rng_u32(g) % 8) {
    case 0: /* tmax at the crossing, a float before it or after it, or half way */
        if (first > 0) {
            float c[4] = {first, nextafterf(first, 0.0f), nextafterf(first, INFINITY),
                          0.5f * first};
            r->tmax = c[rng_u32(g) % 4];
        }
        break;
    case 1: /* tmin there: the search must look past that root */
        if (first > 0) {
            float c[4] = {first, nextafterf(first, 0.0f), nextafterf(first, INFINITY),
                          first * (1.0f + 1e-4f)};
            r->tmin = c[rng_u32(g) % 4];
        }
        break;
    case 2: /* a short piece round it, hi under 1e-4 */
        if (first > 0) {
            float w = first * decades(g, -7.0f, -4.0f);
            r->tmin = first - w * rng_float(g);
            r->tmax = r->tmin + w;
        }
        break;
    case 3: /* arbitrary */
        r->tmin = far * 0.5f * rng_float(g) * rng_float(g);
        r->tmax = rng_u32(g) % 2 ? INFINITY : r->tmin + far * rng_float(g);
        break;
    case 4:
        r->tmax = far * rng_float(g);
        break;
    default:
        break;
    }
}

/* 1.6 million rays, each through four kernels: about a second in the
 * optimised build and two or three under the sanitizers, so both run
 * them all. */
#define STRESS_PACKETS 200000

/* A lane's ray, for a message. */
#define LANE_FMT "o (%a, %a, %a) d (%a, %a, %a) tmin %a tmax %a"
#define LANE_ARGS(r)                                                                           \
    (double)(r).o.x, (double)(r).o.y, (double)(r).o.z, (double)(r).d.x, (double)(r).d.y,      \
        (double)(r).d.z, (double)(r).tmin, (double)(r).tmax
#define TORUS_FMT "torus centre (%a, %a, %a) R %a r %a"
#define TORUS_ARGS(t)                                                                          \
    (double)(t).center.x, (double)(t).center.y, (double)(t).center.z, (double)(t).major,       \
        (double)(t).minor

Test(torus, packets_match_one_ray_at_a_time_to_the_bit_on_every_path, .timeout = 120)
{
    torus8_hit_fn hit8[2];
    torus8_occluded_fn occluded8[2];
    const char *name[2];
    int kernels = torus8_kernels(hit8, occluded8, name);
    if (!kernels)
        cr_skip_test("no eight-wide kernels on this CPU");
    rng g = rng_seed(8128, 5);
    long lanes = 0, hits = 0, blocked = 0, cut = 0, kinds[8] = {0};
    for (long i = 0; i < STRESS_PACKETS; i++) {
        struct torus t = stress_torus(&g);
        ray rays[8];
        for (int k = 0; k < 8; k++) {
            int kind = (int)(rng_u32(&g) % 8);
            rays[k] = stress_ray(&g, &t, kind);
            stress_range(&g, &t, &rays[k]);
            kinds[kind]++;
        }
        int active = (int)(rng_u32(&g) % 256);
        ray8 p;
        if (active && rng_u32(&g) % 2) {
            ray8_pack(&p, rays, active); /* idle lanes repeat an active one */
        } else {
            for (int k = 0; k < 8; k++) /* idle lanes hold rays of their own */
                ray8_put(&p, k, &rays[k]);
        }
        /* the one-ray answers, from the packet's own rays */
        int want_hit = 0, want_blocked = 0;
        shape_hit want[8];
        for (int m = active; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ray r = ray8_get(&p, k);
            want[k] = (shape_hit){0};
            want_hit |= torus_intersect(&t, &r, &want[k]) << k;
            want_blocked |= torus_occluded(&t, &r) << k;
            lanes++;
            cut += !(want_hit >> k & 1) && r.tmax < INFINITY;
        }
        hits += ray8_count(want_hit);
        blocked += ray8_count(want_blocked);
        for (int j = 0; j < kernels; j++) {
            shape_hit got[8];
            memset(got, 0xa5, sizeof got);
            int got_hit = hit8[j](&t, &p, active, got);
            int got_blocked = occluded8[j](&t, &p, active);
            for (int k = 0; k < 8; k++) {
                if (!(active >> k & 1))
                    continue;
                ray r = ray8_get(&p, k);
                bool h = got_hit >> k & 1, b = got_blocked >> k & 1;
                cr_assert_eq(h, want_hit >> k & 1,
                             "%s, packet %ld lane %d (active %#x): torus8_hit %s, torus_intersect "
                             "%s; " TORUS_FMT "; " LANE_FMT,
                             name[j], i, k, (unsigned)active, h ? "hits" : "misses",
                             h ? "misses" : "hits", TORUS_ARGS(t), LANE_ARGS(r));
                cr_assert_eq(b, want_blocked >> k & 1,
                             "%s, packet %ld lane %d (active %#x): torus8_occluded %d, "
                             "torus_occluded %d; " TORUS_FMT "; " LANE_FMT,
                             name[j], i, k, (unsigned)active, b, !b, TORUS_ARGS(t), LANE_ARGS(r));
                if (!h)
                    continue;
                cr_assert(memcmp(&got[k].t, &want[k].t, sizeof got[k].t) == 0,
                          "%s, packet %ld lane %d: t %a, torus_intersect's %a; " TORUS_FMT
                          "; " LANE_FMT,
                          name[j], i, k, (double)got[k].t, (double)want[k].t, TORUS_ARGS(t),
                          LANE_ARGS(r));
                cr_assert(got[k].part == 0 && got[k].b1 == 0.0f && got[k].b2 == 0.0f &&
                              got[k].leaf == 0,
                          "%s, packet %ld lane %d: part %d b1 %g b2 %g leaf %d", name[j], i, k,
                          got[k].part, (double)got[k].b1, (double)got[k].b2, got[k].leaf);
            }
            cr_assert_eq(got_hit & ~active, 0, "%s, packet %ld: hits outside active", name[j], i);
            cr_assert_eq(got_blocked & ~active, 0, "%s, packet %ld: blocked outside active",
                         name[j], i);
        }
    }
    cr_log_info("torus packets: %ld lanes on %d paths, %ld hits, %ld blocked, %ld missed with a "
                "finite tmax",
                lanes, kernels, hits, blocked, cut);
    for (int k = 0; k < 8; k++)
        cr_expect_gt(kinds[k], STRESS_PACKETS / 2, "rays of kind %d: %ld", k, kinds[k]);
    cr_expect_gt(hits, lanes / 5, "not vacuous: many lanes hit (%ld of %ld)", hits, lanes);
    cr_expect_gt(lanes - hits, lanes / 5, "and many miss");
}

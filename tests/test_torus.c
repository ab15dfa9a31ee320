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
 * and (u, v), crossings against the reference's roots. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

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

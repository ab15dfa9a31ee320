/* raybench: glint's triangle-mesh ray queries and BVH build side by side
 * with Embree 3 on the same triangles and the same rays (rows 2 and 3 of
 * bench/README.md). Prints markdown table rows for bench/run.
 *
 * Both back-ends are compiled in:
 * - glint: the Stanford bunny read with mesh_import, placed once in a scene
 *   (scene_intersect / scene_occluded_opaque, the renderer's own path:
 *   scene BVH, then the mesh's BVH), or with --glint-path mesh, the mesh
 *   alone (mesh_intersect / mesh_occluded). Primary rays go eight
 *   neighbouring pixels at a time (scene_intersect8 / mesh_intersect8), as
 *   the renderer's camera rays do; incoherent rays one at a time.
 * - Embree: one RTC_GEOMETRY_TYPE_TRIANGLE geometry sharing copies of
 *   glint's vertex and index arrays (after mesh_init, so the same triangles
 *   in the same order), RTC_BUILD_QUALITY_HIGH, the single-ray API
 *   rtcIntersect1 / rtcOccluded1.
 *
 * Rays (unit directions, the same arrays for both):
 * - primary: a pinhole camera framing the bunny, one ray per pixel centre;
 * - incoherent: origins uniform on a sphere around the bunny's bounds,
 *   each aimed at a uniform point inside the bounds (fixed seed); closest
 *   hit with no far limit, and occlusion of the segment to that point.
 * Each query runs on 1 thread and on all threads (pthreads taking chunks
 * of rays from a shared counter). Every timing is the median of --runs
 * runs, glint and Embree alternating (and swapping who goes first), after
 * one untimed warm-up run of each whose answers are compared ray by ray.
 *
 * Builds: glint's mesh_init as a whole (dropping degenerate triangles,
 * triangle boxes, binned SAH build on as many threads as the process has
 * CPUs, collapse to the wide BVH, reordering triangles) against Embree's
 * rtcCommitScene (high quality), both on all threads and both on one (glint
 * by pinning the process to one CPU for its build, Embree with a device
 * made with threads=1), for the bunny and for the bunny with every triangle split
 * into 16 (midpoint subdivision twice, vertices shared along edges).
 * Bytes: mesh_bytes for glint on a mesh holding only positions and
 * indices; for Embree, what its memory monitor counts after the build plus
 * the vertex and index arrays it shares. Peak RSS: a fresh process per
 * back-end (this program, run again) reads the triangles from a file and
 * builds, then reports its peak resident set (see peak_rss_kib). */
#define _GNU_SOURCE /* sched_setaffinity */
#include <embree3/rtcore.h>
#include <sched.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/rng.h"
#include "load/mesh_import.h"
#include "scene/scene.h"
#include "sphere_field.h"

_Static_assert(sizeof(vec3) == 12, "vertex arrays are shared with Embree as FLOAT3");

#define CHUNK 4096           /* rays a thread takes at a time */
#define MAX_THREADS 256
#define AGREE_TARGET 99.9    /* percent of rays on which both must agree */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void die(const char *what)
{
    fprintf(stderr, "raybench: %s\n", what);
    exit(1);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p)
        die("out of memory");
    return p;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- triangles: bare arrays, as both back-ends take them ---- */

typedef struct tris {
    vec3 *pos;          /* nverts + 1 entries: Embree reads 16 bytes per vertex */
    uint32_t (*tri)[3];
    int nverts, ntris;
} tris;

static tris tris_copy(const vec3 *pos, int nverts, const uint32_t (*tri)[3], int ntris)
{
    tris t = {xmalloc(sizeof(vec3) * ((size_t)nverts + 1)), xmalloc(12 * (size_t)ntris), nverts,
              ntris};
    memcpy(t.pos, pos, sizeof(vec3) * (size_t)nverts);
    t.pos[nverts] = v3s(0.0f);
    memcpy(t.tri, tri, 12 * (size_t)ntris);
    return t;
}

static void tris_free(tris *t)
{
    free(t->pos);
    free(t->tri);
    memset(t, 0, sizeof *t);
}

/* Splits every triangle into four at its edge midpoints. A midpoint is
 * made once per edge (an open-addressing table keyed by the edge's two
 * vertex indices), so neighbouring triangles share it and the surface
 * stays closed; (a + b) / 2 is the same float whichever end comes first. */
static tris subdivide(const tris *in)
{
    size_t nedges_max = 3 * (size_t)in->ntris, cap = 1;
    while (cap < 2 * nedges_max)
        cap <<= 1;
    uint64_t *keys = xmalloc(sizeof *keys * cap);
    uint32_t *vals = xmalloc(sizeof *vals * cap);
    memset(keys, 0xff, sizeof *keys * cap);
    size_t maxv = (size_t)in->nverts + nedges_max;
    if (maxv > UINT32_MAX || 4 * (size_t)in->ntris > INT32_MAX)
        die("mesh too large to subdivide");
    tris out = {xmalloc(sizeof(vec3) * (maxv + 1)), xmalloc(12 * 4 * (size_t)in->ntris),
                in->nverts, 4 * in->ntris};
    memcpy(out.pos, in->pos, sizeof(vec3) * (size_t)in->nverts);
    for (int i = 0; i < in->ntris; i++) {
        uint32_t v[3], m[3];
        memcpy(v, in->tri[i], sizeof v);
        for (int e = 0; e < 3; e++) {
            uint32_t a = v[e], b = v[(e + 1) % 3];
            uint64_t key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
            size_t h = (size_t)((key * 0x9E3779B97F4A7C15ULL) >> 20) & (cap - 1);
            while (keys[h] != UINT64_MAX && keys[h] != key)
                h = (h + 1) & (cap - 1);
            if (keys[h] != key) {
                keys[h] = key;
                vals[h] = (uint32_t)out.nverts;
                out.pos[out.nverts++] = v3_scale(v3_add(in->pos[a], in->pos[b]), 0.5f);
            }
            m[e] = vals[h];
        }
        /* Corners keep the original winding: (v0, m01, m20), (m01, v1, m12),
         * (m20, m12, v2) and the middle (m01, m12, m20). */
        uint32_t(*t)[3] = out.tri + 4 * (size_t)i;
        uint32_t quad[4][3] = {{v[0], m[0], m[2]}, {m[0], v[1], m[1]}, {m[2], m[1], v[2]},
                               {m[0], m[1], m[2]}};
        memcpy(t, quad, sizeof quad);
    }
    out.pos[out.nverts] = v3s(0.0f);
    free(keys);
    free(vals);
    return out;
}

/* ---- glint back-end ---- */

/* mesh_init on fresh copies of the arrays; returns its wall time. */
static double glint_build(const tris *t, size_t *bytes, int *kept);

/* What a build row builds: glint's structure and Embree's over the same
 * primitives, each build timed on its own (wall seconds). */
typedef struct subject {
    const char *name; /* in the row's label, with the count */
    double (*glint)(const void *data);
    double (*embree)(RTCDevice dev, const void *data);
    const void *data;
} subject;

/* sub's glint build with the process pinned to its first CPU, so that the
 * build runs on one thread; the affinity is restored after. */
static double glint_build_one_cpu(const subject *sub)
{
    cpu_set_t all, one;
    if (sched_getaffinity(0, sizeof all, &all) != 0)
        die("sched_getaffinity failed");
    CPU_ZERO(&one);
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &all)) {
            CPU_SET(c, &one);
            break;
        }
    if (sched_setaffinity(0, sizeof one, &one) != 0)
        die("sched_setaffinity failed");
    double dt = sub->glint(sub->data);
    sched_setaffinity(0, sizeof all, &all);
    return dt;
}

static double glint_build(const tris *t, size_t *bytes, int *kept)
{
    mesh m;
    memset(&m, 0, sizeof m);
    m.pos = xmalloc(sizeof(vec3) * (size_t)t->nverts);
    memcpy(m.pos, t->pos, sizeof(vec3) * (size_t)t->nverts);
    m.tri = xmalloc(12 * (size_t)t->ntris);
    memcpy(m.tri, t->tri, 12 * (size_t)t->ntris);
    m.nverts = t->nverts;
    m.ntris = t->ntris;
    glint_error err = {0};
    double t0 = now();
    glint_rc rc = mesh_init(&m, "raybench", 0, NULL, &err);
    double dt = now() - t0;
    if (rc != GLINT_OK)
        die(err.msg);
    if (bytes)
        *bytes = mesh_bytes(&m);
    if (kept)
        *kept = m.ntris;
    mesh_free(&m);
    return dt;
}

/* ---- Embree back-end ---- */

typedef struct embree_mem {
    atomic_llong cur, peak;
} embree_mem;

/* Called by Embree before or after each allocation (> 0) and free (< 0);
 * we never cancel, so every call counts. */
static bool embree_monitor(void *user, ssize_t bytes, bool post)
{
    (void)post;
    embree_mem *m = user;
    long long c = atomic_fetch_add(&m->cur, (long long)bytes) + (long long)bytes;
    long long p = atomic_load(&m->peak);
    while (c > p && !atomic_compare_exchange_weak(&m->peak, &p, c))
        ;
    return true;
}

static void embree_error(void *user, enum RTCError code, const char *str)
{
    (void)user;
    fprintf(stderr, "raybench: embree error %d: %s\n", (int)code, str ? str : "");
    exit(1);
}

static RTCDevice embree_device(const char *config, embree_mem *mem)
{
    RTCDevice d = rtcNewDevice(config);
    if (!d)
        die("rtcNewDevice failed");
    rtcSetDeviceErrorFunction(d, embree_error, NULL);
    if (mem)
        rtcSetDeviceMemoryMonitorFunction(d, embree_monitor, mem);
    return d;
}

/* Commits g and attaches it to sc, then commits sc: the wall time of
 * Embree's build. */
static double embree_commit(RTCScene sc, RTCGeometry g)
{
    double t0 = now();
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    return now() - t0;
}

/* A scene of one triangle geometry sharing t's arrays, built with high
 * quality; *build_s is the wall time of committing it. */
static RTCScene embree_scene(RTCDevice dev, const tris *t, double *build_s)
{
    RTCScene sc = rtcNewScene(dev);
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, t->pos, 0,
                               sizeof(vec3), (size_t)t->nverts);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, t->tri, 0, 12,
                               (size_t)t->ntris);
    double dt = embree_commit(sc, g);
    if (build_s)
        *build_s = dt;
    return sc;
}

/* ---- rays ---- */

typedef struct rayset {
    size_t n;
    vec3 *o, *d;  /* d is unit length */
    float *tmax;  /* far end for occlusion queries (closest hit: no limit) */
    bool coherent; /* a camera's, in pixel order: glint traces them eight at a time */
} rayset;

static rayset rayset_new(size_t n)
{
    return (rayset){n, xmalloc(sizeof(vec3) * n), xmalloc(sizeof(vec3) * n),
                    xmalloc(sizeof(float) * n), false};
}

/* A camera on the +z side of the bounds, looking at their centre, 40
 * degrees wide, far enough that the bounds fill about 90% of the frame. */
static rayset primary_rays(aabb b, int w, int h)
{
    vec3 c = aabb_center(b), e = aabb_extent(b);
    float hfov = 40.0f, th = tanf(hfov * (float)(M_PI / 360.0)), tv = th * (float)h / (float)w;
    float dist = fmaxf(0.55f * e.x / th, 0.55f * e.y / tv) + 0.5f * e.z;
    camera cam = {.eye = v3(c.x, c.y, c.z + dist), .target = c, .up = v3(0, 1, 0), .hfov = hfov,
                  .projection = CAMERA_PERSPECTIVE};
    camera_frame f = camera_frame_make(&cam, w, h);
    rayset rs = rayset_new((size_t)w * (size_t)h);
    rs.coherent = true;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            ray r;
            camera_ray(&f, (float)x + 0.5f, (float)y + 0.5f, 0.5f, 0.5f, &r);
            rs.o[i] = r.o;
            rs.d[i] = v3_norm(r.d);
            rs.tmax[i] = INFINITY;
        }
    return rs;
}

static rayset random_rays(aabb b, size_t n, uint64_t seed)
{
    vec3 c = aabb_center(b), e = aabb_extent(b);
    float radius = 0.75f * v3_len(e); /* 1.5 times the half diagonal */
    rng r = rng_seed(seed, 1);
    rayset rs = rayset_new(n);
    for (size_t i = 0; i < n; i++) {
        float z = 1.0f - 2.0f * rng_float(&r), phi = 2.0f * (float)M_PI * rng_float(&r);
        float s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
        vec3 o = v3_madd(c, v3(s * cosf(phi), s * sinf(phi), z), radius);
        vec3 p = v3_add(b.lo, v3_mul(e, v3(rng_float(&r), rng_float(&r), rng_float(&r))));
        vec3 d = v3_sub(p, o);
        float len = v3_len(d);
        rs.o[i] = o;
        rs.d[i] = v3_scale(d, 1.0f / len);
        rs.tmax[i] = len;
    }
    return rs;
}

static void rayset_free(rayset *rs)
{
    free(rs->o);
    free(rs->d);
    free(rs->tmax);
}

/* ---- running a batch of queries ---- */

typedef enum backend { GLINT, EMBREE } backend;
typedef enum query { CLOSEST, OCCLUDED } query;

typedef struct targets {
    const scene *gs;  /* the glint scene: one object, the mesh */
    const mesh *gm;   /* the same mesh */
    bool mesh_path;   /* glint: query the mesh directly, not the scene */
    RTCScene es;
} targets;

typedef struct job {
    const targets *tg;
    backend be;
    query q;
    const rayset *rs;
    float *t;     /* CLOSEST: distance to the hit, INFINITY for none */
    uint8_t *hit; /* OCCLUDED: 1 when something blocks the segment */
    atomic_size_t next;
} job;

/* Nearest hits of a coherent set, eight neighbouring rays at a time
 * (scene_intersect8, mesh_intersect8), as the renderer traces camera rays. */
static void glint_packets(job *j, size_t lo, size_t hi)
{
    const rayset *rs = j->rs;
    const targets *tg = j->tg;
    for (size_t i = lo; i < hi; i += 8) {
        ray8 r8;
        int active = 0;
        for (int k = 0; k < 8; k++) {
            size_t at = i + (size_t)k < hi ? i + (size_t)k : i; /* idle lanes repeat ray i */
            active |= (i + (size_t)k < hi) << k;
            r8.ox[k] = rs->o[at].x, r8.oy[k] = rs->o[at].y, r8.oz[k] = rs->o[at].z;
            r8.dx[k] = rs->d[at].x, r8.dy[k] = rs->d[at].y, r8.dz[k] = rs->d[at].z;
            r8.tmin[k] = 0.0f, r8.tmax[k] = INFINITY, r8.time[k] = 0.0f;
        }
        int found;
        if (tg->mesh_path) {
            shape_hit h[8];
            found = mesh_intersect8(tg->gm, &r8, active, h);
            for (int k = 0; k < 8 && i + (size_t)k < hi; k++)
                j->t[i + (size_t)k] = found >> k & 1 ? h[k].t : INFINITY;
        } else {
            scene_hit h[8];
            found = scene_intersect8(tg->gs, &r8, active, h);
            for (int k = 0; k < 8 && i + (size_t)k < hi; k++)
                j->t[i + (size_t)k] = found >> k & 1 ? h[k].h.t : INFINITY;
        }
    }
}

static void glint_chunk(job *j, size_t lo, size_t hi)
{
    const rayset *rs = j->rs;
    const targets *tg = j->tg;
    if (j->q == CLOSEST && rs->coherent) {
        glint_packets(j, lo, hi);
    } else if (j->q == OCCLUDED) {
        for (size_t i = lo; i < hi; i++) {
            ray r = ray_make(rs->o[i], rs->d[i], rs->tmax[i]);
            j->hit[i] = tg->mesh_path ? mesh_occluded(tg->gm, &r) : scene_occluded_opaque(tg->gs, &r);
        }
    } else if (tg->mesh_path) {
        for (size_t i = lo; i < hi; i++) {
            ray r = ray_make(rs->o[i], rs->d[i], INFINITY);
            shape_hit h;
            j->t[i] = mesh_intersect(tg->gm, &r, &h) ? h.t : INFINITY;
        }
    } else {
        for (size_t i = lo; i < hi; i++) {
            ray r = ray_make(rs->o[i], rs->d[i], INFINITY);
            scene_hit h;
            j->t[i] = scene_intersect(tg->gs, &r, &h) ? h.h.t : INFINITY;
        }
    }
}

static void embree_chunk(job *j, size_t lo, size_t hi)
{
    const rayset *rs = j->rs;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (j->q == OCCLUDED) {
        for (size_t i = lo; i < hi; i++) {
            struct RTCRay r;
            r.org_x = rs->o[i].x;
            r.org_y = rs->o[i].y;
            r.org_z = rs->o[i].z;
            r.dir_x = rs->d[i].x;
            r.dir_y = rs->d[i].y;
            r.dir_z = rs->d[i].z;
            r.tnear = 0.0f;
            r.tfar = rs->tmax[i];
            r.time = 0.0f;
            r.mask = UINT32_MAX;
            r.id = 0;
            r.flags = 0;
            rtcOccluded1(j->tg->es, &ctx, &r);
            j->hit[i] = r.tfar < 0.0f; /* set to -inf when occluded */
        }
    } else {
        for (size_t i = lo; i < hi; i++) {
            struct RTCRayHit rh;
            rh.ray.org_x = rs->o[i].x;
            rh.ray.org_y = rs->o[i].y;
            rh.ray.org_z = rs->o[i].z;
            rh.ray.dir_x = rs->d[i].x;
            rh.ray.dir_y = rs->d[i].y;
            rh.ray.dir_z = rs->d[i].z;
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = INFINITY;
            rh.ray.time = 0.0f;
            rh.ray.mask = UINT32_MAX;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(j->tg->es, &ctx, &rh);
            j->t[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : INFINITY;
        }
    }
}

static void *worker(void *arg)
{
    job *j = arg;
    for (;;) {
        size_t lo = atomic_fetch_add(&j->next, CHUNK);
        if (lo >= j->rs->n)
            return NULL;
        size_t hi = lo + CHUNK < j->rs->n ? lo + CHUNK : j->rs->n;
        if (j->be == GLINT)
            glint_chunk(j, lo, hi);
        else
            embree_chunk(j, lo, hi);
    }
}

/* Runs every ray of the job on `threads` threads (the caller is one of
 * them); returns the wall time. */
static double run_job(job *j, int threads)
{
    pthread_t th[MAX_THREADS];
    atomic_store(&j->next, 0);
    double t0 = now();
    int started = 0;
    for (int i = 1; i < threads; i++, started++)
        if (pthread_create(&th[started], NULL, worker, j) != 0)
            die("pthread_create failed");
    worker(j);
    for (int i = 0; i < started; i++)
        pthread_join(th[i], NULL);
    return now() - t0;
}

/* ---- output ---- */

static void row(const char *id, const char *what, const char *g, const char *e,
                const char *ratio, const char *target)
{
    printf("| %s | %s | %s | %s | %s | %s |\n", id, what, g, e, ratio, target);
    fflush(stdout);
}

/* A ratio cell: the value and whether it meets the goal (r >= goal when
 * at_least, else r <= goal). */
static void ratio_cell(char *buf, size_t n, double r, double goal, bool at_least)
{
    bool met = at_least ? r >= goal : r <= goal;
    snprintf(buf, n, "%.2f (%s)", r, met ? "met" : "missed");
}

typedef struct opts {
    int runs, threads, width, height, subdiv, spheres;
    size_t nrays;
    const char *mesh;
    bool mesh_path, trace, build, memory;
} opts;

/* Timing of one query over one ray set on `threads` threads, glint then
 * Embree alternating; one row. */
static void time_queries(const opts *o, const targets *tg, const rayset *rs, query q, int threads,
                         const char *what, float *gt, float *et, uint8_t *gh, uint8_t *eh)
{
    job jg = {tg, GLINT, q, rs, gt, gh, 0}, je = {tg, EMBREE, q, rs, et, eh, 0};
    double *tgl = xmalloc(sizeof(double) * (size_t)o->runs);
    double *tem = xmalloc(sizeof(double) * (size_t)o->runs);
    for (int r = 0; r < o->runs; r++) {
        if (r % 2 == 0) {
            tgl[r] = run_job(&jg, threads);
            tem[r] = run_job(&je, threads);
        } else {
            tem[r] = run_job(&je, threads);
            tgl[r] = run_job(&jg, threads);
        }
    }
    double g = (double)rs->n / median(tgl, o->runs) * 1e-6;
    double e = (double)rs->n / median(tem, o->runs) * 1e-6;
    char cg[32], ce[32], cr[48], label[160];
    snprintf(cg, sizeof cg, "%.2f", g);
    snprintf(ce, sizeof ce, "%.2f", e);
    /* coherent primary rays must match Embree; incoherent ones reach 0.8 */
    double goal = q == CLOSEST && strstr(what, "primary") ? 1.0 : 0.8;
    ratio_cell(cr, sizeof cr, g / e, goal, true);
    snprintf(label, sizeof label, "%s, %d thread%s: Mrays/s", what, threads, threads == 1 ? "" : "s");
    row("2", label, cg, ce, cr, goal == 1.0 ? "glint ÷ Embree ≥ 1.0" : "glint ÷ Embree ≥ 0.8");
    free(tgl);
    free(tem);
}

/* Warm-up run of each back-end, then the answers compared ray by ray.
 * Returns false when they agree on fewer than AGREE_TARGET percent. */
static bool agreement(const targets *tg, const rayset *rs, query q, int threads, const char *what,
                      float *gt, float *et, uint8_t *gh, uint8_t *eh)
{
    job jg = {tg, GLINT, q, rs, gt, gh, 0}, je = {tg, EMBREE, q, rs, et, eh, 0};
    run_job(&jg, threads);
    run_job(&je, threads);
    size_t same = 0, ng = 0, ne = 0, both = 0, close = 0;
    for (size_t i = 0; i < rs->n; i++) {
        bool a = q == OCCLUDED ? gh[i] != 0 : isfinite(gt[i]);
        bool b = q == OCCLUDED ? eh[i] != 0 : isfinite(et[i]);
        ng += a;
        ne += b;
        same += a == b;
        if (q == CLOSEST && a && b) {
            both++;
            close += fabsf(gt[i] - et[i]) <= 1e-4f * fmaxf(1.0f, et[i]);
        }
    }
    double pct = 100.0 * (double)same / (double)rs->n;
    char cg[48], ce[48], cr[48], label[160];
    const char *noun = q == OCCLUDED ? "blocked" : "hits";
    snprintf(cg, sizeof cg, "%zu %s", ng, noun);
    snprintf(ce, sizeof ce, "%zu %s", ne, noun);
    snprintf(cr, sizeof cr, "%.4f %% (%s)", pct, pct >= AGREE_TARGET ? "met" : "missed");
    snprintf(label, sizeof label, "%s: %s agreement on %zu rays", what,
             q == OCCLUDED ? "blocked/clear" : "hit/miss", rs->n);
    row("2", label, cg, ce, cr, "≥ 99.9 %");
    if (q == CLOSEST)
        fprintf(stderr, "raybench: %s: distances within 1e-4 (relative) on %.4f %% of %zu common hits\n",
                what, both ? 100.0 * (double)close / (double)both : 100.0, both);
    return pct >= AGREE_TARGET;
}

/* Row 2 for one mesh; prefix names its incoherent rows ("" for the
 * bunny's). */
static bool trace_rows(const opts *o, const targets *tg, aabb bounds, const char *name,
                       const char *prefix)
{
    bool ok = true;
    rayset prim = primary_rays(bounds, o->width, o->height);
    rayset inco = random_rays(bounds, o->nrays, 20240601);
    size_t nmax = prim.n > inco.n ? prim.n : inco.n;
    float *gt = xmalloc(sizeof(float) * nmax), *et = xmalloc(sizeof(float) * nmax);
    uint8_t *gh = xmalloc(nmax), *eh = xmalloc(nmax);
    memset(gt, 0, sizeof(float) * nmax);
    memset(et, 0, sizeof(float) * nmax);
    memset(gh, 0, nmax);
    memset(eh, 0, nmax);

    char what[3][128];
    struct {
        const rayset *rs;
        query q;
        const char *name;
    } sets[3] = {{&prim, CLOSEST, what[0]}, {&inco, CLOSEST, what[1]},
                 {&inco, OCCLUDED, what[2]}};
    snprintf(what[0], sizeof what[0], "%s primary %dx%d", name, o->width, o->height);
    snprintf(what[1], sizeof what[1], "%sincoherent closest hit", prefix);
    snprintf(what[2], sizeof what[2], "%sincoherent occlusion", prefix);
    for (int s = 0; s < 3; s++) {
        ok &= agreement(tg, sets[s].rs, sets[s].q, o->threads, sets[s].name, gt, et, gh, eh);
        time_queries(o, tg, sets[s].rs, sets[s].q, 1, sets[s].name, gt, et, gh, eh);
        if (o->threads > 1)
            time_queries(o, tg, sets[s].rs, sets[s].q, o->threads, sets[s].name, gt, et, gh, eh);
    }
    free(gt);
    free(et);
    free(gh);
    free(eh);
    rayset_free(&prim);
    rayset_free(&inco);
    return ok;
}

/* Row 2 on triangles t (the bunny subdivided), in a scene of their own. */
static bool big_trace_rows(const opts *o, const tris *t, const char *name, RTCDevice dev)
{
    mesh *m = xmalloc(sizeof *m);
    memset(m, 0, sizeof *m);
    m->pos = xmalloc(sizeof(vec3) * (size_t)t->nverts);
    memcpy(m->pos, t->pos, sizeof(vec3) * (size_t)t->nverts);
    m->tri = xmalloc(12 * (size_t)t->ntris);
    memcpy(m->tri, t->tri, 12 * (size_t)t->ntris);
    m->nverts = t->nverts;
    m->ntris = t->ntris;
    glint_error err = {0};
    scene *s = scene_new();
    material mat = material_default();
    shape sh = shape_mesh(m);
    if (mesh_init(m, name, 0, NULL, &err) != GLINT_OK || !s || scene_add_mesh(s, m) < 0 ||
        scene_add_object(s, &sh, scene_add_material(s, &mat), -1) < 0 ||
        scene_build(s, &err) != GLINT_OK)
        die(err.msg[0] ? err.msg : "out of memory");
    double dt;
    targets tg = {s, m, o->mesh_path, embree_scene(dev, t, &dt)};
    char prefix[96];
    snprintf(prefix, sizeof prefix, "%s: ", name);
    bool ok = trace_rows(o, &tg, m->bounds, name, prefix);
    rtcReleaseScene(tg.es);
    scene_free(s);
    return ok;
}

/* ---- build subjects: a mesh, and spheres ---- */

static double mesh_glint(const void *data) { return glint_build(data, NULL, NULL); }

static double mesh_embree(RTCDevice dev, const void *data)
{
    double dt;
    rtcReleaseScene(embree_scene(dev, data, &dt));
    return dt;
}

/* n spheres as row 7 places them (sphere_field.h). */
typedef struct spheres {
    int n;
    float (*xyzr)[4];
    scene *s; /* glint's scene of them, built again by each timing */
} spheres;

static spheres spheres_make(int n)
{
    spheres sp = {n, xmalloc(sizeof *sp.xyzr * (size_t)n), scene_new()};
    if (!sp.s)
        die("out of memory");
    float radius = sphere_field_radius(n);
    material m = material_default();
    int mi = scene_add_material(sp.s, &m);
    rng r = sphere_field_rng();
    for (int i = 0; i < n; i++) {
        vec3 c = sphere_field_next(&r);
        shape sh = shape_sphere(c, radius);
        if (scene_add_object(sp.s, &sh, mi, -1) < 0)
            die("out of memory");
        sp.xyzr[i][0] = c.x, sp.xyzr[i][1] = c.y, sp.xyzr[i][2] = c.z, sp.xyzr[i][3] = radius;
    }
    return sp;
}

/* scene_build as a render does it (object bounds, the binned SAH build,
 * collapsing to the wide BVH). */
static double spheres_glint(const void *data)
{
    const spheres *sp = data;
    glint_error err = {0};
    double t0 = now();
    if (scene_build(sp->s, &err) != GLINT_OK)
        die(err.msg);
    return now() - t0;
}

/* Embree's own sphere primitive (RTC_GEOMETRY_TYPE_SPHERE_POINT), high
 * build quality, on a shared (x, y, z, r) buffer. */
static double spheres_embree(RTCDevice dev, const void *data)
{
    const spheres *sp = data;
    RTCScene sc = rtcNewScene(dev);
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sp->xyzr, 0,
                               sizeof *sp->xyzr, (size_t)sp->n);
    double dt = embree_commit(sc, g);
    rtcReleaseScene(sc);
    return dt;
}

/* Build times of glint against Embree, both on all threads and both on
 * one, alternating. */
static void build_rows(const opts *o, const subject *sub, RTCDevice all, RTCDevice one)
{
    double *ga = xmalloc(sizeof(double) * (size_t)o->runs);
    double *g1 = xmalloc(sizeof(double) * (size_t)o->runs);
    double *ea = xmalloc(sizeof(double) * (size_t)o->runs);
    double *e1 = xmalloc(sizeof(double) * (size_t)o->runs);
    /* one untimed build of each first: page-faults, thread pools */
    sub->glint(sub->data);
    sub->embree(all, sub->data);
    sub->embree(one, sub->data);
    for (int r = 0; r < o->runs; r++) {
        if (r % 2 == 0) {
            ga[r] = sub->glint(sub->data);
            g1[r] = glint_build_one_cpu(sub);
        }
        ea[r] = sub->embree(all, sub->data);
        e1[r] = sub->embree(one, sub->data);
        if (r % 2 == 1) {
            ga[r] = sub->glint(sub->data);
            g1[r] = glint_build_one_cpu(sub);
        }
    }
    double mga = median(ga, o->runs), mg1 = median(g1, o->runs);
    double mea = median(ea, o->runs), me1 = median(e1, o->runs);
    char cg[32], ce[32], cr[48], label[200];
    snprintf(cg, sizeof cg, "%.4f", mga);
    snprintf(ce, sizeof ce, "%.4f", mea);
    ratio_cell(cr, sizeof cr, mga / mea, 1.0, false);
    snprintf(label, sizeof label, "BVH build, %s, s: both %d threads", sub->name, o->threads);
    row("3", label, cg, ce, cr, "glint ÷ Embree ≤ 1.0");
    snprintf(cg, sizeof cg, "%.4f", mg1);
    snprintf(ce, sizeof ce, "%.4f", me1);
    ratio_cell(cr, sizeof cr, mg1 / me1, 1.0, false);
    snprintf(label, sizeof label, "BVH build, %s, s: both 1 thread", sub->name);
    row("3", label, cg, ce, cr, "glint ÷ Embree ≤ 1.0");
    free(ga);
    free(g1);
    free(ea);
    free(e1);
}

static void bytes_row(const tris *t, const char *name, RTCDevice dev, embree_mem *mem)
{
    size_t gbytes;
    int kept;
    glint_build(t, &gbytes, &kept);
    long long before = atomic_load(&mem->cur);
    atomic_store(&mem->peak, before);
    double dt;
    RTCScene sc = embree_scene(dev, t, &dt);
    long long held = atomic_load(&mem->cur) - before, peak = atomic_load(&mem->peak) - before;
    rtcReleaseScene(sc);
    size_t shared = sizeof(vec3) * (size_t)t->nverts + 12 * (size_t)t->ntris;
    double g = (double)gbytes / kept, e = (double)((size_t)held + shared) / t->ntris;
    fprintf(stderr, "raybench: %s: Embree holds %lld bytes after the build (peak %lld during it) "
                    "besides the %zu shared vertex and index bytes; glint kept %d of %d triangles\n",
            name, held, peak, shared, kept, t->ntris);
    char cg[32], ce[32], cr[48], label[160];
    snprintf(cg, sizeof cg, "%.1f", g);
    snprintf(ce, sizeof ce, "%.1f", e);
    snprintf(cr, sizeof cr, "%.2f", g / e);
    snprintf(label, sizeof label, "bytes per triangle, mesh + BVH, %s", name);
    row("3", label, cg, ce, cr, "glint ÷ Embree (lower is better)");
}

/* ---- peak memory, one fresh process per back-end ---- */

static void write_tris(const char *path, const tris *t)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(&t->nverts, sizeof(int), 1, f) != 1 || fwrite(&t->ntris, sizeof(int), 1, f) != 1 ||
        fwrite(t->pos, sizeof(vec3), (size_t)t->nverts, f) != (size_t)t->nverts ||
        fwrite(t->tri, 12, (size_t)t->ntris, f) != (size_t)t->ntris || fclose(f) != 0)
        die("cannot write the temporary mesh file");
}

static tris read_tris(const char *path)
{
    FILE *f = fopen(path, "rb");
    int nv, nt;
    if (!f || fread(&nv, sizeof nv, 1, f) != 1 || fread(&nt, sizeof nt, 1, f) != 1 || nv <= 0 || nt <= 0)
        die("cannot read the temporary mesh file");
    tris t = {xmalloc(sizeof(vec3) * ((size_t)nv + 1)), xmalloc(12 * (size_t)nt), nv, nt};
    if (fread(t.pos, sizeof(vec3), (size_t)nv, f) != (size_t)nv ||
        fread(t.tri, 12, (size_t)nt, f) != (size_t)nt)
        die("cannot read the temporary mesh file");
    t.pos[nv] = v3s(0.0f);
    fclose(f);
    return t;
}

/* Peak resident set of this process in KiB. getrusage's ru_maxrss would
 * be the obvious source, but Linux carries it over from the forking parent
 * through execve, so it would report the parent's peak; VmHWM in
 * /proc/self/status belongs to the new address space alone. */
static long peak_rss_kib(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long kib = -1;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmHWM: %ld kB", &kib) == 1)
            break;
    if (f)
        fclose(f);
    if (kib < 0) {
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        kib = ru.ru_maxrss;
    }
    return kib;
}

/* The child: reads the triangles, builds with one back-end, prints its
 * peak resident set in KiB. */
static int peak_child(const char *backend_name, const char *path)
{
    tris t = read_tris(path);
    if (strcmp(backend_name, "glint") == 0) {
        mesh m;
        memset(&m, 0, sizeof m);
        m.pos = t.pos; /* mesh_init takes the arrays */
        m.tri = t.tri;
        m.nverts = t.nverts;
        m.ntris = t.ntris;
        glint_error err = {0};
        if (mesh_init(&m, "raybench", 0, NULL, &err) != GLINT_OK)
            die(err.msg);
        printf("%ld\n", peak_rss_kib());
        mesh_free(&m);
    } else {
        RTCDevice dev = embree_device(NULL, NULL);
        double dt;
        RTCScene sc = embree_scene(dev, &t, &dt);
        printf("%ld\n", peak_rss_kib());
        rtcReleaseScene(sc);
        rtcReleaseDevice(dev);
        tris_free(&t);
    }
    return 0;
}

static long run_peak_child(const char *backend_name, const char *path)
{
    int fd[2];
    if (pipe(fd) != 0)
        die("pipe failed");
    pid_t pid = fork();
    if (pid < 0)
        die("fork failed");
    if (pid == 0) {
        dup2(fd[1], STDOUT_FILENO);
        close(fd[0]);
        close(fd[1]);
        execl("/proc/self/exe", "raybench", "--peak-child", backend_name, path, (char *)NULL);
        _exit(127);
    }
    close(fd[1]);
    char buf[64] = {0};
    ssize_t n = read(fd[0], buf, sizeof buf - 1);
    close(fd[0]);
    int status;
    waitpid(pid, &status, 0);
    if (n <= 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        die("the peak-memory child failed");
    return atol(buf);
}

static void peak_row(const tris *t, const char *name)
{
    char path[] = "/tmp/raybench-XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0)
        die("mkstemp failed");
    close(fd);
    write_tris(path, t);
    long g = run_peak_child("glint", path), e = run_peak_child("embree", path);
    unlink(path);
    char cg[32], ce[32], cr[48], label[200];
    snprintf(cg, sizeof cg, "%.1f", g / 1024.0);
    snprintf(ce, sizeof ce, "%.1f", e / 1024.0);
    snprintf(cr, sizeof cr, "%.2f", (double)g / (double)e);
    snprintf(label, sizeof label,
             "peak RSS, MiB: a process reading %s (%d triangles) and building", name, t->ntris);
    row("3", label, cg, ce, cr, "glint ÷ Embree (lower is better)");
}

/* ---- main ---- */

static void usage(int code)
{
    fprintf(code ? stderr : stdout,
            "usage: raybench [--runs N] [--rays N] [--size WxH] [--threads N] [--subdiv N]\n"
            "                [--spheres N] [--mesh FILE] [--glint-path scene|mesh] [--only trace,build,memory]\n"
            "       raybench --version\n");
    exit(code);
}

int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "--peak-child") == 0)
        return peak_child(argv[2], argv[3]);
    opts o = {5, glint_default_threads(), 1920, 1080, 2, 1000000, 2000000,
              "/usr/share/glmark2/models/bunny.obj", false, true, true, true};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
            usage(0);
        if (strcmp(a, "--version") == 0) {
            RTCDevice d = embree_device(NULL, NULL);
            ssize_t ver = rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION);
            printf("embree %zd.%zd.%zd\n", ver / 10000, ver / 100 % 100, ver % 100);
            rtcReleaseDevice(d);
            return 0;
        }
        if (!v)
            usage(2);
        i++;
        if (strcmp(a, "--runs") == 0)
            o.runs = atoi(v);
        else if (strcmp(a, "--rays") == 0)
            o.nrays = (size_t)atof(v);
        else if (strcmp(a, "--size") == 0) {
            if (sscanf(v, "%dx%d", &o.width, &o.height) != 2)
                usage(2);
        } else if (strcmp(a, "--threads") == 0)
            o.threads = atoi(v);
        else if (strcmp(a, "--subdiv") == 0)
            o.subdiv = atoi(v);
        else if (strcmp(a, "--spheres") == 0)
            o.spheres = atoi(v);
        else if (strcmp(a, "--mesh") == 0)
            o.mesh = v;
        else if (strcmp(a, "--glint-path") == 0) {
            if (strcmp(v, "scene") != 0 && strcmp(v, "mesh") != 0)
                usage(2);
            o.mesh_path = strcmp(v, "mesh") == 0;
        } else if (strcmp(a, "--only") == 0) {
            o.trace = strstr(v, "trace") != NULL;
            o.build = strstr(v, "build") != NULL;
            o.memory = strstr(v, "memory") != NULL;
        } else
            usage(2);
    }
    if (o.runs < 1 || o.threads < 1 || o.threads > MAX_THREADS || o.width < 1 || o.height < 1 ||
        o.nrays < 1 || o.subdiv < 0 || o.subdiv > 3 || o.spheres < 0)
        usage(2);

    glint_error err = {0};
    mesh_file mf;
    if (mesh_import(o.mesh, NULL, &mf, &err) != GLINT_OK) {
        fprintf(stderr, "raybench: %s\n", err.msg);
        return 1;
    }
    mesh *m = mf.mesh;
    mf.mesh = NULL; /* the scene takes it */
    mesh_file_free(&mf);
    scene *s = scene_new();
    material mat = material_default();
    shape sh = shape_mesh(m);
    if (!s || scene_add_mesh(s, m) < 0 || scene_add_object(s, &sh, scene_add_material(s, &mat), -1) < 0)
        die("out of memory");
    if (scene_build(s, &err) != GLINT_OK) {
        fprintf(stderr, "raybench: %s\n", err.msg);
        return 1;
    }
    /* The triangles as glint keeps them (degenerate ones dropped, leaf
     * order) are what Embree gets. */
    tris bunny = tris_copy(m->pos, m->nverts, (const uint32_t(*)[3])m->tri, m->ntris);
    fprintf(stderr, "raybench: %s: %d vertices, %d triangles; glint queries %s\n", o.mesh, m->nverts,
            m->ntris,
            o.mesh_path ? "the mesh alone (mesh_intersect, mesh_occluded; primary rays: "
                          "mesh_intersect8, eight at a time)"
                        : "a scene holding the mesh (scene_intersect, scene_occluded_opaque; "
                          "primary rays: scene_intersect8, eight at a time; Embree: rtcIntersect1)");

    embree_mem mem = {0, 0};
    RTCDevice dev = embree_device(NULL, &mem);
    bool ok = true;
    if (o.trace) {
        double dt;
        targets tg = {s, m, o.mesh_path, embree_scene(dev, &bunny, &dt)};
        ok = trace_rows(&o, &tg, m->bounds, "bunny", "");
        rtcReleaseScene(tg.es);
    }
    tris big = bunny;
    char bigname[64] = "bunny";
    for (int i = 0; i < o.subdiv; i++) {
        tris next = subdivide(&big);
        if (i > 0)
            tris_free(&big);
        big = next;
    }
    if (o.subdiv > 0)
        snprintf(bigname, sizeof bigname, "bunny, each triangle in %d", 1 << (2 * o.subdiv));
    if (o.trace && o.subdiv > 0) /* the second, larger mesh */
        ok &= big_trace_rows(&o, &big, bigname, dev);
    if (o.build) {
        RTCDevice one = embree_device("threads=1", NULL);
        char label[200];
        snprintf(label, sizeof label, "bunny (%d triangles)", bunny.ntris);
        build_rows(&o, &(subject){label, mesh_glint, mesh_embree, &bunny}, dev, one);
        if (o.subdiv > 0) {
            snprintf(label, sizeof label, "%s (%d triangles)", bigname, big.ntris);
            build_rows(&o, &(subject){label, mesh_glint, mesh_embree, &big}, dev, one);
        }
        if (o.spheres > 0) {
            spheres sp = spheres_make(o.spheres);
            snprintf(label, sizeof label, "%d random spheres (scene_build; Embree: sphere points)",
                     o.spheres);
            build_rows(&o, &(subject){label, spheres_glint, spheres_embree, &sp}, dev, one);
            scene_free(sp.s);
            free(sp.xyzr);
        }
        rtcReleaseDevice(one);
    }
    if (o.memory) {
        bytes_row(&bunny, "bunny", dev, &mem);
        if (o.subdiv > 0)
            bytes_row(&big, bigname, dev, &mem);
        peak_row(&bunny, "bunny");
        if (o.subdiv > 0)
            peak_row(&big, bigname);
    }
    if (o.subdiv > 0)
        tris_free(&big);
    tris_free(&bunny);
    rtcReleaseDevice(dev);
    scene_free(s);
    return ok ? 0 : 3;
}

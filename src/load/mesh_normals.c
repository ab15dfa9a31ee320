#include "mesh_normals.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct keyed {
    float p[3];
    uint32_t v;
} keyed;

typedef struct crease {
    mesh_data *md;
    uint32_t v0, nv, t0, nt;
    keyed *order;      /* vertices sorted by position */
    uint32_t *group;   /* vertex -> welded position */
    uint32_t *start;   /* group -> first entry in faces (ngroups + 1) */
    uint32_t *faces;   /* triangles around each group */
    double *weight;    /* per entry of faces: its corner's angle / the triangle's len */
    double (*fn)[3];   /* triangle normals, length twice the area */
    double *len;       /* their lengths */
} crease;

/* Orders by position; NaN coordinates (dropped later) compare equal to
 * everything, which only welds what will not be drawn. */
static int by_position(const void *a, const void *b)
{
    const float *p = ((const keyed *)a)->p, *q = ((const keyed *)b)->p;
    for (int k = 0; k < 3; k++)
        if (p[k] < q[k] || p[k] > q[k])
            return p[k] < q[k] ? -1 : 1;
    return 0;
}

/* Welds vertices at one position; returns the number of groups. */
static uint32_t weld(crease *c)
{
    for (uint32_t i = 0; i < c->nv; i++) {
        memcpy(c->order[i].p, c->md->pos[c->v0 + i], sizeof c->order[i].p);
        c->order[i].v = i;
    }
    qsort(c->order, c->nv, sizeof *c->order, by_position);
    uint32_t g = 0;
    for (uint32_t i = 0; i < c->nv; i++) {
        if (i > 0 && by_position(&c->order[i - 1], &c->order[i]) != 0)
            g++;
        c->group[c->order[i].v] = g;
    }
    return c->nv ? g + 1 : 0;
}

static void face_normals(crease *c)
{
    for (uint32_t t = 0; t < c->nt; t++) {
        const uint32_t *tri = c->md->tri[c->t0 + t];
        const float *a = c->md->pos[tri[0]], *b = c->md->pos[tri[1]], *d = c->md->pos[tri[2]];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        double *n = c->fn[t];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        c->len[t] = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!isfinite(c->len[t]))
            c->len[t] = 0;
    }
}

/* The triangles around each group, in CSR form. */
static void incidence(crease *c, uint32_t ngroups)
{
    memset(c->start, 0, (ngroups + 1) * sizeof *c->start);
    for (uint32_t t = 0; t < c->nt; t++)
        for (int k = 0; k < 3; k++)
            c->start[c->group[c->md->tri[c->t0 + t][k] - c->v0] + 1]++;
    for (uint32_t g = 0; g < ngroups; g++)
        c->start[g + 1] += c->start[g];
    uint32_t *fill = (uint32_t *)c->order; /* free again: reused as cursors */
    memcpy(fill, c->start, ngroups * sizeof *fill);
    for (uint32_t t = 0; t < c->nt; t++)
        for (int k = 0; k < 3; k++)
            c->faces[fill[c->group[c->md->tri[c->t0 + t][k] - c->v0]]++] = t;
}

/* The angle of triangle h at its corner in group g (Thürmer and Wüthrich's
 * weight, which makes the result independent of how faces were split into
 * triangles). */
static double corner_angle(const crease *c, uint32_t h, uint32_t g)
{
    const uint32_t *tri = c->md->tri[c->t0 + h];
    int k = 0;
    while (k < 2 && c->group[tri[k] - c->v0] != g)
        k++;
    const float *p = c->md->pos[tri[k]], *a = c->md->pos[tri[(k + 1) % 3]],
                *b = c->md->pos[tri[(k + 2) % 3]];
    double u[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
    double v[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
    double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double angle = atan2(sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]),
                         u[0] * v[0] + u[1] * v[1] + u[2] * v[2]);
    return isfinite(angle) ? angle : 0;
}

/* Each entry's weight, computed once (a corner is in every fan of its
 * group's other corners). */
static void corner_weights(crease *c, uint32_t ngroups)
{
    for (uint32_t g = 0; g < ngroups; g++)
        for (uint32_t i = c->start[g]; i < c->start[g + 1]; i++) {
            uint32_t h = c->faces[i];
            c->weight[i] = c->len[h] > 0 ? corner_angle(c, h, g) / c->len[h] : 0;
        }
}

static void corner_normal(const crease *c, uint32_t t, uint32_t g, double cosmax, float out[3])
{
    double s[3] = {0, 0, 0};
    const double *n = c->fn[t];
    uint32_t from = c->start[g], to = c->start[g + 1];
    if (c->len[t] > 0 && to - from <= MESH_NORMALS_MAX_FAN) {
        for (uint32_t i = from; i < to; i++) {
            uint32_t h = c->faces[i];
            const double *m = c->fn[h];
            if (c->len[h] > 0 &&
                (m[0] * n[0] + m[1] * n[1] + m[2] * n[2]) >= cosmax * c->len[h] * c->len[t]) {
                double w = c->weight[i];
                for (int k = 0; k < 3; k++)
                    s[k] += m[k] * w;
            }
        }
    } else {
        memcpy(s, n, sizeof s);
    }
    double l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int k = 0; k < 3; k++)
        out[k] = l > 0 && isfinite(l) ? (float)(s[k] / l) : 0.0f;
}

/* Gives every corner its normal, splitting vertices as needed; the
 * vertices are rebuilt in scratch copies and copied back. */
static bool split(crease *c, double cosmax)
{
    mesh_data *md = c->md;
    uint32_t cap = 3 * c->nt, n = 0;
    int64_t *head = malloc(c->nv * sizeof *head), *next = malloc(cap * sizeof *next);
    uint32_t *src = malloc(cap * sizeof *src), (*tri)[3] = malloc(c->nt * sizeof *tri);
    float(*nrm)[3] = malloc(cap * sizeof *nrm);
    if (!head || !next || !src || !nrm || !tri) {
        free(head), free(next), free(src), free(nrm), free(tri);
        return false;
    }
    for (uint32_t v = 0; v < c->nv; v++)
        head[v] = -1;
    for (uint32_t t = 0; t < c->nt; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = md->tri[c->t0 + t][k] - c->v0;
            float nn[3];
            corner_normal(c, t, c->group[v], cosmax, nn);
            int64_t e = head[v];
            while (e >= 0 && memcmp(nrm[e], nn, sizeof nn) != 0)
                e = next[e];
            if (e < 0) {
                e = n++;
                memcpy(nrm[e], nn, sizeof nn);
                src[e] = v;
                next[e] = head[v];
                head[v] = e;
            }
            tri[t][k] = c->v0 + (uint32_t)e; /* md->tri is still read above */
        }
    /* copy the attributes of each new vertex's source (scratch first: ranges overlap) */
    bool ok = true;
    float(*tmp)[3] = malloc((size_t)n * sizeof *tmp);
    float(*tuv)[2] = md->uv ? malloc((size_t)n * sizeof *tuv) : NULL;
    float(*tcol)[3] = md->col ? malloc((size_t)n * sizeof *tcol) : NULL;
    if (!tmp || (md->uv && !tuv) || (md->col && !tcol)) {
        ok = false;
    } else {
        for (uint32_t e = 0; e < n; e++) {
            memcpy(tmp[e], md->pos[c->v0 + src[e]], sizeof tmp[e]);
            if (tuv)
                memcpy(tuv[e], md->uv[c->v0 + src[e]], sizeof tuv[e]);
            if (tcol)
                memcpy(tcol[e], md->col[c->v0 + src[e]], sizeof tcol[e]);
        }
        memcpy(md->tri + c->t0, tri, (size_t)c->nt * sizeof *tri);
        memcpy(md->pos + c->v0, tmp, (size_t)n * sizeof *tmp);
        memcpy(md->nrm + c->v0, nrm, (size_t)n * sizeof *nrm);
        if (tuv)
            memcpy(md->uv + c->v0, tuv, (size_t)n * sizeof *tuv);
        if (tcol)
            memcpy(md->col + c->v0, tcol, (size_t)n * sizeof *tcol);
        c->nv = n;
    }
    free(head), free(next), free(src), free(nrm), free(tmp), free(tuv), free(tcol), free(tri);
    return ok;
}

bool mesh_normals_crease(mesh_data *md, uint32_t v0, uint32_t *nv, uint32_t t0, uint32_t t1,
                         float angle)
{
    crease c = {md, v0, *nv, t0, t1 - t0, NULL, NULL, NULL, NULL, NULL, NULL, NULL};
    if (c.nt == 0)
        return true;
    size_t nv1 = c.nv ? c.nv : 1;
    c.order = malloc(nv1 * sizeof *c.order);
    c.group = malloc(nv1 * sizeof *c.group);
    c.start = malloc((nv1 + 1) * sizeof *c.start);
    c.faces = malloc(3 * (size_t)c.nt * sizeof *c.faces);
    c.fn = malloc(c.nt * sizeof *c.fn);
    c.len = malloc(c.nt * sizeof *c.len);
    c.weight = malloc(3 * (size_t)c.nt * sizeof *c.weight);
    bool ok = c.order && c.group && c.start && c.faces && c.fn && c.len && c.weight;
    if (ok) {
        uint32_t ngroups = weld(&c);
        face_normals(&c);
        incidence(&c, ngroups);
        corner_weights(&c, ngroups);
        double cosmax = cos((double)angle * 3.14159265358979323846 / 180.0) - 1e-6;
        ok = split(&c, angle >= 180.0f ? -2.0 : cosmax);
        if (ok)
            *nv = c.nv;
    }
    free(c.order), free(c.group), free(c.start), free(c.faces);
    free(c.fn), free(c.len), free(c.weight);
    return ok;
}

/* Polyhedra: checking and preparing the input (this file), the Platonic
 * presets (polyhedron_preset.c), and the ray queries (polyhedron_hit.c). */
#include "polyhedron.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct dvec {
    double x, y, z;
} dvec;

static dvec dv(vec3 a) { return (dvec){a.x, a.y, a.z}; }
static dvec dsub(dvec a, dvec b) { return (dvec){a.x - b.x, a.y - b.y, a.z - b.z}; }
static double ddot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

static bool fail(poly_error *why, poly_problem what, int face, int corner)
{
    *why = (poly_error){.what = what, .face = face, .corner = corner, .other = -1};
    return false;
}

/* The indices of each face: enough of them, in range, none twice. */
static bool check_indices(const polyhedron *p, poly_error *why)
{
    for (int f = 0; f < p->nfaces; f++) {
        const poly_face *F = &p->faces[f];
        if (F->count < 3) {
            fail(why, POLY_FEW_VERTICES, f, -1);
            why->a = F->count;
            return false;
        }
        for (int i = 0; i < F->count; i++) {
            int32_t v = p->idx[F->first + i];
            if (v < 0 || v >= p->nverts) {
                fail(why, POLY_INDEX, f, i);
                why->a = v;
                why->b = p->nverts;
                return false;
            }
            for (int j = 0; j < i; j++)
                if (p->idx[F->first + j] == v)
                    return fail(why, POLY_REPEAT, f, i);
        }
    }
    return true;
}

/* Plane (Newell's normal through the centroid), area, flatness and the
 * (u, v) frame of face f. */
static bool face_plane(polyhedron *p, int f, poly_error *why)
{
    poly_face *F = &p->faces[f];
    const int32_t *ix = p->idx + F->first;
    dvec n = {0, 0, 0}, c = {0, 0, 0};
    double size = 0.0;
    for (int i = 0; i < F->count; i++) {
        dvec a = dv(p->verts[ix[i]]), b = dv(p->verts[ix[(i + 1) % F->count]]);
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
        c = (dvec){c.x + a.x, c.y + a.y, c.z + a.z};
        dvec e = dsub(b, a);
        size = fmax(size, sqrt(ddot(e, e)));
    }
    double len = sqrt(ddot(n, n));
    if (!(len > 1e-12 * size * size))
        return fail(why, POLY_FLAT, f, -1);
    n = (dvec){n.x / len, n.y / len, n.z / len};
    c = (dvec){c.x / F->count, c.y / F->count, c.z / F->count};
    for (int i = 0; i < F->count; i++) {
        double dist = fabs(ddot(n, dsub(dv(p->verts[ix[i]]), c)));
        if (dist > 1e-3 * size) {
            fail(why, POLY_NOT_PLANAR, f, i);
            why->a = ix[i];
            why->dist = (float)dist;
            why->size = (float)size;
            return false;
        }
    }
    F->n = v3((float)n.x, (float)n.y, (float)n.z);
    F->d = (float)ddot(n, c);
    vec3 tu, tv;
    v3_basis(F->n, &tu, &tv);
    float u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (int i = 0; i < F->count; i++) {
        float u = v3_dot(p->verts[ix[i]], tu), v = v3_dot(p->verts[ix[i]], tv);
        u0 = fminf(u0, u), u1 = fmaxf(u1, u), v0 = fminf(v0, v), v1 = fmaxf(v1, v);
    }
    F->uo = v3_add(v3_scale(tu, u0), v3_scale(tv, v0));
    F->su = v3_scale(tu, 1.0f / fmaxf(u1 - u0, 1e-30f));
    F->sv = v3_scale(tv, 1.0f / fmaxf(v1 - v0, 1e-30f));
    return true;
}

/* Corner i of face f in the face's own 2D frame. */
static void corner2(const polyhedron *p, int f, int i, double *x, double *y)
{
    const poly_face *F = &p->faces[f];
    vec3 tu, tv, q = p->verts[p->idx[F->first + i]];
    v3_basis(F->n, &tu, &tv);
    *x = (double)q.x * tu.x + (double)q.y * tu.y + (double)q.z * tu.z;
    *y = (double)q.x * tv.x + (double)q.y * tv.y + (double)q.z * tv.z;
}

static double orient(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

static bool segments_cross(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    return ((o1 > 0) != (o2 > 0)) && ((o3 > 0) != (o4 > 0)) && o1 != 0 && o2 != 0 && o3 != 0 &&
           o4 != 0;
}

/* Whether c lies inside triangle (a, b, q), counter-clockwise. */
static bool in_triangle(const double *a, const double *b, const double *q, const double *c)
{
    return orient(a, b, c) >= 0 && orient(b, q, c) >= 0 && orient(q, a, c) >= 0;
}

/* Cuts face f into count - 2 triangles by ear clipping, appended to tri. A
 * face whose edges cross is refused first. */
static bool triangulate(polyhedron *p, int f, double (*pt)[2], int *ring, poly_error *why)
{
    const poly_face *F = &p->faces[f];
    int n = F->count;
    for (int i = 0; i < n; i++)
        corner2(p, f, i, &pt[i][0], &pt[i][1]);
    for (int i = 0; i < n; i++)
        for (int j = i + 2; j < n; j++)
            if ((j + 1) % n != i && segments_cross(pt[i], pt[(i + 1) % n], pt[j], pt[(j + 1) % n]))
                return fail(why, POLY_TANGLED, f, -1);
    for (int i = 0; i < n; i++)
        ring[i] = i;
    int left = n, i = 0, tried = 0;
    while (left > 3) {
        if (tried++ > left)
            return fail(why, POLY_TANGLED, f, -1); /* round the ring without an ear */
        int a = ring[(i + left - 1) % left], b = ring[i], c = ring[(i + 1) % left];
        bool ear = orient(pt[a], pt[b], pt[c]) > 0; /* a convex corner */
        for (int k = 0; k < left && ear; k++) {
            int q = ring[k];
            if (q != a && q != b && q != c && in_triangle(pt[a], pt[b], pt[c], pt[q]))
                ear = false;
        }
        if (!ear) {
            i = (i + 1) % left;
            continue;
        }
        uint32_t *t = p->tri[p->ntris];
        t[0] = (uint32_t)p->idx[F->first + a];
        t[1] = (uint32_t)p->idx[F->first + b];
        t[2] = (uint32_t)p->idx[F->first + c];
        p->tri_face[p->ntris++] = f;
        memmove(ring + i, ring + i + 1, sizeof *ring * (size_t)(left - i - 1));
        left--;
        i = (i + left - 1) % left;
        tried = 0;
    }
    uint32_t *t = p->tri[p->ntris];
    for (int k = 0; k < 3; k++)
        t[k] = (uint32_t)p->idx[F->first + ring[k]];
    p->tri_face[p->ntris++] = f;
    return true;
}

typedef struct edge {
    int32_t lo, hi; /* vertices, lo < hi */
    int face;
    bool forward; /* the face runs lo -> hi */
} edge;

static int edge_cmp(const void *pa, const void *pb)
{
    const edge *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return (a->face > b->face) - (a->face < b->face);
}

/* Every edge in exactly two faces, which run along it opposite ways. */
static bool check_edges(const polyhedron *p, poly_error *why)
{
    edge *e = malloc(sizeof *e * (size_t)p->nidx);
    if (!e)
        return fail(why, POLY_NOMEM, -1, -1);
    int n = 0;
    for (int f = 0; f < p->nfaces; f++) {
        const poly_face *F = &p->faces[f];
        for (int i = 0; i < F->count; i++) {
            int32_t a = p->idx[F->first + i], b = p->idx[F->first + (i + 1) % F->count];
            e[n++] = (edge){a < b ? a : b, a < b ? b : a, f, a < b};
        }
    }
    qsort(e, (size_t)n, sizeof *e, edge_cmp);
    bool ok = true;
    for (int i = 0; i < n && ok;) {
        int j = i;
        while (j < n && e[j].lo == e[i].lo && e[j].hi == e[i].hi)
            j++;
        poly_problem what = j - i == 1 ? POLY_OPEN : j - i > 2 ? POLY_NOT_MANIFOLD
                            : e[i].forward == e[i + 1].forward ? POLY_WINDING : POLY_OK;
        if (what != POLY_OK) {
            ok = fail(why, what, e[i].face, -1);
            why->other = j - i > 1 ? e[i + 1].face : -1;
            why->a = e[i].forward ? e[i].lo : e[i].hi;
            why->b = e[i].forward ? e[i].hi : e[i].lo;
        }
        i = j;
    }
    free(e);
    return ok;
}

/* Orientation (the enclosed volume is positive when the faces are
 * counter-clockwise seen from outside) and convexity. */
static bool check_solid(polyhedron *p, poly_error *why)
{
    double vol = 0.0;
    for (int t = 0; t < p->ntris; t++) {
        dvec a = dv(p->verts[p->tri[t][0]]), b = dv(p->verts[p->tri[t][1]]),
             c = dv(p->verts[p->tri[t][2]]);
        vol += a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) +
               a.z * (b.x * c.y - b.y * c.x);
    }
    if (!(vol > 0.0))
        return fail(why, POLY_INSIDE_OUT, -1, -1);
    vec3 ext = aabb_extent(p->bounds);
    float tol = 1e-5f * v3_max_comp(ext);
    p->convex = true;
    for (int f = 0; f < p->nfaces && p->convex; f++)
        for (int v = 0; v < p->nverts && p->convex; v++)
            if (v3_dot(p->faces[f].n, p->verts[v]) - p->faces[f].d > tol)
                p->convex = false;
    return true;
}

static bool prepare(polyhedron *p, poly_error *why)
{
    if (!check_indices(p, why))
        return false;
    p->bounds = aabb_empty();
    for (int i = 0; i < p->nverts; i++)
        p->bounds = aabb_grow(p->bounds, p->verts[i]);
    int most = 3, ntris = 0;
    for (int f = 0; f < p->nfaces; f++) {
        most = p->faces[f].count > most ? p->faces[f].count : most;
        ntris += p->faces[f].count - 2;
    }
    p->tri = malloc(sizeof *p->tri * (size_t)ntris);
    p->tri_face = malloc(sizeof *p->tri_face * (size_t)ntris);
    double(*pt)[2] = malloc(sizeof *pt * (size_t)most);
    int *ring = malloc(sizeof *ring * (size_t)most);
    bool ok = p->tri && p->tri_face && pt && ring ? true : fail(why, POLY_NOMEM, -1, -1);
    for (int f = 0; ok && f < p->nfaces; f++)
        ok = face_plane(p, f, why) && triangulate(p, f, pt, ring, why);
    free(pt);
    free(ring);
    return ok && check_edges(p, why) && check_solid(p, why);
}

bool polyhedron_init(polyhedron *p, vec3 *verts, int nverts, int32_t *idx, const int *sizes,
                     int nfaces, poly_error *why)
{
    memset(p, 0, sizeof *p);
    p->verts = verts;
    p->nverts = nverts;
    p->idx = idx;
    p->nfaces = nfaces;
    p->faces = calloc((size_t)(nfaces ? nfaces : 1), sizeof *p->faces);
    if (!p->faces) {
        polyhedron_free(p);
        return fail(why, POLY_NOMEM, -1, -1);
    }
    for (int f = 0; f < nfaces; f++) {
        p->faces[f].first = p->nidx;
        p->faces[f].count = sizes[f];
        p->nidx += sizes[f];
    }
    *why = (poly_error){.what = POLY_OK};
    if (!prepare(p, why)) {
        polyhedron_free(p);
        return false;
    }
    return true;
}

void polyhedron_free(polyhedron *p)
{
    if (!p)
        return;
    free(p->verts);
    free(p->idx);
    free(p->faces);
    free(p->tri);
    free(p->tri_face);
    memset(p, 0, sizeof *p);
}

void polyhedron_explain(const poly_error *e, char *buf, size_t size)
{
    switch (e->what) {
    case POLY_FEW_VERTICES:
        snprintf(buf, size, "face %d has %d vertices (a face needs at least 3)", e->face, e->a);
        return;
    case POLY_INDEX:
        snprintf(buf, size, "vertex index %d is out of range (the polyhedron has %d vertices, "
                            "0 to %d)", e->a, e->b, e->b - 1);
        return;
    case POLY_REPEAT:
        snprintf(buf, size, "face %d names a vertex twice", e->face);
        return;
    case POLY_FLAT:
        snprintf(buf, size, "face %d has no area (its vertices lie on one line)", e->face);
        return;
    case POLY_NOT_PLANAR:
        snprintf(buf, size, "face %d is not planar: its vertex %d is %.3g off the face's plane "
                            "(at most %.3g, 0.1%% of the face's size, is allowed)",
                 e->face, e->a, (double)e->dist, (double)e->size * 1e-3);
        return;
    case POLY_TANGLED:
        snprintf(buf, size, "face %d crosses itself (a face must be a simple polygon)", e->face);
        return;
    case POLY_OPEN:
        snprintf(buf, size, "the solid is not closed: the edge from vertex %d to %d of face %d "
                            "belongs to no other face", e->a, e->b, e->face);
        return;
    case POLY_NOT_MANIFOLD:
        snprintf(buf, size, "the solid is not manifold: the edge between vertices %d and %d "
                            "belongs to more than two faces (%d, %d and more)",
                 e->a < e->b ? e->a : e->b, e->a < e->b ? e->b : e->a, e->face, e->other);
        return;
    case POLY_WINDING:
        snprintf(buf, size, "faces %d and %d both run from vertex %d to %d: neighbouring faces "
                            "must run along their shared edge in opposite directions (each "
                            "counter-clockwise seen from outside)",
                 e->face, e->other, e->a, e->b);
        return;
    case POLY_INSIDE_OUT:
        snprintf(buf, size, "the faces are clockwise seen from outside (the solid is inside "
                            "out): list each face's vertices the other way round");
        return;
    case POLY_NOMEM:
        snprintf(buf, size, "out of memory");
        return;
    case POLY_OK:
        break;
    }
    snprintf(buf, size, "no problem");
}

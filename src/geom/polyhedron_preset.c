/* The five Platonic solids. Their vertices are the classic coordinates
 * (with phi the golden ratio), scaled onto the circumsphere; the faces are
 * found as the convex hull of the vertices (every plane through three of
 * them with all the others behind it), each face's vertices ordered
 * counter-clockwise round its outward normal. A cube's faces are axis
 * aligned. */
#include "polyhedron.h"

#include <math.h>
#include <stdlib.h>

const char *const poly_preset_names[] = {
    "tetrahedron", "cube", "octahedron", "dodecahedron", "icosahedron", NULL,
};
_Static_assert(sizeof poly_preset_names / sizeof *poly_preset_names == POLY_PRESET_COUNT + 1,
               "poly_preset_names names every poly_preset, in order");

#define MAXV 20

/* The preset's vertices on the unit sphere. */
static int preset_vertices(poly_preset kind, vec3 *v)
{
    const float phi = 1.6180339887498949f, iphi = 0.6180339887498949f;
    int n = 0;
    switch (kind) {
    case POLY_TETRAHEDRON:
        v[n++] = v3(1, 1, 1), v[n++] = v3(1, -1, -1), v[n++] = v3(-1, 1, -1), v[n++] = v3(-1, -1, 1);
        break;
    case POLY_CUBE:
    case POLY_DODECAHEDRON:
        for (int i = 0; i < 8; i++)
            v[n++] = v3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
        for (int i = 0; kind == POLY_DODECAHEDRON && i < 4; i++) {
            float a = i & 1 ? iphi : -iphi, b = i & 2 ? phi : -phi;
            v[n++] = v3(0, a, b), v[n++] = v3(a, b, 0), v[n++] = v3(b, 0, a);
        }
        break;
    case POLY_OCTAHEDRON:
        for (int i = 0; i < 6; i++)
            v[n++] = v3(i == 0 ? 1 : i == 1 ? -1 : 0, i == 2 ? 1 : i == 3 ? -1 : 0,
                        i == 4 ? 1 : i == 5 ? -1 : 0);
        break;
    case POLY_ICOSAHEDRON:
        for (int i = 0; i < 4; i++) {
            float a = i & 1 ? 1 : -1, b = i & 2 ? phi : -phi;
            v[n++] = v3(0, a, b), v[n++] = v3(a, b, 0), v[n++] = v3(b, 0, a);
        }
        break;
    case POLY_PRESET_COUNT:
        break;
    }
    for (int i = 0; i < n; i++)
        v[i] = v3_norm(v[i]);
    return n;
}

/* Whether the plane n . p = d (n unit) was found already. */
static bool known(const vec3 *ns, const float *ds, int count, vec3 n, float d)
{
    for (int i = 0; i < count; i++)
        if (v3_dot(ns[i], n) > 0.9999f && fabsf(ds[i] - d) < 1e-4f)
            return true;
    return false;
}

/* Appends the vertices on plane (n, d) to idx, counter-clockwise round n. */
static int face_ring(const vec3 *v, int nv, vec3 n, float d, int32_t *idx)
{
    int k = 0;
    vec3 c = v3s(0.0f);
    for (int i = 0; i < nv; i++)
        if (fabsf(v3_dot(n, v[i]) - d) < 1e-4f) {
            idx[k++] = i;
            c = v3_add(c, v[i]);
        }
    c = v3_scale(c, 1.0f / (float)k);
    vec3 tu, tv;
    v3_basis(n, &tu, &tv);
    float ang[MAXV];
    for (int i = 0; i < k; i++) {
        vec3 q = v3_sub(v[idx[i]], c);
        ang[i] = atan2f(v3_dot(q, tv), v3_dot(q, tu));
    }
    for (int i = 1; i < k; i++) /* insertion sort by angle */
        for (int j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
            float ta = ang[j];
            ang[j] = ang[j - 1], ang[j - 1] = ta;
            int32_t ti = idx[j];
            idx[j] = idx[j - 1], idx[j - 1] = ti;
        }
    return k;
}

bool polyhedron_preset(polyhedron *p, poly_preset kind, vec3 center, float radius,
                       poly_error *why)
{
    vec3 v[MAXV], ns[MAXV];
    float ds[MAXV];
    int nv = preset_vertices(kind, v), nf = 0, sizes[MAXV], nidx = 0;
    int32_t ring[MAXV * 5];
    for (int i = 0; i < nv; i++)
        for (int j = i + 1; j < nv; j++)
            for (int k = j + 1; k < nv; k++) {
                vec3 n = v3_cross(v3_sub(v[j], v[i]), v3_sub(v[k], v[i]));
                if (v3_len(n) < 1e-3f)
                    continue;
                n = v3_norm(n);
                float d = v3_dot(n, v[i]);
                if (d < 0.0f)
                    n = v3_neg(n), d = -d;
                bool hull = true;
                for (int m = 0; m < nv && hull; m++)
                    hull = v3_dot(n, v[m]) <= d + 1e-4f;
                if (!hull || known(ns, ds, nf, n, d))
                    continue;
                ns[nf] = n, ds[nf] = d;
                sizes[nf++] = face_ring(v, nv, n, d, ring + nidx);
                nidx += sizes[nf - 1];
            }
    vec3 *verts = malloc(sizeof *verts * (size_t)nv);
    int32_t *idx = malloc(sizeof *idx * (size_t)nidx);
    if (!verts || !idx) {
        free(verts);
        free(idx);
        *why = (poly_error){.what = POLY_NOMEM};
        return false;
    }
    for (int i = 0; i < nv; i++)
        verts[i] = v3_madd(center, v[i], radius);
    for (int i = 0; i < nidx; i++)
        idx[i] = ring[i];
    return polyhedron_init(p, verts, nv, idx, sizes, nf, why);
}

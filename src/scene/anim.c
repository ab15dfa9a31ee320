#include "anim.h"

#include <stdlib.h>
#include <string.h>

#include "core/array.h"

void anim_free(anim *a)
{
    for (int i = 0; i < a->ntracks; i++) {
        free(a->tracks[i].times);
        free(a->tracks[i].values);
    }
    free(a->tracks);
    free(a->channels);
    free(a->steps);
    free(a->step_channels);
    free(a->motions);
    a->tracks = NULL;
    a->channels = a->step_channels = NULL;
    a->steps = NULL;
    a->motions = NULL;
    a->ntracks = a->nchannels = a->nsteps = a->nstep_channels = a->nmotions = 0;
    a->cap_tracks = a->cap_channels = a->cap_steps = a->cap_step_channels = a->cap_motions = 0;
}

int anim_add_track(anim *a, anim_interp interp, int nkeys, int dim, const float *times,
                   const float *values)
{
    float *t = malloc(sizeof *t * (size_t)nkeys);
    float *v = malloc(sizeof *v * (size_t)nkeys * (size_t)dim);
    int i = t && v ? array_push((void **)&a->tracks, &a->ntracks, &a->cap_tracks,
                                sizeof *a->tracks)
                   : -1;
    if (i < 0) {
        free(t);
        free(v);
        return -1;
    }
    memcpy(t, times, sizeof *t * (size_t)nkeys);
    memcpy(v, values, sizeof *v * (size_t)nkeys * (size_t)dim);
    a->tracks[i] = (anim_track){interp, nkeys, dim, t, v};
    return i;
}

int anim_add_channel(anim *a, const anim_channel *c)
{
    int i = array_push((void **)&a->channels, &a->nchannels, &a->cap_channels,
                       sizeof *a->channels);
    if (i >= 0)
        a->channels[i] = *c;
    return i;
}

int anim_add_motion(anim *a, int xf, const anim_step *steps, int nsteps,
                    const anim_channel *channels, int nchannels)
{
    int m = array_push((void **)&a->motions, &a->nmotions, &a->cap_motions, sizeof *a->motions);
    if (m < 0)
        return -1;
    a->motions[m] = (anim_motion){xf, a->nsteps, nsteps, a->nstep_channels, nchannels};
    for (int i = 0; i < nsteps; i++) {
        int k = array_push((void **)&a->steps, &a->nsteps, &a->cap_steps, sizeof *a->steps);
        if (k < 0)
            return -1;
        a->steps[k] = steps[i];
    }
    for (int i = 0; i < nchannels; i++) {
        int k = array_push((void **)&a->step_channels, &a->nstep_channels,
                           &a->cap_step_channels, sizeof *a->step_channels);
        if (k < 0)
            return -1;
        a->step_channels[k] = channels[i];
    }
    return m;
}

/* Cubic Hermite between p0 (at s = 0) and p1 (s = 1) with tangents m0, m1
 * per unit of s. */
static float hermite(float p0, float p1, float m0, float m1, float s)
{
    float s2 = s * s, s3 = s2 * s;
    return (2.0f * s3 - 3.0f * s2 + 1.0f) * p0 + (s3 - 2.0f * s2 + s) * m0 +
           (-2.0f * s3 + 3.0f * s2) * p1 + (s3 - s2) * m1;
}

/* The tangent at key k per second: Catmull-Rom's central difference
 * (Catmull and Rom, "A Class of Local Interpolating Splines", 1974), in
 * the form for uneven key times; one-sided at the ends. */
static float tangent(const anim_track *t, int k, int c)
{
    int a = k > 0 ? k - 1 : k, b = k + 1 < t->nkeys ? k + 1 : k;
    return (t->values[b * t->dim + c] - t->values[a * t->dim + c]) / (t->times[b] - t->times[a]);
}

void anim_track_eval(const anim_track *t, float time, float *out)
{
    int n = t->nkeys, d = t->dim;
    if (n == 1 || !(time > t->times[0])) {
        memcpy(out, t->values, sizeof *out * (size_t)d);
        return;
    }
    if (time >= t->times[n - 1]) {
        memcpy(out, t->values + (n - 1) * d, sizeof *out * (size_t)d);
        return;
    }
    int k = 0; /* the key before time: times[k] <= time < times[k + 1] */
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (t->times[mid] <= time)
            lo = mid;
        else
            hi = mid;
    }
    k = lo;
    float span = t->times[k + 1] - t->times[k], s = (time - t->times[k]) / span;
    const float *p0 = t->values + k * d, *p1 = p0 + d;
    for (int c = 0; c < d; c++) {
        switch (t->interp) {
        case ANIM_INTERP_LINEAR:
            out[c] = p0[c] + (p1[c] - p0[c]) * s;
            break;
        case ANIM_INTERP_SMOOTH:
            out[c] = hermite(p0[c], p1[c], tangent(t, k, c) * span, tangent(t, k + 1, c) * span, s);
            break;
        case ANIM_INTERP_STEP:
            out[c] = p0[c];
            break;
        }
    }
}

void anim_apply_channel(const anim *a, const anim_channel *c, float *base, float time)
{
    const anim_track *t = &a->tracks[c->track];
    float v[ANIM_MAX_DIM];
    anim_track_eval(t, time, v);
    for (int i = 0; i < t->dim; i++)
        base[c->offset + i] = v[i] < c->lo ? c->lo : v[i] > c->hi ? c->hi : v[i];
}

void anim_apply(const anim *a, anim_target target, int index, float *base, float time)
{
    for (int i = 0; i < a->nchannels; i++) {
        const anim_channel *c = &a->channels[i];
        if (c->target == target && c->index == index)
            anim_apply_channel(a, c, base, time);
    }
}

bool anim_drives(const anim *a, anim_target target)
{
    for (int i = 0; i < a->nchannels; i++)
        if (a->channels[i].target == target)
            return true;
    return false;
}

xform anim_step_xform(const anim_step *s)
{
    const float *v = s->v;
    switch (s->kind) {
    case ANIM_STEP_TRANSLATE:
        return xform_translate(v3(v[0], v[1], v[2]));
    case ANIM_STEP_ROTATE:
        return xform_rotate(v3(v[0], v[1], v[2]), v[3]);
    case ANIM_STEP_SCALE:
        return xform_scale(v3(v[0], v[1], v[2]));
    case ANIM_STEP_SHEAR:
        return xform_shear(v[0], v[1], v[2], v[3], v[4], v[5]);
    case ANIM_STEP_FIXED:
        return s->fixed;
    }
    return xform_identity();
}

bool anim_motion_xform(const anim *a, int motion, float time, xform *out)
{
    const anim_motion *m = &a->motions[motion];
    xform acc = xform_identity();
    for (int i = 0; i < m->nsteps; i++) {
        anim_step s = a->steps[m->first_step + i];
        for (int c = 0; c < m->nchannels; c++) {
            const anim_channel *ch = &a->step_channels[m->first_channel + c];
            if (ch->index == i)
                anim_apply_channel(a, ch, s.v, time);
        }
        xform x = anim_step_xform(&s);
        acc = i == 0 ? x : xform_then(&acc, &x);
    }
    *out = acc;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(acc.fwd.m[i][j]) || !isfinite(acc.inv.m[i][j]))
                return false;
    return true;
}

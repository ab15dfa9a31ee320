/* anim: animation tracks and what they drive. A track is a list of keys
 * (time in seconds, a value of 1 to 3 numbers) read between keys by linear,
 * smooth (Catmull-Rom) or step interpolation, and held before the first key
 * and after the last. A channel writes a track's value into a float field
 * of the camera, a light, a material or a transform step, clamped to the
 * field's range. A motion is an object's transform written as steps, some
 * of them driven by channels, composed at any time.
 *
 * Lights and materials take their values once per frame (scene_set_time);
 * the camera and motions are evaluated at each ray's own time when the
 * shutter is open, which is what makes motion blur. Everything is read-only
 * during a render. */
#ifndef GLINT_SCENE_ANIM_H
#define GLINT_SCENE_ANIM_H

#include <stdbool.h>
#include "core/mat4.h"

typedef enum anim_interp {
    ANIM_INTERP_LINEAR,
    ANIM_INTERP_SMOOTH, /* Catmull-Rom through the keys */
    ANIM_INTERP_STEP, /* each key's value until the next key */
} anim_interp;

#define ANIM_MAX_DIM 3

typedef struct anim_track {
    anim_interp interp;
    int nkeys, dim;
    float *times;  /* nkeys, strictly increasing */
    float *values; /* nkeys * dim */
} anim_track;

typedef enum anim_target {
    ANIM_CAMERA,   /* the scene's camera (index 0) */
    ANIM_LIGHT,    /* a light, by index */
    ANIM_MATERIAL, /* a material, by index */
    ANIM_STEP,     /* a step of a motion, by index into the motion's steps */
} anim_target;

typedef struct anim_channel {
    anim_target target;
    int index;
    int offset; /* the first float written, in floats from the start of the
                   target's structure (camera, light, material or anim_step.v) */
    int track;
    float lo, hi; /* every component is clamped to [lo, hi] */
} anim_channel;

typedef enum anim_step_kind {
    ANIM_STEP_TRANSLATE, /* v[0..2] */
    ANIM_STEP_ROTATE,    /* v[0..2] the axis, v[3] degrees */
    ANIM_STEP_SCALE,     /* v[0..2] */
    ANIM_STEP_SHEAR,     /* v[0..5]: xy, xz, yx, yz, zx, zy */
    ANIM_STEP_FIXED,     /* a transform that does not change (matrix, or fixed steps) */
} anim_step_kind;

typedef struct anim_step {
    anim_step_kind kind;
    float v[6];
    xform fixed; /* ANIM_STEP_FIXED */
} anim_step;

/* The transform of scene xform `xform`, as steps (first applied first) and
 * the channels that drive them. */
typedef struct anim_motion {
    int xform;
    int first_step, nsteps;
    int first_channel, nchannels;
} anim_motion;

typedef struct anim {
    anim_track *tracks;
    int ntracks, cap_tracks;
    anim_channel *channels; /* the camera's, lights' and materials' */
    int nchannels, cap_channels;
    anim_step *steps;
    int nsteps, cap_steps;
    anim_channel *step_channels; /* by motion, in the order of motions */
    int nstep_channels, cap_step_channels;
    anim_motion *motions;
    int nmotions, cap_motions;
    /* the frames: frame k (from 1) opens its shutter at start + (k - 1) / fps */
    int frames;
    float fps, start;
} anim;

void anim_free(anim *a);

/* Each add copies what it is given and returns the new index, or -1 when
 * memory runs out. times strictly increasing, nkeys >= 1, dim 1..3. */
int anim_add_track(anim *a, anim_interp interp, int nkeys, int dim, const float *times,
                   const float *values);
int anim_add_channel(anim *a, const anim_channel *c);
/* A motion for scene xform xf; the channels' indices count from the
 * motion's first step. */
int anim_add_motion(anim *a, int xf, const anim_step *steps, int nsteps,
                    const anim_channel *channels, int nchannels);

/* The track's value at time t into out[0..dim). */
void anim_track_eval(const anim_track *t, float time, float *out);
/* Writes channel c's value at time t into base, the target seen as floats. */
void anim_apply_channel(const anim *a, const anim_channel *c, float *base, float time);
/* Writes every channel aimed at (target, index) into base, the target's
 * structure seen as floats, at time t. */
void anim_apply(const anim *a, anim_target target, int index, float *base, float time);
/* Whether some channel drives the target (any index). */
bool anim_drives(const anim *a, anim_target target);
/* A motion's transform at time t; false when it is not invertible then. */
bool anim_motion_xform(const anim *a, int motion, float time, xform *out);
/* The xform of one step (kind and values). */
xform anim_step_xform(const anim_step *s);

#endif

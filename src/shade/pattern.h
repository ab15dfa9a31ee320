/* pattern: the procedural patterns as plain functions of a point q in
 * pattern space (after the texture's transform, scale and offset), each
 * giving a value that a colour map turns into a colour (texture.h).
 *
 *   checker     (floor x + floor y + floor z) mod 2: 0 or 1; cubes of side
 *               1, squares on (u, v) (z = 0 there)
 *   stripes     floor x mod 2: slabs of width 1 across x
 *   rings       floor r mod 2, r = sqrt(x^2 + y^2): tubes round the z axis,
 *               circles on (u, v)
 *   gradient    x - floor x: a ramp from 0 to 1 along x, repeating
 *   noise       0.5 + 0.5 perlin(q): Perlin's improved noise (stb_perlin),
 *               smooth, period 256, perlin(q) in [-1, 1]
 *   turbulence  sum over octaves i of |perlin(q lacunarity^i)| gain^i,
 *               divided by the sum of gain^i: in [0, 1]
 *   marble      0.5 + 0.5 sin(pi (x + k turbulence(q))): veins across x
 *               bent by k = the texture's turbulence amount
 *   wood        triangle wave of r + k turbulence(q), r as for rings: rings
 *               of period 1 round the z axis, 0 at the ring's edge
 *
 * The step patterns (checker, stripes, rings) in space (solid = true) add
 * PATTERN_EDGE_BIAS to each coordinate before taking the floor, so that a
 * surface lying on a cell face (a floor at y = 0 under a solid checker)
 * lands on one side of it rather than on float noise. Every function is
 * pure: the same point gives the same value on every thread. */
#ifndef GLINT_SHADE_PATTERN_H
#define GLINT_SHADE_PATTERN_H

#include <stdbool.h>
#include "core/vec3.h"

#define PATTERN_EDGE_BIAS 1e-4f

/* Fractal sum parameters (turbulence, marble, wood). */
typedef struct pattern_noise {
    int octaves;      /* 1 to 16, default 6 */
    float lacunarity; /* > 0, default 2: frequency ratio between octaves */
    float gain;       /* > 0, default 0.5: amplitude ratio between octaves */
    float amount;     /* >= 0: turbulence added to marble and wood */
} pattern_noise;

float pattern_checker(vec3 q, bool solid);
float pattern_stripes(vec3 q, bool solid);
float pattern_rings(vec3 q, bool solid);
float pattern_gradient(vec3 q);
/* Perlin noise itself, in [-1, 1]; 0 at integer points. */
float pattern_perlin(vec3 q);
float pattern_noise_value(vec3 q);
float pattern_turbulence(vec3 q, const pattern_noise *pn);
float pattern_marble(vec3 q, const pattern_noise *pn);
float pattern_wood(vec3 q, const pattern_noise *pn);

#endif

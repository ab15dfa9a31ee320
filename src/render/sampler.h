/* sampler: where a pixel's samples go, on the image, on the lens and in
 * the shutter interval. Every value is a pure function of the pixel, the
 * sample's number and the settings (hashes, no shared random state), so an
 * image is the same for any thread count, tile order or split into passes:
 * a progressive renderer may trace samples k0..k1 of a pixel now and the
 * rest later and get the same pixel.
 *
 * grid:   sample k = (a, b) = (k mod N, k div N) at the centre of cell
 *         (a, b) of the pixel's N x N cells.
 * jitter: the same cell, anywhere in it (stratified sampling, Cook 1986,
 *         "Stochastic Sampling in Computer Graphics").
 * Both place the lens sample in a cell of an N x N grid on the lens and
 * the time in one of N*N slots of the shutter interval, each cell and slot
 * used once per pixel in an order shuffled per pixel (a hash-driven
 * permutation, after Kensler 2013, "Correlated Multi-Jittered Sampling"),
 * so lens, time and image position are each stratified and not correlated.
 * adaptive: points of a lattice over the image (render.c decides which);
 *         sampler_point gives a point's lens position and time. */
#ifndef GLINT_RENDER_SAMPLER_H
#define GLINT_RENDER_SAMPLER_H

#include <stdbool.h>
#include <stdint.h>
#include "glint.h"

typedef struct pixel_sample {
    float fx, fy; /* position in the pixel, [0, 1)^2 from its top-left corner */
    float lu, lv; /* position on the lens, [0, 1)^2 (camera_ray maps it to the disc) */
    float time;   /* share of the shutter interval, [0, 1) */
} pixel_sample;

typedef struct sampler {
    glint_sampler kind;
    int n;       /* grid and jitter: N, the side of the N x N grid */
    bool lens;   /* lens positions are used (a thin lens); else they are 0.5 */
    bool motion; /* times are used (the shutter is open); else they are 0 */
} sampler;

/* For settings already checked; lens and motion say which of the lens
 * position and the time the camera uses (the others are skipped). */
sampler sampler_make(const glint_settings *s, bool lens, bool motion);
/* Samples per pixel of grid and jitter: N * N. */
int sampler_count(const sampler *s);
/* Whether sample k is the same in every pixel (a grid without lens or
 * time): sampler_get then gives one pixel's for all. */
bool sampler_same_in_every_pixel(const sampler *s);
/* Sample k (0 <= k < sampler_count) of pixel (x, y), for grid and jitter. */
pixel_sample sampler_get(const sampler *s, int x, int y, int k);
/* Lens position and time for the adaptive sampler's lattice point (gx, gy)
 * (integer coordinates on the finest lattice over the whole image), which
 * lies at (fx, fy) of its pixel. */
pixel_sample sampler_point(uint32_t gx, uint32_t gy, float fx, float fy);

#endif

#include "settings.h"

#include <math.h>
#include <stdint.h>

#include "core/cpus.h"
#include "core/error.h"

int settings_default_threads(void)
{
    return cpus_threads(0, SETTINGS_MAX_THREADS);
}

int settings_grid_side(int samples)
{
    if (samples < 1)
        return -1;
    int r = (int)lround(sqrt((double)samples));
    return r * r == samples ? r : -1;
}

glint_rc settings_check(const glint_settings *s, glint_error *err)
{
    if (s->width < 1 || s->height < 1 || s->width > SETTINGS_MAX_SIDE ||
        s->height > SETTINGS_MAX_SIDE)
        return err_set(err, GLINT_ERR_INPUT, "resolution %dx%d is out of range (1 to %d per side)",
                       s->width, s->height, SETTINGS_MAX_SIDE);
    if ((uint64_t)s->width * (uint64_t)s->height > SETTINGS_MAX_PIXELS)
        return err_set(err, GLINT_ERR_INPUT,
                       "resolution %dx%d needs more than the %u-pixel limit", s->width,
                       s->height, SETTINGS_MAX_PIXELS);
    if (s->samples < 1 || s->samples > SETTINGS_MAX_SAMPLES)
        return err_set(err, GLINT_ERR_INPUT, "samples per pixel must be 1 to %d (got %d)",
                       SETTINGS_MAX_SAMPLES, s->samples);
    if (settings_grid_side(s->samples) < 0)
        return err_set(err, GLINT_ERR_INPUT,
                       "samples per pixel must be a perfect square (1, 4, 9, 16, ...) "
                       "for the regular grid (got %d)",
                       s->samples);
    if (s->max_depth < 0 || s->max_depth > SETTINGS_MAX_DEPTH)
        return err_set(err, GLINT_ERR_INPUT, "recursion depth must be 0 to %d (got %d)",
                       SETTINGS_MAX_DEPTH, s->max_depth);
    if (s->threads < 0 || s->threads > SETTINGS_MAX_THREADS)
        return err_set(err, GLINT_ERR_INPUT, "threads must be 0 (all cores) to %d (got %d)",
                       SETTINGS_MAX_THREADS, s->threads);
    if (s->transfer != GLINT_TRANSFER_NONE && s->transfer != GLINT_TRANSFER_SRGB)
        return err_set(err, GLINT_ERR_INPUT, "transfer must be none (%d) or srgb (%d) (got %d)",
                       GLINT_TRANSFER_NONE, GLINT_TRANSFER_SRGB, (int)s->transfer);
    if ((unsigned)s->sampler > GLINT_SAMPLER_ADAPTIVE)
        return err_set(err, GLINT_ERR_INPUT,
                       "sampler must be grid (%d), jitter (%d) or adaptive (%d) (got %d)",
                       GLINT_SAMPLER_GRID, GLINT_SAMPLER_JITTER, GLINT_SAMPLER_ADAPTIVE,
                       (int)s->sampler);
    if (!(s->threshold >= 0.0 && s->threshold <= 1.0))
        return err_set(err, GLINT_ERR_INPUT, "adaptive threshold must be 0 to 1 (got %g)",
                       s->threshold);
    if (s->adaptive_depth < 0 || s->adaptive_depth > SETTINGS_MAX_ADAPTIVE_DEPTH)
        return err_set(err, GLINT_ERR_INPUT, "adaptive max_depth must be 0 to %d (got %d)",
                       SETTINGS_MAX_ADAPTIVE_DEPTH, s->adaptive_depth);
    if (!(s->adc_bailout >= 0.0 && s->adc_bailout <= 1.0))
        return err_set(err, GLINT_ERR_INPUT, "adc_bailout must be 0 (never prune) to 1 (got %g)",
                       s->adc_bailout);
    return GLINT_OK;
}

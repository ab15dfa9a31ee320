#include "fingerprint.h"

#include <stdio.h>
#include <string.h>

#include "scene.h"

#define FNV_PRIME 0x100000001b3ULL

/* One word into a lane: FNV's step, then the high bits folded down. */
static inline uint64_t lane_step(uint64_t h, uint64_t w)
{
    h = (h ^ w) * FNV_PRIME;
    return h ^ (h >> 29); /* carries the high bits down, which the product alone never does */
}

uint64_t fingerprint_bytes(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    size_t i = 0;
    if (n >= FINGERPRINT_LANES_FROM) {
        /* four lanes, words 0-3 of each 32 bytes, then folded into one:
         * four times the single lane's speed, whose steps wait on the one
         * before (a 1024x512 texture's pixels, or a film's). Four
         * variables, not an array, which compilers turn into SSE2 code
         * that multiplies in shifts and adds, slower than one lane. */
        uint64_t a = h, b = h ^ 0x9e3779b97f4a7c15ULL, c = h ^ 0xc2b2ae3d27d4eb4fULL,
                 d = h ^ 0x165667b19e3779f9ULL;
        for (; i + 32 <= n; i += 32) {
            uint64_t w[4];
            memcpy(w, p + i, 32); /* the host's byte order, as below */
            a = lane_step(a, w[0]);
            b = lane_step(b, w[1]);
            c = lane_step(c, w[2]);
            d = lane_step(d, w[3]);
        }
        h = lane_step(lane_step(lane_step(a, b), c), d);
    }
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8); /* the host's byte order: files are read back on a like host */
        h = lane_step(h, w);
    }
    for (; i < n; i++)
        h = (h ^ p[i]) * FNV_PRIME;
    return h;
}

static uint64_t hash_int(uint64_t h, int64_t v) { return fingerprint_bytes(h, &v, sizeof v); }
static uint64_t hash_float(uint64_t h, float v) { return fingerprint_bytes(h, &v, sizeof v); }

static uint64_t hash_vec(uint64_t h, vec3 v)
{
    return hash_float(hash_float(hash_float(h, v.x), v.y), v.z);
}

static uint64_t hash_settings(uint64_t h, const glint_settings *st)
{
    h = hash_int(h, st->width);
    h = hash_int(h, st->height);
    h = hash_int(h, st->samples);
    h = hash_int(h, st->max_depth);
    h = hash_int(h, (int64_t)st->transfer);
    h = hash_int(h, (int64_t)st->sampler);
    h = fingerprint_bytes(h, &st->threshold, sizeof st->threshold);
    h = hash_int(h, st->adaptive_depth);
    h = hash_int(h, st->alpha != 0);
    return fingerprint_bytes(h, &st->adc_bailout, sizeof st->adc_bailout);
}

static uint64_t hash_data(uint64_t h, const scene *s)
{
    for (int i = 0; i < s->nimages; i++) {
        const image *im = &s->images[i];
        size_t n = (size_t)im->width * (size_t)im->height * 3;
        h = hash_int(hash_int(h, im->width), im->height);
        if (im->rgb)
            h = fingerprint_bytes(h, im->rgb, n);
        if (im->linear)
            h = fingerprint_bytes(h, im->linear, n * sizeof *im->linear);
    }
    for (int i = 0; i < s->nmeshes; i++) {
        const mesh *m = s->meshes[i];
        size_t nv = (size_t)m->nverts, nt = (size_t)m->ntris;
        h = hash_int(hash_int(h, m->nverts), m->ntris);
        h = fingerprint_bytes(h, m->pos, nv * sizeof *m->pos);
        h = fingerprint_bytes(h, m->tri, nt * sizeof *m->tri);
    }
    for (int i = 0; i < s->nxforms; i++)
        h = fingerprint_bytes(h, s->xforms[i].fwd.m, sizeof s->xforms[i].fwd.m);
    return h;
}

uint64_t fingerprint_file_bytes(const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t h = FINGERPRINT_SEED;
    for (size_t at = 0; at < n; at += FINGERPRINT_FILE_PIECE)
        h = fingerprint_bytes(h, p + at,
                              n - at < FINGERPRINT_FILE_PIECE ? n - at : FINGERPRINT_FILE_PIECE);
    return h;
}

/* The bytes of each file the scene was read from: as the front end read
 * them, or for a file it did not read itself (a mesh the importer opens),
 * as they are now. */
static uint64_t hash_sources(uint64_t h, const scene *s)
{
    for (int i = 0; i < s->nsources; i++) {
        const scene_source *src = &s->sources[i];
        uint64_t bytes = src->bytes;
        bool there = src->read;
        if (!there) {
            FILE *f = fopen(src->path, "rb");
            unsigned char buf[FINGERPRINT_FILE_PIECE];
            bytes = FINGERPRINT_SEED;
            for (size_t n; f && (n = fread(buf, 1, sizeof buf, f)) > 0;)
                bytes = fingerprint_bytes(bytes, buf, n);
            there = f != NULL;
            if (f)
                fclose(f);
        }
        h = hash_int(h, there);
        h = hash_int(h, (int64_t)bytes);
    }
    return h;
}

uint64_t scene_fingerprint(const scene *s, const glint_settings *settings)
{
    uint64_t h = fingerprint_bytes(FINGERPRINT_SEED, GLINT_VERSION, sizeof GLINT_VERSION);
    h = hash_settings(h, settings);
    const camera *c = &s->camera;
    h = hash_float(hash_vec(hash_vec(hash_vec(h, c->eye), c->target), c->up), c->hfov);
    /* the projection, the lens, the shutter and the frame's time */
    h = hash_int(h, (int64_t)c->projection);
    h = hash_float(hash_float(hash_float(h, c->aperture), c->focus_distance), c->width);
    h = hash_float(hash_float(hash_float(h, c->shutter), s->time), s->shutter_seconds);
    h = hash_vec(hash_vec(h, s->background), s->ambient);
    const int counts[] = {s->nobjects, s->nlights, s->nmaterials, s->ntextures,
                          s->nimages,  s->nmeshes, s->nxforms};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++)
        h = hash_int(h, counts[i]);
    return hash_sources(hash_data(h, s), s);
}

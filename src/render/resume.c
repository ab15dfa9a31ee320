#include "resume.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/spare.h"
#include "io/file.h"
#include "render/render.h"
#include "scene/fingerprint.h"
#include "scene/scene.h"
#include "scene/settings.h"

static const char magic[8] = {'G', 'L', 'I', 'N', 'T', 'R', 'S', 'M'};

#define HEADER_BYTES (8 + 4 + 4 + 6 * 4 + 8 + 8 + 4 + 4)

/* A probe: the scene rendered at 24 x 16 pixels, 1 sample each. */
#define PROBE_W 24
#define PROBE_H 16

uint64_t resume_fingerprint(const scene *sc, const glint_settings *s)
{
    uint64_t h = scene_fingerprint(sc, s);
    glint_settings probe = *s;
    probe.width = PROBE_W;
    probe.height = PROBE_H;
    probe.samples = 1;
    probe.threads = 1;
    float rgb[PROBE_W * PROBE_H * 3] = {0};
    glint_film film = {.width = PROBE_W, .height = PROBE_H, .rgb = rgb};
    render_work w = {.region = {0, 0, PROBE_W, PROBE_H}};
    glint_error err;
    glint_rc rc = render_run(sc, &probe, NULL, &w, &film, NULL, &err);
    h = fingerprint_bytes(h, &rc, sizeof rc);
    return fingerprint_bytes(h, rgb, sizeof rgb);
}

glint_rc resume_init(glint_resume *r, const scene *sc, const glint_settings *s, glint_error *err)
{
    glint_rc rc = settings_check(s, err);
    if (rc != GLINT_OK)
        return rc;
    if (!sc->built)
        return err_set(err, GLINT_ERR_INPUT, "scene was not built (objects were added since)");
    *r = (glint_resume){0};
    r->settings = *s;
    r->fingerprint = resume_fingerprint(sc, s);
    r->ntiles = render_tile_count(s->width, s->height);
    r->done = calloc((size_t)r->ntiles, 1);
    r->film.rgb = render_film_rgb(s->width, s->height, s->threads);
    if (s->alpha)
        r->film.alpha = calloc((size_t)s->width * (size_t)s->height, sizeof(float));
    if (!r->done || !r->film.rgb || (s->alpha && !r->film.alpha)) {
        resume_free(r);
        return err_nomem(err);
    }
    r->film.width = s->width;
    r->film.height = s->height;
    return GLINT_OK;
}

void resume_free(glint_resume *r)
{
    if (!r)
        return;
    free(r->done);
    spare_free(r->film.rgb);
    free(r->film.alpha);
    free(r->note);
    *r = (glint_resume){0};
}

int resume_done_count(const glint_resume *r)
{
    int n = 0;
    for (int i = 0; i < r->ntiles; i++)
        n += r->done[i] != 0;
    return n;
}

/* ---- encoding ------------------------------------------------------------- */

typedef struct buf {
    unsigned char *p;
    size_t len, cap;
} buf;

static void put(buf *b, const void *data, size_t n)
{
    memcpy(b->p + b->len, data, n);
    b->len += n;
}

static void put_u32(buf *b, uint32_t v)
{
    unsigned char x[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    put(b, x, 4);
}

static void put_u64(buf *b, uint64_t v)
{
    put_u32(b, (uint32_t)v);
    put_u32(b, (uint32_t)(v >> 32));
}

static void put_f32(buf *b, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put_u32(b, v);
}

static size_t tile_pixels(const glint_settings *s, int tile)
{
    glint_rect t = render_tile_rect(s->width, s->height, tile);
    return (size_t)(t.x1 - t.x0) * (size_t)(t.y1 - t.y0);
}

static void put_tile(buf *b, const glint_resume *r, int tile)
{
    const glint_settings *s = &r->settings;
    glint_rect t = render_tile_rect(s->width, s->height, tile);
    for (int y = t.y0; y < t.y1; y++)
        for (int x = t.x0; x < t.x1; x++) {
            size_t at = (size_t)y * (size_t)s->width + (size_t)x;
            for (int c = 0; c < 3; c++)
                put_f32(b, r->film.rgb[at * 3 + (size_t)c]);
            if (r->film.alpha) /* coverage follows its pixel (image.alpha) */
                put_f32(b, r->film.alpha[at]);
        }
}

glint_rc resume_write(const glint_resume *r, const char *path, glint_error *err)
{
    const glint_settings *s = &r->settings;
    size_t size = HEADER_BYTES + r->note_len + (size_t)r->ntiles + 8;
    for (int i = 0; i < r->ntiles; i++)
        if (r->done[i])
            size += tile_pixels(s, i) * (r->film.alpha ? 16 : 12);
    buf b = {malloc(size), 0, size};
    if (!b.p)
        return err_nomem(err);
    put(&b, magic, sizeof magic);
    put_u32(&b, RESUME_VERSION);
    put_u32(&b, RENDER_TILE);
    /* the transfer's word carries the alpha flag in bit 8 */
    const int32_t v[6] = {s->width, s->height, s->samples, s->max_depth,
                          (int32_t)s->transfer | (s->alpha ? 0x100 : 0), s->threads};
    for (int i = 0; i < 6; i++)
        put_u32(&b, (uint32_t)v[i]);
    uint64_t bailout;
    memcpy(&bailout, &s->adc_bailout, 8);
    put_u64(&b, bailout);
    put_u64(&b, r->fingerprint);
    put_u32(&b, (uint32_t)r->ntiles);
    put_u32(&b, (uint32_t)r->note_len);
    if (r->note_len)
        put(&b, r->note, r->note_len);
    for (int i = 0; i < r->ntiles; i++) {
        unsigned char d = r->done[i] ? 1 : 0;
        put(&b, &d, 1);
    }
    for (int i = 0; i < r->ntiles; i++)
        if (r->done[i])
            put_tile(&b, r, i);
    put_u64(&b, fingerprint_bytes(FINGERPRINT_SEED, b.p, b.len));
    glint_rc rc = file_write(path, b.p, b.len, err);
    free(b.p);
    return rc;
}

/* ---- decoding ------------------------------------------------------------- */

typedef struct reader {
    const unsigned char *p;
    size_t len, at;
} reader;

static bool get(reader *rd, void *out, size_t n)
{
    if (rd->len - rd->at < n)
        return false;
    memcpy(out, rd->p + rd->at, n);
    rd->at += n;
    return true;
}

static bool get_u32(reader *rd, uint32_t *v)
{
    unsigned char x[4];
    if (!get(rd, x, 4))
        return false;
    *v = (uint32_t)x[0] | (uint32_t)x[1] << 8 | (uint32_t)x[2] << 16 | (uint32_t)x[3] << 24;
    return true;
}

static bool get_u64(reader *rd, uint64_t *v)
{
    uint32_t lo, hi;
    if (!get_u32(rd, &lo) || !get_u32(rd, &hi))
        return false;
    *v = (uint64_t)hi << 32 | lo;
    return true;
}

static glint_rc read_all(const char *path, unsigned char **data, size_t *len, glint_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(err, GLINT_ERR_INPUT, "cannot read resume file '%s': %s", path,
                       strerror(errno));
    size_t cap = 1 << 16, n = 0;
    unsigned char *p = malloc(cap);
    for (;;) {
        if (!p) {
            fclose(f);
            return err_nomem(err);
        }
        n += fread(p + n, 1, cap - n, f);
        if (n < cap)
            break;
        if (cap >= ((size_t)SETTINGS_MAX_PIXELS * 12 + RESUME_MAX_NOTE * 2))
            break;
        unsigned char *q = realloc(p, cap * 2);
        if (!q)
            free(p);
        p = q;
        cap *= 2;
    }
    bool bad = ferror(f) != 0;
    fclose(f);
    if (bad) {
        free(p);
        return err_set(err, GLINT_ERR_INPUT, "cannot read resume file '%s'", path);
    }
    *data = p;
    *len = n;
    return GLINT_OK;
}

/* The header: settings, fingerprint, tile count and note. */
static glint_rc read_header(reader *rd, const char *path, glint_resume *r, glint_error *err)
{
    char m[8];
    uint32_t version, tile, v[6], ntiles, note_len;
    if (!get(rd, m, 8) || memcmp(m, magic, 8) != 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: not a glint resume file", path);
    if (!get_u32(rd, &version) || version != RESUME_VERSION || !get_u32(rd, &tile) ||
        tile != RENDER_TILE)
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file of another glint version", path);
    for (int i = 0; i < 6; i++)
        if (!get_u32(rd, &v[i]))
            return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    uint64_t bailout;
    if (!get_u64(rd, &bailout))
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    r->settings = (glint_settings){.width = (int32_t)v[0], .height = (int32_t)v[1],
                                   .samples = (int32_t)v[2], .max_depth = (int32_t)v[3],
                                   .threads = (int32_t)v[5],
                                   .transfer = (glint_transfer)(v[4] & 0xff),
                                   .alpha = (int)(v[4] >> 8)};
    memcpy(&r->settings.adc_bailout, &bailout, 8);
    glint_error inner;
    if ((v[4] & 0xff) > GLINT_TRANSFER_SRGB || v[4] >> 9 || settings_check(&r->settings, &inner) != GLINT_OK)
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file holds bad settings", path);
    if (!get_u64(rd, &r->fingerprint) || !get_u32(rd, &ntiles) || !get_u32(rd, &note_len))
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    r->ntiles = render_tile_count(r->settings.width, r->settings.height);
    if (ntiles != (uint32_t)r->ntiles || note_len > RESUME_MAX_NOTE)
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is damaged", path);
    r->note_len = note_len;
    r->note = malloc(note_len + 1);
    if (!r->note)
        return err_nomem(err);
    if (!get(rd, r->note, note_len))
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    r->note[note_len] = '\0';
    return GLINT_OK;
}

static bool get_tile(reader *rd, glint_resume *r, int tile)
{
    const glint_settings *s = &r->settings;
    glint_rect t = render_tile_rect(s->width, s->height, tile);
    for (int y = t.y0; y < t.y1; y++)
        for (int x = t.x0; x < t.x1; x++) {
            size_t at = (size_t)y * (size_t)s->width + (size_t)x;
            for (int c = 0; c < 4; c++) {
                uint32_t u;
                if (c == 3 && !r->film.alpha)
                    break;
                if (!get_u32(rd, &u))
                    return false;
                memcpy(c == 3 ? &r->film.alpha[at] : &r->film.rgb[at * 3 + (size_t)c], &u, 4);
            }
        }
    return true;
}

/* The tile flags and pixels, then the checksum over everything. */
static glint_rc read_body(reader *rd, const char *path, glint_resume *r, glint_error *err)
{
    const glint_settings *s = &r->settings;
    r->done = calloc((size_t)r->ntiles, 1);
    r->film.rgb = render_film_rgb(s->width, s->height, s->threads);
    if (s->alpha)
        r->film.alpha = calloc((size_t)s->width * (size_t)s->height, sizeof(float));
    if (!r->done || !r->film.rgb || (s->alpha && !r->film.alpha))
        return err_nomem(err);
    r->film.width = s->width;
    r->film.height = s->height;
    if (!get(rd, r->done, (size_t)r->ntiles))
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    for (int i = 0; i < r->ntiles; i++) {
        if (r->done[i] > 1)
            return err_set(err, GLINT_ERR_INPUT, "%s: resume file is damaged", path);
        if (r->done[i] && !get_tile(rd, r, i))
            return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    }
    size_t body = rd->at;
    uint64_t sum;
    if (!get_u64(rd, &sum))
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is cut short", path);
    if (rd->at != rd->len || sum != fingerprint_bytes(FINGERPRINT_SEED, rd->p, body))
        return err_set(err, GLINT_ERR_INPUT, "%s: resume file is damaged (checksum mismatch)", path);
    return GLINT_OK;
}

glint_rc resume_read(const char *path, glint_resume *out, glint_error *err)
{
    unsigned char *data = NULL;
    size_t len = 0;
    glint_rc rc = read_all(path, &data, &len, err);
    if (rc != GLINT_OK)
        return rc;
    reader rd = {data, len, 0};
    glint_resume r = {0};
    rc = read_header(&rd, path, &r, err);
    if (rc == GLINT_OK)
        rc = read_body(&rd, path, &r, err);
    free(data);
    if (rc != GLINT_OK) {
        resume_free(&r);
        return rc;
    }
    *out = r;
    return GLINT_OK;
}

/* ---- checking and rendering ---------------------------------------------- */

glint_rc resume_check(const glint_resume *r, const scene *sc, const glint_settings *s,
                      glint_error *err)
{
    const glint_settings *w = &r->settings;
    if (w->width != s->width || w->height != s->height)
        return err_set(err, GLINT_ERR_INPUT,
                       "resume file is for a %dx%d image, this render is %dx%d", w->width,
                       w->height, s->width, s->height);
    if (w->samples != s->samples)
        return err_set(err, GLINT_ERR_INPUT,
                       "resume file is for %d samples per pixel, this render takes %d",
                       w->samples, s->samples);
    if (w->max_depth != s->max_depth)
        return err_set(err, GLINT_ERR_INPUT, "resume file is for depth %d, this render has %d",
                       w->max_depth, s->max_depth);
    if (w->transfer != s->transfer)
        return err_set(err, GLINT_ERR_INPUT, "resume file is for another transfer function");
    if ((w->alpha != 0) != (s->alpha != 0))
        return err_set(err, GLINT_ERR_INPUT, "resume file is for an image %s alpha",
                       w->alpha ? "with" : "without");
    if (w->adc_bailout != s->adc_bailout)
        return err_set(err, GLINT_ERR_INPUT, "resume file is for adc_bailout %g, this render has %g",
                       w->adc_bailout, s->adc_bailout);
    if (!sc->built)
        return err_set(err, GLINT_ERR_INPUT, "scene was not built (objects were added since)");
    if (r->fingerprint != resume_fingerprint(sc, s))
        return err_set(err, GLINT_ERR_INPUT,
                       "resume file was written for a different scene or camera");
    return GLINT_OK;
}

typedef struct relay {
    const glint_callbacks *user;
    glint_resume *r;
    int tiles_x;
    uint64_t before, all; /* samples final before this render, and in the image */
} relay;

static void relay_tile(void *u, const glint_film *film, int x0, int y0, int x1, int y1)
{
    relay *rl = u;
    rl->r->done[(y0 / RENDER_TILE) * rl->tiles_x + x0 / RENDER_TILE] = 1;
    if (rl->user && rl->user->tile_done)
        rl->user->tile_done(rl->user->user, film, x0, y0, x1, y1);
}

/* Progress of the whole image, tiles final before this render included. */
static void relay_progress(void *u, const glint_progress *p)
{
    relay *rl = u;
    if (!rl->user || !rl->user->progress)
        return;
    glint_progress q = *p;
    q.samples_done = rl->before + p->samples_done;
    q.samples_total = rl->all;
    q.percent = q.samples_done == q.samples_total ? 100.0
                                                  : 100.0 * (double)q.samples_done / (double)rl->all;
    rl->user->progress(rl->user->user, &q);
}

static int relay_cancelled(void *u)
{
    relay *rl = u;
    return rl->user && rl->user->cancelled && rl->user->cancelled(rl->user->user);
}

glint_rc resume_render(const scene *sc, const glint_settings *s, const glint_callbacks *cb,
                       glint_resume *r, glint_stats *stats, glint_error *err)
{
    glint_rc rc = resume_check(r, sc, s, err);
    if (rc != GLINT_OK)
        return rc;
    int *todo = malloc((size_t)r->ntiles * sizeof *todo), n = 0;
    if (!todo)
        return err_nomem(err);
    uint64_t spp = (uint64_t)s->samples, before = 0;
    for (int i = 0; i < r->ntiles; i++) {
        if (!r->done[i])
            todo[n++] = i;
        else
            before += tile_pixels(s, i) * spp;
    }
    relay rl = {cb, r, (s->width + RENDER_TILE - 1) / RENDER_TILE, before,
                (uint64_t)s->width * (uint64_t)s->height * spp};
    glint_callbacks mine = {&rl, relay_tile, relay_progress, relay_cancelled};
    render_work w = {.tiles = todo, .ntiles = n};
    if (n > 0)
        rc = render_run(sc, s, &mine, &w, &r->film, stats, err);
    else if (stats)
        *stats = (glint_stats){0};
    free(todo);
    return rc;
}

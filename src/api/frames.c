/* Frame sequences: frame lists, output names with a frame number, and
 * whether a frame's output is already complete (include/glint.h). Pure
 * string work but for the last, which decodes the file with the image
 * readers. */
#include "glint.h"

#include <errno.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/check.h"
#include "core/error.h"
#include "io/image.h"

/* A whole decimal number in [1, INT_MAX] from s to end (exclusive). */
static bool parse_frame(const char *s, const char *end, int *out)
{
    if (s == end || *s < '0' || *s > '9')
        return false;
    long v = 0;
    for (; s < end; s++) {
        if (*s < '0' || *s > '9')
            return false;
        v = v * 10 + (*s - '0');
        if (v > INT_MAX)
            return false;
    }
    *out = (int)v;
    return v >= 1;
}

glint_rc glint_frames_parse(const char *spec, int frames, int *first, int *last,
                            glint_error *err)
{
    static const char fn[] = "glint_frames_parse";
    if (!spec || !first || !last)
        return api_null(err, fn, !spec ? "spec" : !first ? "first" : "last");
    if (frames < 1)
        return api_bad(err, fn, "frames must be >= 1 (got %d)", frames);
    const char *colon = strchr(spec, ':');
    const char *end = spec + strlen(spec);
    int a, b;
    bool ok = colon ? parse_frame(spec, colon, &a) && parse_frame(colon + 1, end, &b)
                    : parse_frame(spec, end, &a);
    if (!colon)
        b = a;
    if (!ok)
        return err_set(err, GLINT_ERR_INPUT,
                       "expected frames as FIRST:LAST or N, numbered from 1, got '%s'", spec);
    if (a > b)
        return err_set(err, GLINT_ERR_INPUT, "frames %d:%d: the first is after the last", a, b);
    if (b > frames)
        return err_set(err, GLINT_ERR_INPUT, "frame %d is past the animation's last (%d)", b,
                       frames);
    *first = a;
    *last = b;
    return GLINT_OK;
}

/* Finds the pattern's number field: *at its '%', *len its length; *at is
 * NULL when there is none. */
static glint_rc find_field(const char *p, const char **at, size_t *len, glint_error *err)
{
    *at = NULL;
    for (const char *c = p; *c; c++) {
        if (*c != '%')
            continue;
        if (c[1] == '%') {
            c++;
            continue;
        }
        const char *d = c + 1;
        if (*d == '0')
            d++;
        if (*d >= '1' && *d <= '9')
            d++;
        if (*d != 'd')
            return err_set(err, GLINT_ERR_INPUT,
                           "output name '%s': the only %% field allowed is the frame number "
                           "(%%d, %%4d, %%04d); write %%%% for a %% sign",
                           p);
        if (*at)
            return err_set(err, GLINT_ERR_INPUT,
                           "output name '%s' has two frame number fields", p);
        *at = c;
        *len = (size_t)(d + 1 - c);
        c = d;
    }
    return GLINT_OK;
}

/* Appends text (n bytes) at *o, within size; false when it does not fit. */
static bool put(char *out, size_t size, size_t *o, const char *text, size_t n)
{
    if (*o + n >= size)
        return false;
    memcpy(out + *o, text, n);
    *o += n;
    out[*o] = '\0';
    return true;
}

/* Copies pattern[0, n) into out, turning "%%" into "%". */
static bool put_literal(char *out, size_t size, size_t *o, const char *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (p[i] == '%' && i + 1 < n && p[i + 1] == '%')
            i++;
        if (!put(out, size, o, p + i, 1))
            return false;
    }
    return true;
}

glint_rc glint_frame_path(const char *pattern, int frame, char *out, size_t size,
                          glint_error *err)
{
    static const char fn[] = "glint_frame_path";
    if (!pattern || !out)
        return api_null(err, fn, !pattern ? "pattern" : "out");
    if (frame < 0)
        return api_bad(err, fn, "frame must be >= 0 (got %d)", frame);
    if (size == 0)
        return api_bad(err, fn, "size must be > 0");
    out[0] = '\0';
    if (strcmp(pattern, "-") == 0)
        return err_set(err, GLINT_ERR_INPUT,
                       "a sequence of frames cannot go to standard output ('-')");
    const char *at;
    size_t len = 0;
    glint_rc rc = find_field(pattern, &at, &len, err);
    if (rc != GLINT_OK)
        return rc;
    char field[8] = "-%04d";
    size_t before, after;
    if (at) {
        memcpy(field, at, len);
        field[len] = '\0';
        before = (size_t)(at - pattern);
        after = before + len;
    } else {
        /* before the extension: the last '.' of the last path component,
         * not leading it (".hidden" has no extension) */
        const char *base = strrchr(pattern, '/');
        base = base ? base + 1 : pattern;
        const char *dot = strrchr(base, '.');
        before = after = dot && dot != base ? (size_t)(dot - pattern) : strlen(pattern);
    }
    char num[32];
    int n = snprintf(num, sizeof num, field, frame);
    size_t o = 0;
    if (n < 0 || !put_literal(out, size, &o, pattern, before) ||
        !put(out, size, &o, num, (size_t)n) ||
        !put_literal(out, size, &o, pattern + after, strlen(pattern + after))) {
        out[0] = '\0';
        return err_set(err, GLINT_ERR_INPUT, "output name for frame %d of '%s' is too long",
                       frame, pattern);
    }
    return GLINT_OK;
}

int glint_output_complete(const char *path, int width, int height)
{
    if (!path || strcmp(path, "-") == 0)
        return 0;
    image img;
    glint_error err;
    if (image_load(path, &img, &err) != GLINT_OK)
        return 0;
    bool ok = (width <= 0 || img.width == width) && (height <= 0 || img.height == height);
    image_free(&img);
    return ok;
}

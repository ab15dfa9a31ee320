#include "image.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include <stb_image.h>
#include <stb_image_write.h>

#include <sys/stat.h>

#include "core/error.h"

#define IMAGE_MAX_FILE_BYTES (1L << 30)

glint_rc image_load_memory(const void *data, size_t size, const char *name, image *out,
                           glint_error *err)
{
    int w, h, comp;
    if (size > (size_t)INT32_MAX)
        return err_set(err, GLINT_ERR_INPUT, "%s: image file too large", name);
    if (!stbi_info_from_memory(data, (int)size, &w, &h, &comp))
        return err_set(err, GLINT_ERR_INPUT, "%s: not a readable image (%s)", name,
                       stbi_failure_reason());
    if (w <= 0 || h <= 0 || (uint64_t)w * (uint64_t)h > IMAGE_MAX_PIXELS)
        return err_set(err, GLINT_ERR_INPUT, "%s: image size %dx%d is out of range", name, w, h);
    unsigned char *px = stbi_load_from_memory(data, (int)size, &w, &h, &comp, 3);
    if (!px)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot decode image (%s)", name,
                       stbi_failure_reason());
    out->width = w;
    out->height = h;
    out->rgb = px;
    return GLINT_OK;
}

glint_rc image_load(const char *path, image *out, glint_error *err)
{
    glint_rc rc = GLINT_OK;
    unsigned char *buf = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot open image: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot open image: %s", path, strerror(EISDIR));
        goto out;
    }
    if (fseek(f, 0, SEEK_END) != 0) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read image: %s", path, strerror(errno));
        goto out;
    }
    long size = ftell(f);
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read image: %s", path, strerror(errno));
        goto out;
    }
    if (size == 0 || size > IMAGE_MAX_FILE_BYTES) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: image file is %s", path,
                     size == 0 ? "empty" : "too large");
        goto out;
    }
    buf = malloc((size_t)size);
    if (!buf) {
        rc = err_nomem(err);
        goto out;
    }
    if (fread(buf, 1, (size_t)size, f) != (size_t)size) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read image: %s", path,
                     ferror(f) ? strerror(errno) : "unexpected end of file");
        goto out;
    }
    rc = image_load_memory(buf, (size_t)size, path, out, err);
out:
    free(buf);
    fclose(f);
    return rc;
}

void image_free(image *img)
{
    if (!img)
        return;
    stbi_image_free(img->rgb);
    img->rgb = NULL;
    img->width = img->height = 0;
}

static void write_cb(void *ctx, void *data, int size)
{
    FILE *f = ctx;
    fwrite(data, 1, (size_t)size, f);
}

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        return "";
    return dot;
}

/* Creates a new file beside path, named path.tmp.PID.N, with the mode a
 * plain creat() would give (mkstemp's 0600 would stay on the final file). */
static int open_temp(const char *path, char *tmp, size_t len)
{
    static atomic_uint counter;
    for (int tries = 0; tries < 100; tries++) {
        snprintf(tmp, len, "%s.tmp.%ld.%u", path, (long)getpid(), atomic_fetch_add(&counter, 1));
        int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            return fd;
    }
    return -1;
}

glint_rc image_write(const char *path, int width, int height, const uint8_t *rgb,
                     glint_error *err)
{
    const char *ext = extension(path);
    bool png = strcasecmp(ext, ".png") == 0, ppm = strcasecmp(ext, ".ppm") == 0;
    if (!png && !ppm)
        return err_set(err, GLINT_ERR_INPUT,
                       "%s: unknown output format '%s' (use .png or .ppm)", path, ext);

    size_t len = strlen(path) + 48;
    char *tmp = malloc(len);
    if (!tmp)
        return err_nomem(err);
    int fd = open_temp(path, tmp, len);
    if (fd < 0) {
        glint_rc rc = err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
        free(tmp);
        return rc;
    }
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        close(fd);
        goto fail;
    }
    if (png) {
        if (!stbi_write_png_to_func(write_cb, f, width, height, 3, rgb, width * 3))
            goto fail;
    } else {
        fprintf(f, "P6\n%d %d\n255\n", width, height);
        fwrite(rgb, 3, (size_t)width * (size_t)height, f);
    }
    if (fflush(f) != 0 || ferror(f) || fsync(fileno(f)) != 0)
        goto fail;
    if (fclose(f) != 0) {
        f = NULL;
        goto fail;
    }
    f = NULL;
    if (rename(tmp, path) != 0)
        goto fail;
    free(tmp);
    return GLINT_OK;
fail: {
    glint_rc rc = err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", path,
                          errno ? strerror(errno) : "write failed");
    if (f)
        fclose(f);
    unlink(tmp);
    free(tmp);
    return rc;
}
}

static float srgb_encode(float x)
{
    return x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
}

static float srgb_decode(float x)
{
    return x <= 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
}

void image_quantize(const float *src, size_t count, glint_transfer transfer, uint8_t *dst)
{
    for (size_t i = 0; i < count; i++) {
        float x = src[i];
        if (!(x > 0.0f))
            x = 0.0f; /* also maps NaN to black */
        if (x > 1.0f)
            x = 1.0f;
        switch (transfer) {
        case GLINT_TRANSFER_NONE:
            break;
        case GLINT_TRANSFER_SRGB:
            x = srgb_encode(x);
            break;
        }
        dst[i] = (uint8_t)lrintf(x * 255.0f);
    }
}

void image_decode_table(glint_transfer transfer, float table[256])
{
    for (int i = 0; i < 256; i++) {
        float x = (float)i / 255.0f;
        switch (transfer) {
        case GLINT_TRANSFER_NONE:
            break;
        case GLINT_TRANSFER_SRGB:
            x = srgb_decode(x);
            break;
        }
        table[i] = x;
    }
}

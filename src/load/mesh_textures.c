/* A model file's materials and textures joining a scene (mesh_file_add):
 * textures the file names are read from the model's folder, textures held
 * in the file are decoded from its bytes, both through the image readers
 * of src/io that read scene textures. */
#include "mesh_import.h"

#include <ctype.h>
#include <dirent.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/error.h"
#include "io/image.h"
#include "load/loader.h"
#include "scene/scene.h"
#include "shade/texture.h"

/* The file in dir whose name matches name but for case ("EarthCylindric.jpg"
 * written, "earthCylindric.jpg" on disk), or NULL. */
static char *match_case(const char *dir, const char *name)
{
    DIR *d = opendir(dir[0] ? dir : ".");
    char *found = NULL;
    struct dirent *e;
    while (d && !found && (e = readdir(d)) != NULL)
        if (strcasecmp(e->d_name, name) == 0)
            found = path_join(dir, e->d_name);
    if (d)
        closedir(d);
    return found;
}

/* A texture named by the model (with '\' read as '/'), tried in turn: as
 * written, relative to the model's folder (absolute paths as they are); an
 * absolute or drive-letter path again inside the model's folder; its last
 * part there; its last part there in any case (exporters often write the
 * author's own paths, from Windows). The first attempt's error is kept. */
static glint_rc read_named(mesh_file *f, const mesh_tex *t, image *img, glint_error *err)
{
    char *written = strndup((const char *)t->bytes, t->size);
    if (!written)
        return err_nomem(err);
    for (char *c = written; *c; c++)
        if (*c == '\\')
            *c = '/';
    const char *rel = written;
    if (isalpha((unsigned char)rel[0]) && rel[1] == ':')
        rel += 2;
    while (*rel == '/')
        rel++;
    const char *last = strrchr(written, '/') ? strrchr(written, '/') + 1 : written;
    char *folder = path_join(f->dir, rel), *slash = folder ? strrchr(folder, '/') : NULL;
    if (slash)
        *slash = 0;
    glint_rc rc = folder ? GLINT_ERR_INPUT : err_nomem(err);
    glint_error e = {0};
    for (int attempt = 0; attempt < 5 && rc == GLINT_ERR_INPUT; attempt++) {
        char *p = attempt == 0   ? path_join(f->dir, written)
                  : attempt == 1 ? (rel != written ? path_join(f->dir, rel) : NULL)
                  : attempt == 2 ? (slash ? match_case(folder, last) : NULL)
                  : attempt == 3 ? (last != rel ? path_join(f->dir, last) : NULL)
                                 : match_case(f->dir, last);
        if (p)
            rc = image_load(p, img, attempt == 0 ? err : &e);
        free(p);
    }
    free(folder);
    free(written);
    return rc;
}

static glint_rc load_texels(const mesh_tex *t, image *img, glint_error *err)
{
    size_t n = (size_t)t->width * t->height;
    img->width = (int)t->width;
    img->height = (int)t->height;
    img->linear = NULL;
    img->rgb = malloc(n * 3);
    if (!img->rgb)
        return err_nomem(err);
    for (size_t i = 0; i < n; i++) {
        img->rgb[3 * i] = t->bytes[4 * i + 2];
        img->rgb[3 * i + 1] = t->bytes[4 * i + 1];
        img->rgb[3 * i + 2] = t->bytes[4 * i];
    }
    return GLINT_OK;
}

/* The scene texture for the file's texture i, or -1 (with a warning) when
 * it cannot be read; GLINT_ERR_NOMEM only for memory. */
static glint_rc add_texture(scene *s, mesh_file *f, int i, int *tex, glint_error *err)
{
    const mesh_tex *t = &f->textures[i];
    image img = {0};
    glint_error e = {0};
    glint_rc rc;
    char shown[64];
    snprintf(shown, sizeof shown, "texture %d", i);
    *tex = -1;
    if (t->kind == MESH_TEX_FILE && !f->dir)
        rc = err_set(&e, GLINT_ERR_INPUT, "'%.*s' is not read for a mesh given from memory",
                     (int)(t->size < 200 ? t->size : 200), (const char *)t->bytes);
    else if (t->kind == MESH_TEX_FILE)
        rc = read_named(f, t, &img, &e);
    else if (t->kind == MESH_TEX_ENCODED)
        rc = image_load_memory(t->bytes, t->size, shown, &img, &e);
    else
        rc = load_texels(t, &img, &e);
    if (rc == GLINT_ERR_NOMEM)
        return err_nomem(err);
    if (rc != GLINT_OK) {
        mesh_file_warn(f, "%s: texture not used: %s", f->name, e.msg);
        return GLINT_OK;
    }
    int im = scene_add_image(s, &img);
    if (im < 0) {
        image_free(&img);
        return err_nomem(err);
    }
    texture tx = texture_image(im);
    *tex = scene_add_texture(s, &tx);
    return *tex < 0 ? err_nomem(err) : GLINT_OK;
}

glint_rc mesh_file_add(scene *s, mesh_file *f, int *index, glint_error *err)
{
    int *tex = malloc((f->ntextures ? (size_t)f->ntextures : 1) * sizeof *tex);
    if (!tex)
        return err_nomem(err);
    glint_rc rc = GLINT_OK;
    for (int i = 0; rc == GLINT_OK && i < f->ntextures; i++)
        rc = add_texture(s, f, i, &tex[i], err);
    int base = scene_material_count(s);
    for (int i = 0; rc == GLINT_OK && i < f->nmaterials; i++) {
        material m = f->materials[i];
        m.texture = m.texture >= 0 && m.texture < f->ntextures ? tex[m.texture] : -1;
        if (scene_add_material(s, &m) < 0)
            rc = err_nomem(err);
    }
    free(tex);
    if (rc != GLINT_OK)
        return rc;
    for (int t = 0; t < f->mesh->ntris; t++)
        f->mesh->tri_material[t] += base;
    *index = scene_add_mesh(s, f->mesh);
    if (*index < 0)
        return err_nomem(err);
    f->mesh = NULL;
    return GLINT_OK;
}

void mesh_file_free(mesh_file *f)
{
    if (f->mesh) {
        mesh_free(f->mesh);
        free(f->mesh);
    }
    free(f->materials);
    for (int i = 0; f->textures && i < f->ntextures; i++)
        free(f->textures[i].bytes);
    free(f->textures);
    free(f->dir);
    free(f->name);
    memset(f, 0, sizeof *f);
}

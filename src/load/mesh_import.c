#include "mesh_import.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "geom/shape.h"
#include "load/assimp_load.h"
#include "load/mesh_assimp.h"
#include "load/mesh_isolate.h"
#include "load/mesh_limits.h"
#include "load/load.h"
#include "load/names.h"

/* Corners farther than this from the origin are dropped: products of two
 * coordinates (cross products, ray offsets) must stay finite in float. So
 * are triangles whose normal overflows single precision (triangle_check). */
#define MESH_MAX_COORD 1e15f

/* assimp keeps the reason for the last failure in one process-wide string,
 * so in-process imports are serialised: the message read after a failed
 * import is that import's own, whatever other threads load at the same time.
 * The child processes are started under the same lock, so none is forked
 * while another thread is inside assimp. The library's only shared state. */
static pthread_mutex_t import_lock = PTHREAD_MUTEX_INITIALIZER;

void mesh_file_warn(mesh_file *f, const char *fmt, ...)
{
    size_t used = strlen(f->warnings);
    if (used + 2 >= sizeof f->warnings)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(f->warnings + used, sizeof f->warnings - used - 1, fmt, ap);
    va_end(ap);
    strcat(f->warnings, "\n");
}

/* ---- checks on what came back ------------------------------------------- */

typedef struct drops {
    int nonfinite, huge, zero;
} drops;

/* Marks the triangles mesh_init must drop and counts them by reason. */
static void screen(const mesh_data *md, uint32_t (*tri)[3], drops *d)
{
    for (uint32_t t = 0; t < md->ntris; t++) {
        double c[3][3];
        bool finite = true, huge = false;
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++) {
                c[k][j] = md->pos[tri[t][k]][j];
                finite = finite && isfinite(c[k][j]);
                huge = huge || fabs(c[k][j]) > MESH_MAX_COORD;
            }
        double e1[3], e2[3];
        for (int j = 0; j < 3; j++) {
            e1[j] = c[1][j] - c[0][j];
            e2[j] = c[2][j] - c[0][j];
        }
        double n0 = e1[1] * e2[2] - e1[2] * e2[1], n1 = e1[2] * e2[0] - e1[0] * e2[2],
               n2 = e1[0] * e2[1] - e1[1] * e2[0];
        bool zero = !(n0 * n0 + n1 * n1 + n2 * n2 > 0);
        if (finite && !huge && !zero) { /* the renderer's own test, in floats */
            const float *p0 = md->pos[tri[t][0]], *p1 = md->pos[tri[t][1]],
                        *p2 = md->pos[tri[t][2]];
            triangle_fit fit = triangle_check(v3(p0[0], p0[1], p0[2]), v3(p1[0], p1[1], p1[2]),
                                              v3(p2[0], p2[1], p2[2]));
            huge = fit == TRIANGLE_TOO_LARGE;
            zero = fit == TRIANGLE_DEGENERATE;
        }
        if (!finite)
            d->nonfinite++;
        else if (huge)
            d->huge++;
        else if (zero)
            d->zero++;
        if (!finite || huge || zero)
            tri[t][0] = tri[t][1] = tri[t][2] = UINT32_MAX; /* dropped by mesh_init */
    }
}

static void drop_warning(mesh_file *f, const char *name, const drops *d, int dropped,
                         uint32_t total, uint32_t bad_faces)
{
    if (bad_faces > 0)
        mesh_file_warn(f, "%s: %u faces with bad indices left out", name, bad_faces);
    if (dropped <= 0)
        return;
    char why[256] = "";
    int zero = dropped - d->nonfinite - d->huge; /* mesh_init's own checks add to these */
    if (d->nonfinite)
        snprintf(why + strlen(why), sizeof why - strlen(why), ", %d with NaN or infinite corners",
                 d->nonfinite);
    if (zero > 0)
        snprintf(why + strlen(why), sizeof why - strlen(why), ", %d of zero area", zero);
    if (d->huge)
        snprintf(why + strlen(why), sizeof why - strlen(why),
                 ", %d too large for single precision (overflow)", d->huge);
    mesh_file_warn(f, "%s: %d of %u triangles dropped (%s)", name, dropped, total, why + 2);
}

static material to_material(const mesh_mat *mm)
{
    material m = material_default();
    m.color = v3(mm->diffuse[0], mm->diffuse[1], mm->diffuse[2]);
    m.specular = fmaxf(mm->specular[0], fmaxf(mm->specular[1], mm->specular[2]));
    if (mm->shininess > 0)
        m.shininess = mm->shininess;
    if (mm->opacity < 1)
        m.transmit = 1.0f - mm->opacity;
    m.texture = mm->texture;
    if (!v3_is_finite(m.color) || !isfinite(m.specular) || !isfinite(m.shininess) ||
        !isfinite(m.transmit))
        m = material_default();
    return m;
}

/* The arrays of md moved or copied into m (md keeps what it still owns). */
static glint_rc take_arrays(mesh_data *md, mesh *m, glint_error *err)
{
    size_t nv = md->nverts, nt = md->ntris;
    m->nverts = (int)nv;
    m->ntris = (int)nt;
    m->pos = malloc(nv * sizeof *m->pos);
    m->nrm = md->nrm ? malloc(nv * sizeof *m->nrm) : NULL;
    m->col = md->col ? malloc(nv * sizeof *m->col) : NULL;
    m->tri_material = malloc(nt * sizeof *m->tri_material);
    if (!m->pos || (md->nrm && !m->nrm) || (md->col && !m->col) || !m->tri_material)
        return err_nomem(err);
    for (size_t v = 0; v < nv; v++) {
        m->pos[v] = v3(md->pos[v][0], md->pos[v][1], md->pos[v][2]);
        if (m->nrm) {
            vec3 n = v3(md->nrm[v][0], md->nrm[v][1], md->nrm[v][2]);
            m->nrm[v] = v3_is_finite(n) && v3_len2(n) > 0 ? v3_norm(n) : v3s(0.0f);
        }
        if (m->col) {
            vec3 c = v3(md->col[v][0], md->col[v][1], md->col[v][2]);
            m->col[v] = v3_is_finite(c) ? c : v3s(1.0f);
        }
    }
    for (size_t t = 0; t < nt; t++)
        m->tri_material[t] = (int32_t)md->tri_mat[t];
    m->uv = md->uv;
    md->uv = NULL;
    m->tri = md->tri;
    md->tri = NULL;
    return GLINT_OK;
}

glint_rc mesh_file_from_data(mesh_data *md, const char *name, int threads, mesh_file *out,
                             glint_error *err)
{
    if (md->ntris == 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: mesh has no triangles", name);
    if (md->nverts > INT_MAX || md->ntris > INT_MAX)
        return err_set(err, GLINT_ERR_INPUT, "%s: mesh is too large", name);
    mesh *m = calloc(1, sizeof *m);
    out->materials = malloc(md->nmats * sizeof *out->materials);
    if (!m || !out->materials) {
        free(m);
        return err_nomem(err);
    }
    out->nmaterials = (int)md->nmats;
    for (uint32_t i = 0; i < md->nmats; i++)
        out->materials[i] = to_material(&md->mats[i]);
    drops d = {0, 0, 0};
    screen(md, md->tri, &d);
    uint32_t total = md->ntris;
    glint_rc rc = take_arrays(md, m, err);
    if (rc == GLINT_OK)
        rc = mesh_init(m, name, threads, &out->dropped, err);
    if (rc != GLINT_OK) {
        mesh_free(m);
        free(m);
        free(out->materials);
        out->materials = NULL;
        out->nmaterials = 0;
        return rc;
    }
    out->mesh = m;
    drop_warning(out, name, &d, out->dropped, total, md->dropped);
    if (md->skinned)
        mesh_file_warn(out, "%s: %u skinned mesh%s shown in the rest pose of the file's skeleton", name,
             md->skinned, md->skinned == 1 ? "" : "es");
    out->textures = md->texs;
    out->ntextures = (int)md->ntexs;
    md->texs = NULL;
    md->ntexs = 0;
    return GLINT_OK;
}

/* ---- importing ------------------------------------------------------------ */

/* The first bytes of the file at path, refusing anything but a regular file
 * without blocking (load_open_regular); *size gets its size. */
static glint_rc read_head(const char *path, char *head, size_t *n, uint64_t *size,
                          glint_error *err)
{
    int fd;
    glint_error oerr = {0};
    if (load_open_regular(path, &fd, &oerr) != GLINT_OK)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot open mesh: %s", path, oerr.msg);
    struct stat st;
    glint_rc rc = GLINT_OK;
    ssize_t got = -1;
    if (fstat(fd, &st) == 0) {
        *size = (uint64_t)st.st_size;
        while ((got = read(fd, head, MESH_HEAD_BYTES)) < 0 && errno == EINTR)
            ;
    }
    if (got < 0)
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read mesh: %s", path, strerror(errno));
    *n = got < 0 ? 0 : (size_t)got;
    close(fd);
    return rc;
}

/* The lines of an ASCII PLY's body, from the file at path or from data. */
static uint64_t body_lines(const char *path, const void *data, size_t size, uint64_t body)
{
    bool open = false;
    if (data)
        return body < size ? mesh_count_lines((const char *)data + body, size - body, &open) : 0;
    FILE *f = fopen(path, "rb"); /* a regular file: read_head checked it */
    if (!f || fseek(f, (long)body, SEEK_SET) != 0) {
        if (f)
            fclose(f);
        return 0;
    }
    char buf[65536];
    uint64_t lines = 0;
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, f)) > 0)
        lines += mesh_count_lines(buf, got, &open);
    fclose(f);
    return lines;
}

/* A warning when the file holds fewer faces than its header declares. */
static void check_count(mesh_file *out, const char *name, const void *data, size_t size,
                        const mesh_header *hdr, uint64_t got)
{
    uint64_t faces = hdr->faces;
    if (hdr->lines) {
        uint64_t lines = body_lines(name, data, size, hdr->body);
        uint64_t missing = lines < hdr->lines ? hdr->lines - lines : 0;
        got = missing < faces ? faces - missing : 0;
    }
    if (got < faces)
        mesh_file_warn(out, "%s: the header declares %llu faces but the file holds %llu (truncated file?)",
             name, (unsigned long long)faces, (unsigned long long)got);
}

static glint_rc run_import(const char *name, const void *data, size_t size,
                           const mesh_header *hdr, const mesh_options *opts, mesh_file *out,
                           glint_error *err)
{
    mesh_limits lim;
    mesh_limits_get(&lim);
    mesh_assimp_opts ao = {opts ? opts->smooth_angle : MESH_DEFAULT_SMOOTH_ANGLE, lim.triangles};
    if (!(ao.smooth_angle >= 0 && ao.smooth_angle <= 180))
        ao.smooth_angle = MESH_DEFAULT_SMOOTH_ANGLE;
    mesh_data md;
    glint_rc rc;
    /* assimp opened here, before a child process is forked, not in it */
    const char *why_not = NULL;
    if (!assimp_load(&why_not))
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot import meshes: %s", name, why_not);
    pthread_mutex_lock(&import_lock);
    if (lim.trusted) {
        rc = mesh_assimp_read(name, data, size, &ao, &md, err);
        pthread_mutex_unlock(&import_lock);
    } else {
        /* the lock is released in the parent once the child exists */
        rc = mesh_isolate_read(name, data, size, &ao, &lim, &import_lock, &md, err);
    }
    if (rc == GLINT_OK && md.ntris > lim.triangles)
        rc = err_set(err, GLINT_ERR_INPUT, "%s: mesh is too large (%u triangles, limit %llu)", name,
                     md.ntris, (unsigned long long)lim.triangles);
    uint64_t got = rc == GLINT_OK ? (uint64_t)md.ntris + md.dropped : 0;
    if (rc == GLINT_OK)
        rc = mesh_file_from_data(&md, name, opts ? opts->threads : 0, out, err);
    if (rc == GLINT_OK)
        check_count(out, name, data, size, hdr, got);
    mesh_data_free(&md);
    return rc;
}

static glint_rc set_names(mesh_file *out, const char *name, bool with_dir, glint_error *err)
{
    out->name = strdup(name);
    if (with_dir) {
        const char *slash = strrchr(name, '/');
        size_t n = !slash ? 0 : slash == name ? 1 : (size_t)(slash - name);
        out->dir = strndup(name, n);
    }
    return !out->name || (with_dir && !out->dir) ? err_nomem(err) : GLINT_OK;
}

glint_rc mesh_import(const char *path, const mesh_options *opts, mesh_file *out,
                     glint_error *err)
{
    memset(out, 0, sizeof *out);
    char *head = malloc(MESH_HEAD_BYTES);
    if (!head)
        return err_nomem(err);
    size_t n = 0;
    uint64_t size = 0;
    mesh_header hdr;
    mesh_limits lim;
    mesh_limits_get(&lim);
    glint_rc rc = read_head(path, head, &n, &size, err);
    if (rc == GLINT_OK)
        rc = mesh_precheck(path, head, n, size, &lim, &hdr, err);
    free(head);
    if (rc == GLINT_OK)
        rc = set_names(out, path, true, err);
    if (rc == GLINT_OK)
        rc = run_import(path, NULL, 0, &hdr, opts, out, err);
    if (rc != GLINT_OK)
        mesh_file_free(out);
    return rc;
}

glint_rc mesh_import_memory(const void *data, size_t size, const char *name,
                            const mesh_options *opts, mesh_file *out, glint_error *err)
{
    memset(out, 0, sizeof *out);
    if (size == 0 || size > UINT_MAX)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot import mesh: %s", name,
                       size ? "file too large" : "file is empty");
    mesh_limits lim;
    mesh_limits_get(&lim);
    mesh_header hdr;
    glint_rc rc = mesh_precheck(name, data, size < MESH_HEAD_BYTES ? size : MESH_HEAD_BYTES,
                                size, &lim, &hdr, err);
    if (rc == GLINT_OK)
        rc = set_names(out, name, false, err);
    if (rc == GLINT_OK)
        rc = run_import(name, data, size, &hdr, opts, out, err);
    if (rc != GLINT_OK)
        mesh_file_free(out);
    return rc;
}

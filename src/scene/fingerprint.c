#include "fingerprint.h"

#include "scene.h"

uint64_t fingerprint_bytes(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ULL;
    }
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
    return hash_int(h, (int64_t)st->transfer);
}

static uint64_t hash_materials(uint64_t h, const scene *s)
{
    for (int i = 0; i < s->nmaterials; i++) {
        const material *m = &s->materials[i];
        h = hash_vec(hash_int(h, m->texture), m->color);
        const float f[] = {m->ambient, m->diffuse, m->specular, m->shininess,
                           m->reflect, m->transmit, m->ior};
        for (size_t k = 0; k < sizeof f / sizeof f[0]; k++)
            h = hash_float(h, f[k]);
        h = hash_vec(h, m->tint);
    }
    return h;
}

static uint64_t hash_textures(uint64_t h, const scene *s)
{
    for (int i = 0; i < s->ntextures; i++) {
        const texture *t = &s->textures[i];
        h = hash_int(hash_int(h, (int64_t)t->kind), t->image);
        h = hash_vec(hash_vec(h, t->even), t->odd);
        h = hash_float(hash_float(h, t->scale_u), t->scale_v);
        h = hash_float(hash_float(h, t->offset_u), t->offset_v);
        h = hash_int(hash_int(h, (int64_t)t->wrap_u), (int64_t)t->wrap_v);
    }
    for (int i = 0; i < s->nimages; i++) {
        const image *im = &s->images[i];
        size_t n = (size_t)im->width * (size_t)im->height * 3;
        h = hash_int(hash_int(h, im->width), im->height);
        if (im->rgb)
            h = fingerprint_bytes(h, im->rgb, n);
        if (im->linear)
            h = fingerprint_bytes(h, im->linear, n * sizeof *im->linear);
    }
    return h;
}

static uint64_t hash_meshes(uint64_t h, const scene *s)
{
    for (int i = 0; i < s->nmeshes; i++) {
        const mesh *m = s->meshes[i];
        size_t nv = (size_t)m->nverts, nt = (size_t)m->ntris;
        h = hash_int(hash_int(h, m->nverts), m->ntris);
        h = fingerprint_bytes(h, m->pos, nv * sizeof *m->pos);
        h = fingerprint_bytes(h, m->tri, nt * sizeof *m->tri);
        if (m->nrm)
            h = fingerprint_bytes(h, m->nrm, nv * sizeof *m->nrm);
        if (m->uv)
            h = fingerprint_bytes(h, m->uv, nv * sizeof *m->uv);
        if (m->tri_material)
            h = fingerprint_bytes(h, m->tri_material, nt * sizeof *m->tri_material);
    }
    return h;
}

/* A shape's own numbers, member by member: one case per kind. */
static uint64_t hash_shape(uint64_t h, const scene *s, const shape *sh)
{
    h = hash_int(h, (int64_t)sh->kind);
    switch (sh->kind) {
    case SHAPE_SPHERE:
        return hash_float(hash_vec(h, sh->sphere.center), sh->sphere.radius);
    case SHAPE_PLANE:
        return hash_vec(hash_vec(h, sh->plane.point), sh->plane.normal);
    case SHAPE_QUAD:
        return hash_vec(hash_vec(hash_vec(h, sh->quad.origin), sh->quad.edge_u), sh->quad.edge_v);
    case SHAPE_BOX:
        return hash_vec(hash_vec(h, sh->box.lo), sh->box.hi);
    case SHAPE_CYLINDER:
        h = hash_float(hash_float(hash_vec(h, sh->cylinder.base), sh->cylinder.radius),
                       sh->cylinder.height);
        return hash_int(h, sh->cylinder.capped);
    case SHAPE_TRIANGLE:
        h = hash_vec(hash_vec(hash_vec(h, sh->triangle.p0), sh->triangle.p1), sh->triangle.p2);
        return fingerprint_bytes(h, sh->triangle.uv, sizeof sh->triangle.uv);
    case SHAPE_MESH:
        for (int i = 0; i < s->nmeshes; i++)
            if (s->meshes[i] == sh->mesh)
                return hash_int(h, i);
        return h;
    }
    return h;
}

static uint64_t hash_objects(uint64_t h, const scene *s)
{
    for (int i = 0; i < s->nxforms; i++)
        h = fingerprint_bytes(h, s->xforms[i].fwd.m, sizeof s->xforms[i].fwd.m);
    for (int i = 0; i < s->nobjects; i++) {
        const object *o = &s->objects[i];
        h = hash_int(hash_int(hash_shape(h, s, &o->shape), o->material), o->xform);
    }
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        h = hash_vec(hash_vec(hash_int(h, (int64_t)l->kind), l->position), l->color);
    }
    return h;
}

uint64_t scene_fingerprint(const scene *s, const glint_settings *settings)
{
    uint64_t h = hash_settings(FINGERPRINT_SEED, settings);
    const camera *c = &s->camera;
    h = hash_float(hash_vec(hash_vec(hash_vec(h, c->eye), c->target), c->up), c->hfov);
    h = hash_vec(hash_vec(h, s->background), s->ambient);
    h = hash_materials(h, s);
    h = hash_textures(h, s);
    h = hash_meshes(h, s);
    return hash_objects(h, s);
}

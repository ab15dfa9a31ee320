#include "yaml_merge.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"
#include "core/error.h"

/* A pair while merge keys are applied and duplicates found. */
typedef struct ymerge_pair {
    const char *text;
    uint32_t len;
    uint32_t key, value;
    uint32_t order; /* own pairs first, in file order, then merged ones */
} mpair;

/* The state of one mapping's merge. */
typedef struct job {
    ymerge *m;
    const ydoc *d;
    const char *name;
    glint_error *err;
} job;

static int by_key_then_order(const void *pa, const void *pb)
{
    const mpair *a = pa, *b = pb;
    uint32_t n = a->len < b->len ? a->len : b->len;
    int c = memcmp(a->text, b->text, n);
    if (c == 0 && a->len != b->len)
        c = a->len < b->len ? -1 : 1;
    if (c == 0)
        c = a->order < b->order ? -1 : a->order > b->order ? 1 : 0;
    return c;
}

/* Texts are NUL-terminated, so the first bytes can be compared first:
 * keys of one mapping mostly differ there. */
static bool same_text(const char *a, uint32_t alen, const char *b, uint32_t blen)
{
    return alen == blen && a[0] == b[0] && memcmp(a, b, alen) == 0;
}

static bool same_key(const mpair *a, const mpair *b)
{
    return same_text(a->text, a->len, b->text, b->len);
}

static int by_order(const void *pa, const void *pb)
{
    const mpair *a = pa, *b = pb;
    return a->order < b->order ? -1 : a->order > b->order ? 1 : 0;
}

/* Whether the pairs stand as read: a few scalar keys, none a merge key,
 * all different (most mappings); the general way would keep them as they
 * are, and need not be taken. */
static bool as_read(const ydoc *d, const uint32_t *kids, size_t nkids)
{
    if (nkids % 2 != 0 || nkids > 32)
        return false;
    for (size_t i = 0; i < nkids; i += 2) {
        const ynode *k = &d->nodes[kids[i]];
        if (k->kind == YNODE_SEQ || k->kind == YNODE_MAP || (k->flags & YNODE_MERGE_KEY))
            return false;
        for (size_t j = 0; j < i; j += 2) {
            const ynode *o = &d->nodes[kids[j]];
            if (same_text(d->text + k->first, k->count, d->text + o->first, o->count))
                return false;
        }
    }
    return true;
}

static glint_rc add_pair(job *j, size_t *n, uint32_t key, uint32_t value)
{
    ymerge *m = j->m;
    if (*n >= UINT32_MAX)
        return err_set(j->err, GLINT_ERR_INPUT, "%s: the document is too large", j->name);
    if (!array_reserve((void **)&m->pairs, &m->cap_pairs, *n + 1, sizeof *m->pairs))
        return err_nomem(j->err);
    const ynode *k = &j->d->nodes[key];
    m->pairs[*n] = (mpair){j->d->text + k->first, k->count, key, value, (uint32_t)*n};
    (*n)++;
    return GLINT_OK;
}

/* The pairs less merged keys the mapping has, in order; refuses repeated
 * own keys. A few own pairs, all different (most mappings), need no sorting. */
static glint_rc dedupe(job *j, size_t n, size_t own, size_t nsources, size_t *kept)
{
    mpair *pairs = j->m->pairs;
    bool repeats = nsources > 0 || n > 16;
    for (size_t i = 1; i < n && !repeats; i++)
        for (size_t k = 0; k < i && !repeats; k++)
            repeats = same_key(&pairs[i], &pairs[k]);
    *kept = n;
    if (!repeats)
        return GLINT_OK;
    qsort(pairs, n, sizeof *pairs, by_key_then_order);
    *kept = 0;
    for (size_t i = 0; i < n; i++) {
        const mpair *p = &pairs[i];
        if (*kept > 0 && same_key(p, &pairs[*kept - 1])) {
            if (p->order < own) {
                const ynode *k = &j->d->nodes[p->key];
                const ynode *first = &j->d->nodes[pairs[*kept - 1].key];
                char shown[YDOC_SHOW_MAX * 4 + 8];
                ydoc_show(p->text, p->len, shown, sizeof shown);
                return err_set(j->err, GLINT_ERR_INPUT,
                               "%s:%u:%u: duplicate key '%s' (first at line %u, column %u)",
                               j->name, k->line, k->col, shown, first->line, first->col);
            }
            continue;
        }
        pairs[(*kept)++] = *p;
    }
    qsort(pairs, *kept, sizeof *pairs, by_order);
    return GLINT_OK;
}

/* The mappings a merge key's value v names, appended to m->ids. */
static glint_rc add_sources(job *j, uint32_t v, size_t *nsources)
{
    const ynode *vn = &j->d->nodes[v];
    size_t count = vn->kind == YNODE_SEQ ? vn->count : 1;
    for (size_t i = 0; i < count; i++) {
        uint32_t s = vn->kind == YNODE_SEQ ? ydoc_item(j->d, vn, (uint32_t)i) : v;
        const ynode *sn = &j->d->nodes[s];
        if (sn->kind != YNODE_MAP)
            return err_set(j->err, GLINT_ERR_INPUT,
                           "%s:%u:%u: a merge key '<<' takes a mapping or a list of mappings, "
                           "not %s",
                           j->name, sn->line, sn->col, ydoc_kind_name((ynode_kind)sn->kind));
        if (!array_reserve((void **)&j->m->ids, &j->m->cap_ids, *nsources + 1, sizeof *j->m->ids))
            return err_nomem(j->err);
        j->m->ids[(*nsources)++] = s;
    }
    return GLINT_OK;
}

/* Collects the mapping's own pairs, then those of merged mappings, into
 * m->pairs (*n of them, the first own of them its own). */
static glint_rc collect(job *j, const uint32_t *kids, size_t nkids, size_t *n, size_t *own,
                        size_t *nsources)
{
    const ydoc *d = j->d;
    for (size_t i = 0; i + 1 < nkids; i += 2) {
        const ynode *k = &d->nodes[kids[i]];
        if (k->kind == YNODE_SEQ || k->kind == YNODE_MAP)
            return err_set(j->err, GLINT_ERR_INPUT,
                           "%s:%u:%u: a mapping key must be a single value, not %s", j->name,
                           k->line, k->col, ydoc_kind_name((ynode_kind)k->kind));
        glint_rc rc = k->flags & YNODE_MERGE_KEY ? add_sources(j, kids[i + 1], nsources)
                                                 : add_pair(j, n, kids[i], kids[i + 1]);
        if (rc != GLINT_OK)
            return rc;
    }
    *own = *n;
    for (size_t s = 0; s < *nsources; s++) {
        const ynode *sn = &d->nodes[j->m->ids[s]];
        for (uint32_t p = 0; p < sn->count; p++) {
            glint_rc rc = add_pair(j, n, ydoc_key(d, sn, p), ydoc_value(d, sn, p));
            if (rc != GLINT_OK)
                return rc;
        }
    }
    return GLINT_OK;
}

glint_rc ymerge_pairs(ymerge *m, const ydoc *d, const char *name, glint_error *err,
                      const uint32_t **kids, size_t *n)
{
    if (as_read(d, *kids, *n)) {
        *n /= 2;
        return GLINT_OK;
    }
    job j = {m, d, name, err};
    size_t npairs = 0, own = 0, nsources = 0, kept;
    glint_rc rc = collect(&j, *kids, *n, &npairs, &own, &nsources);
    if (rc == GLINT_OK)
        rc = dedupe(&j, npairs, own, nsources, &kept);
    if (rc != GLINT_OK)
        return rc;
    /* The merged mappings are done with: their room takes the list. */
    if (!array_reserve((void **)&m->ids, &m->cap_ids, 2 * kept, sizeof *m->ids))
        return err_nomem(err);
    for (size_t i = 0; i < kept; i++) {
        m->ids[2 * i] = m->pairs[i].key;
        m->ids[2 * i + 1] = m->pairs[i].value;
    }
    *kids = m->ids;
    *n = kept;
    return GLINT_OK;
}

void ymerge_free(ymerge *m)
{
    free(m->pairs);
    free(m->ids);
    *m = (ymerge){0};
}

#include "yaml_doc.h"

#include <errno.h>
#include <langinfo.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "core/error.h"
#include "core/text.h"
#include "load/names.h"
#include "load/yaml_fast.h"

typedef struct anchor {
    uint32_t node;
    uint64_t size; /* nodes visited by walking it, aliases followed */
    bool open;     /* a collection still being read */
} anchor;

/* A collection being read: its children collect in pending[start ...]. */
typedef struct frame {
    uint32_t node;
    size_t start;
    uint64_t size;
    int anchor; /* index into anchors, or -1 */
} frame;

/* A mapping pair while merge keys are applied and duplicates found. */
typedef struct mpair {
    const char *text;
    uint32_t len;
    uint32_t key, value;
    uint32_t order; /* own pairs first, in file order, then merged ones */
} mpair;

typedef struct builder {
    ydoc *d;
    const char *name;
    const char *src;
    size_t srclen;
    glint_error *err;
    names anchor_names; /* anchor name -> index into anchors */
    anchor *anchors;
    int nanchors, cap_anchors;
    uint32_t *pending;
    size_t npending, cap_pending;
    frame stack[YDOC_MAX_DEPTH];
    int depth;
    uint64_t expanded; /* nodes a full walk visits so far */
    mpair *scratch;
    size_t cap_scratch;
    uint32_t *sources;
    size_t cap_sources;
    int documents;
    bool done;
} builder;

static glint_rc vfail(builder *b, uint32_t line, uint32_t col, const char *fmt, va_list ap)
{
    char msg[768];
    vsnprintf(msg, sizeof msg, fmt, ap);
    return err_set(b->err, GLINT_ERR_INPUT, "%s:%u:%u: %s", b->name, line, col, msg);
}

/* Fails with "NAME:LINE:COL: message" at a node's 1-based position. */
GLINT_PRINTF(4, 5)
static glint_rc fail(builder *b, uint32_t line, uint32_t col, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    glint_rc rc = vfail(b, line, col, fmt, ap);
    va_end(ap);
    return rc;
}

/* The same at a libyaml mark (0-based). */
GLINT_PRINTF(3, 4)
static glint_rc fail_mark(builder *b, yaml_mark_t m, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    glint_rc rc = vfail(b, (uint32_t)m.line + 1, (uint32_t)m.column + 1, fmt, ap);
    va_end(ap);
    return rc;
}

/* Grows *p (element size elem, capacity *cap) to hold at least need. */
static bool reserve(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return true;
    size_t ncap = *cap ? *cap : 16;
    while (ncap < need) {
        if (ncap > SIZE_MAX / 2 / elem)
            return false;
        ncap *= 2;
    }
    void *q = realloc(*p, ncap * elem);
    if (!q)
        return false;
    *p = q;
    *cap = ncap;
    return true;
}

/* Types a scalar by its tag, or for an untagged plain scalar by its form. */
static glint_rc resolve_scalar(builder *b, const yaml_event_t *ev, ynode *n)
{
    const char *s = (const char *)ev->data.scalar.value;
    size_t len = ev->data.scalar.length;
    const char *tag = (const char *)ev->data.scalar.tag;
    bool plain = !tag && ev->data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
    if (!tag && !plain) {
        n->kind = YNODE_STRING;
        return GLINT_OK;
    }
    if (tag && (strcmp(tag, "!") == 0 || strcmp(tag, YAML_STR_TAG) == 0)) {
        n->kind = YNODE_STRING;
        return GLINT_OK;
    }
    bool is_true, is_int;
    ynode_kind kind = ydoc_plain_kind(s, len, &is_true, &is_int);
    if (plain) {
        if (len == 2 && memcmp(s, "<<", 2) == 0)
            n->flags |= YNODE_MERGE_KEY;
    } else {
        const char *want = NULL;
        if (strcmp(tag, YAML_NULL_TAG) == 0) {
            want = kind == YNODE_NULL ? NULL : "!!null";
        } else if (strcmp(tag, YAML_BOOL_TAG) == 0) {
            want = kind == YNODE_BOOL ? NULL : "!!bool";
        } else if (strcmp(tag, YAML_INT_TAG) == 0) {
            want = kind == YNODE_NUMBER && is_int ? NULL : "!!int";
        } else if (strcmp(tag, YAML_FLOAT_TAG) == 0) {
            want = kind == YNODE_NUMBER ? NULL : "!!float";
        } else {
            char shown[YDOC_SHOW_MAX * 4 + 8];
            ydoc_show(tag, strlen(tag), shown, sizeof shown);
            return fail_mark(b, ev->start_mark, "unsupported tag '%s'", shown);
        }
        if (want) {
            char shown[YDOC_SHOW_MAX * 4 + 8];
            ydoc_show(s, len, shown, sizeof shown);
            return fail_mark(b, ev->start_mark, "'%s' is not a valid %s", shown, want);
        }
    }
    n->kind = (uint8_t)kind;
    if (kind == YNODE_BOOL && is_true)
        n->flags |= YNODE_TRUE;
    return GLINT_OK;
}

/* ---- tree building ---------------------------------------------------- */

static glint_rc new_node(builder *b, ynode_kind kind, yaml_mark_t m, uint32_t *out)
{
    ydoc *d = b->d;
    if (d->nnodes >= YDOC_MAX_NODES)
        return err_set(b->err, GLINT_ERR_INPUT, "%s:%u:%u: more than %u YAML nodes", b->name,
                       (uint32_t)m.line + 1, (uint32_t)m.column + 1, YDOC_MAX_NODES);
    if (d->nnodes == d->cap_nodes) {
        size_t cap = d->cap_nodes;
        if (!reserve((void **)&d->nodes, &cap, (size_t)d->nnodes + 1, sizeof *d->nodes))
            return err_nomem(b->err);
        d->cap_nodes = cap > YDOC_MAX_NODES ? YDOC_MAX_NODES : (uint32_t)cap;
    }
    *out = d->nnodes++;
    d->nodes[*out] = (ynode){(uint8_t)kind, 0, (uint32_t)m.line + 1, (uint32_t)m.column + 1, 0, 0};
    b->expanded++;
    return GLINT_OK;
}

/* Hands a finished node (size: nodes a walk of it visits) to its parent. */
static glint_rc add_child(builder *b, uint32_t node, uint64_t size)
{
    if (b->depth == 0) {
        b->d->root = node;
        return GLINT_OK;
    }
    if (!reserve((void **)&b->pending, &b->cap_pending, b->npending + 1, sizeof *b->pending))
        return err_nomem(b->err);
    b->pending[b->npending++] = node;
    b->stack[b->depth - 1].size += size;
    return GLINT_OK;
}

static glint_rc begin_anchor(builder *b, const yaml_char_t *name, uint32_t node, bool open,
                             int *index)
{
    *index = -1;
    if (!name)
        return GLINT_OK;
    if (b->nanchors == b->cap_anchors) {
        size_t cap = (size_t)b->cap_anchors;
        if (cap > INT_MAX / 4 ||
            !reserve((void **)&b->anchors, &cap, (size_t)b->nanchors + 1, sizeof *b->anchors))
            return err_nomem(b->err);
        b->cap_anchors = (int)cap;
    }
    *index = b->nanchors++;
    b->anchors[*index] = (anchor){node, 1, open};
    const char *s = (const char *)name;
    if (!names_put(&b->anchor_names, s, strlen(s), *index))
        return err_nomem(b->err);
    return GLINT_OK;
}

static glint_rc on_scalar(builder *b, const yaml_event_t *ev)
{
    ydoc *d = b->d;
    size_t len = ev->data.scalar.length;
    if (len >= UINT32_MAX - d->ntext)
        return fail_mark(b, ev->start_mark, "the file is too large");
    uint32_t node;
    glint_rc rc = new_node(b, YNODE_STRING, ev->start_mark, &node);
    if (rc != GLINT_OK)
        return rc;
    if (!reserve((void **)&d->text, &d->cap_text, d->ntext + len + 1, 1))
        return err_nomem(b->err);
    ynode *n = &d->nodes[node];
    n->first = (uint32_t)d->ntext;
    n->count = (uint32_t)len;
    memcpy(d->text + d->ntext, ev->data.scalar.value, len);
    d->text[d->ntext + len] = '\0';
    d->ntext += len + 1;
    rc = resolve_scalar(b, ev, n);
    int a;
    if (rc == GLINT_OK)
        rc = begin_anchor(b, ev->data.scalar.anchor, node, false, &a);
    if (rc == GLINT_OK)
        rc = add_child(b, node, 1);
    return rc;
}

static glint_rc on_alias(builder *b, const yaml_event_t *ev)
{
    const char *name = (const char *)ev->data.alias.anchor;
    char shown[YDOC_SHOW_MAX * 4 + 8];
    ydoc_show(name, strlen(name), shown, sizeof shown);
    int i = names_find(&b->anchor_names, name, strlen(name));
    if (i < 0)
        return fail_mark(b, ev->start_mark, "alias '*%s' names no anchor defined before it",
                         shown);
    const anchor *a = &b->anchors[i];
    if (a->open)
        return fail_mark(b, ev->start_mark,
                         "alias '*%s' refers to a collection that contains it", shown);
    b->expanded += a->size;
    uint64_t limit = YDOC_EXPANSION_SLACK + (uint64_t)YDOC_EXPANSION_RATIO * b->d->nnodes;
    if (b->expanded > limit) {
        return fail_mark(b, ev->start_mark, "aliases expand the document beyond %llu nodes",
                         (unsigned long long)limit);
    }
    return add_child(b, a->node, a->size);
}

static glint_rc begin_collection(builder *b, const yaml_event_t *ev, ynode_kind kind)
{
    bool map = kind == YNODE_MAP;
    const yaml_char_t *tag = map ? ev->data.mapping_start.tag : ev->data.sequence_start.tag;
    const yaml_char_t *anchor_name =
        map ? ev->data.mapping_start.anchor : ev->data.sequence_start.anchor;
    if (tag && strcmp((const char *)tag, "!") != 0 &&
        strcmp((const char *)tag, map ? YAML_MAP_TAG : YAML_SEQ_TAG) != 0) {
        char shown[YDOC_SHOW_MAX * 4 + 8];
        ydoc_show((const char *)tag, strlen((const char *)tag), shown, sizeof shown);
        return fail_mark(b, ev->start_mark, "unsupported tag '%s'", shown);
    }
    if (b->depth == YDOC_MAX_DEPTH)
        return fail_mark(b, ev->start_mark, "collections nested more than %d deep",
                         YDOC_MAX_DEPTH);
    uint32_t node;
    glint_rc rc = new_node(b, kind, ev->start_mark, &node);
    if (rc != GLINT_OK)
        return rc;
    frame *f = &b->stack[b->depth++];
    *f = (frame){node, b->npending, 1, -1};
    return begin_anchor(b, anchor_name, node, true, &f->anchor);
}

/* Appends n node ids to the document's kids; first gets where they start. */
static glint_rc push_kids(builder *b, const uint32_t *ids, size_t n, uint32_t *first)
{
    ydoc *d = b->d;
    if (d->nkids + n > UINT32_MAX)
        return err_set(b->err, GLINT_ERR_INPUT, "%s: the document is too large", b->name);
    if (!reserve((void **)&d->kids, &d->cap_kids, d->nkids + n, sizeof *d->kids))
        return err_nomem(b->err);
    *first = (uint32_t)d->nkids;
    if (n)
        memcpy(d->kids + d->nkids, ids, n * sizeof *ids);
    d->nkids += n;
    return GLINT_OK;
}

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

static bool same_key(const mpair *a, const mpair *b)
{
    return a->len == b->len && memcmp(a->text, b->text, a->len) == 0;
}

static int by_order(const void *pa, const void *pb)
{
    const mpair *a = pa, *b = pb;
    return a->order < b->order ? -1 : a->order > b->order ? 1 : 0;
}

static glint_rc add_pair(builder *b, size_t *n, uint32_t key, uint32_t value)
{
    if (*n >= UINT32_MAX)
        return err_set(b->err, GLINT_ERR_INPUT, "%s: the document is too large", b->name);
    if (!reserve((void **)&b->scratch, &b->cap_scratch, *n + 1, sizeof *b->scratch))
        return err_nomem(b->err);
    const ynode *k = &b->d->nodes[key];
    b->scratch[*n] = (mpair){b->d->text + k->first, k->count, key, value, (uint32_t)*n};
    (*n)++;
    return GLINT_OK;
}

/* The pairs less merged keys the mapping has, in order; refuses repeated
 * own keys. A few own pairs, all different (most mappings), need no sorting. */
static glint_rc dedupe(builder *b, size_t n, size_t own, size_t nsources, size_t *kept)
{
    bool repeats = nsources > 0 || n > 16;
    for (size_t i = 1; i < n && !repeats; i++)
        for (size_t j = 0; j < i && !repeats; j++)
            repeats = same_key(&b->scratch[i], &b->scratch[j]);
    *kept = n;
    if (!repeats)
        return GLINT_OK;
    qsort(b->scratch, n, sizeof *b->scratch, by_key_then_order);
    *kept = 0;
    for (size_t i = 0; i < n; i++) {
        const mpair *p = &b->scratch[i];
        if (*kept > 0 && same_key(p, &b->scratch[*kept - 1])) {
            if (p->order < own) {
                const ynode *k = &b->d->nodes[p->key];
                const ynode *first = &b->d->nodes[b->scratch[*kept - 1].key];
                char shown[YDOC_SHOW_MAX * 4 + 8];
                ydoc_show(p->text, p->len, shown, sizeof shown);
                return fail(b, k->line, k->col, "duplicate key '%s' (first at line %u, column %u)",
                            shown, first->line, first->col);
            }
            continue;
        }
        b->scratch[(*kept)++] = *p;
    }
    qsort(b->scratch, *kept, sizeof *b->scratch, by_order);
    return GLINT_OK;
}

/* Collects the mapping's own pairs, then those of merged mappings, drops
 * merged keys it already has and refuses repeated own keys (YAML 1.1 merge
 * key type, https://yaml.org/type/merge.html). */
static glint_rc finish_map(builder *b, ynode *map, const uint32_t *kids, size_t nkids)
{
    ydoc *d = b->d;
    size_t n = 0, nsources = 0;
    for (size_t i = 0; i + 1 < nkids; i += 2) {
        const ynode *k = &d->nodes[kids[i]], *v = &d->nodes[kids[i + 1]];
        if (k->kind == YNODE_SEQ || k->kind == YNODE_MAP)
            return fail(b, k->line, k->col, "a mapping key must be a single value, not %s",
                        ydoc_kind_name((ynode_kind)k->kind));
        if (!(k->flags & YNODE_MERGE_KEY)) {
            glint_rc rc = add_pair(b, &n, kids[i], kids[i + 1]);
            if (rc != GLINT_OK)
                return rc;
            continue;
        }
        size_t count = v->kind == YNODE_SEQ ? v->count : 1;
        for (size_t j = 0; j < count; j++) {
            uint32_t s = v->kind == YNODE_SEQ ? ydoc_item(d, v, (uint32_t)j) : kids[i + 1];
            const ynode *sn = &d->nodes[s];
            if (sn->kind != YNODE_MAP)
                return fail(b, sn->line, sn->col,
                            "a merge key '<<' takes a mapping or a list of mappings, not %s",
                            ydoc_kind_name((ynode_kind)sn->kind));
            if (!reserve((void **)&b->sources, &b->cap_sources, nsources + 1, sizeof *b->sources))
                return err_nomem(b->err);
            b->sources[nsources++] = s;
        }
    }
    size_t own = n;
    for (size_t j = 0; j < nsources; j++) {
        const ynode *sn = &d->nodes[b->sources[j]];
        for (uint32_t p = 0; p < sn->count; p++) {
            glint_rc rc = add_pair(b, &n, ydoc_key(d, sn, p), ydoc_value(d, sn, p));
            if (rc != GLINT_OK)
                return rc;
        }
    }
    size_t kept;
    glint_rc rc = dedupe(b, n, own, nsources, &kept);
    if (rc != GLINT_OK)
        return rc;
    /* Reuse the sources buffer for the flat key, value list. */
    if (!reserve((void **)&b->sources, &b->cap_sources, 2 * kept, sizeof *b->sources))
        return err_nomem(b->err);
    for (size_t i = 0; i < kept; i++) {
        b->sources[2 * i] = b->scratch[i].key;
        b->sources[2 * i + 1] = b->scratch[i].value;
    }
    uint32_t first;
    rc = push_kids(b, b->sources, 2 * kept, &first);
    map->first = first;
    map->count = (uint32_t)kept;
    return rc;
}

static glint_rc end_collection(builder *b)
{
    frame f = b->stack[--b->depth];
    ynode *n = &b->d->nodes[f.node];
    const uint32_t *kids = b->pending ? b->pending + f.start : NULL;
    size_t nkids = b->npending - f.start;
    glint_rc rc;
    if (n->kind == YNODE_MAP) {
        rc = finish_map(b, n, kids, nkids);
    } else {
        uint32_t first;
        rc = push_kids(b, kids, nkids, &first);
        n->first = first;
        n->count = (uint32_t)nkids;
    }
    if (rc != GLINT_OK)
        return rc;
    b->npending = f.start;
    if (f.anchor >= 0) {
        b->anchors[f.anchor].open = false;
        b->anchors[f.anchor].size = f.size;
    }
    return add_child(b, f.node, f.size);
}

static glint_rc on_event(builder *b, const yaml_event_t *ev)
{
    switch (ev->type) {
    case YAML_NO_EVENT:
    case YAML_STREAM_START_EVENT:
    case YAML_DOCUMENT_END_EVENT:
        return GLINT_OK;
    case YAML_STREAM_END_EVENT:
        b->done = true;
        return GLINT_OK;
    case YAML_DOCUMENT_START_EVENT:
        if (++b->documents > 1)
            return fail_mark(b, ev->start_mark,
                             "a second YAML document: a scene file holds one document");
        return GLINT_OK;
    case YAML_ALIAS_EVENT:
        return on_alias(b, ev);
    case YAML_SCALAR_EVENT:
        return on_scalar(b, ev);
    case YAML_SEQUENCE_START_EVENT:
        return begin_collection(b, ev, YNODE_SEQ);
    case YAML_MAPPING_START_EVENT:
        return begin_collection(b, ev, YNODE_MAP);
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT:
        return end_collection(b);
    }
    return GLINT_OK;
}

/* Line and column (1-based, in characters) of a byte offset into the text. */
static void offset_position(const char *s, size_t len, size_t offset, uint32_t *line,
                            uint32_t *col)
{
    uint32_t l = 1, c = 1;
    for (size_t i = 0; i < offset && i < len; i++) {
        unsigned char ch = (unsigned char)s[i];
        if (ch == '\n') {
            l++;
            c = 1;
        } else if ((ch & 0xC0) != 0x80) {
            c++;
        }
    }
    *line = l;
    *col = c;
}

/* The column (from 1) of the first tab in the indentation of the line
 * holding byte at, or 0 when it has none. libyaml's own words for a tab
 * that indents ("found character that cannot start any token") do not
 * say what is wrong. */
static uint32_t indent_tab(const char *src, size_t len, size_t at)
{
    if (at > len)
        return 0;
    size_t start = at;
    while (start > 0 && src[start - 1] != '\n' && src[start - 1] != '\r')
        start--;
    for (size_t i = start; i < len && (src[i] == ' ' || src[i] == '\t'); i++)
        if (src[i] == '\t')
            return (uint32_t)(i - start + 1);
    return 0;
}

static glint_rc parser_error(builder *b, const yaml_parser_t *p)
{
    const char *problem = p->problem ? p->problem : "cannot parse the YAML";
    switch (p->error) {
    case YAML_MEMORY_ERROR:
        return err_nomem(b->err);
    case YAML_READER_ERROR: {
        uint32_t line, col;
        offset_position(b->src, b->srclen, p->problem_offset, &line, &col);
        if (p->problem_value >= 0)
            return fail(b, line, col, "%s (byte 0x%02X)", problem, (unsigned)p->problem_value);
        return fail(b, line, col, "%s", problem);
    }
    case YAML_NO_ERROR:
    case YAML_SCANNER_ERROR:
    case YAML_PARSER_ERROR:
    case YAML_COMPOSER_ERROR:
    case YAML_WRITER_ERROR:
    case YAML_EMITTER_ERROR:
        break;
    }
    uint32_t line = (uint32_t)p->problem_mark.line + 1, col = (uint32_t)p->problem_mark.column + 1;
    uint32_t tab = indent_tab(b->src, b->srclen, p->problem_mark.index);
    if (tab)
        return fail(b, line, tab, "tabs cannot indent YAML; use spaces");
    if (p->context)
        return fail(b, line, col, "%s (%s at line %u, column %u)", problem, p->context,
                    (uint32_t)p->context_mark.line + 1, (uint32_t)p->context_mark.column + 1);
    return fail(b, line, col, "%s", problem);
}

static glint_rc take_event(void *ctx, const yaml_event_t *ev) { return on_event(ctx, ev); }

/* The text through libyaml, event by event. */
static glint_rc read_libyaml(builder *b, const char *text, size_t len)
{
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser))
        return err_nomem(b->err);
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, len);
    glint_rc rc = GLINT_OK;
    while (!b->done) {
        yaml_event_t ev;
        if (!yaml_parser_parse(&parser, &ev)) {
            rc = parser_error(b, &parser);
            break;
        }
        rc = on_event(b, &ev);
        yaml_event_delete(&ev);
        if (rc != GLINT_OK)
            break;
    }
    yaml_parser_delete(&parser);
    return rc;
}

/* The plain subset by yaml_fast; any other text, and any text the tree
 * refuses (for libyaml's word on what comes first), again by libyaml. */
glint_rc ydoc_parse(const char *text, size_t len, const char *name, ydoc **out,
                    glint_error *err)
{
    glint_rc rc = GLINT_OK;
    for (int pass = 0; pass < 2; pass++) {
        ydoc *d = calloc(1, sizeof *d);
        if (!d)
            return err_nomem(err);
        d->root = YDOC_NONE;
        builder b = {.d = d, .name = name, .src = text, .srclen = len, .err = err};
        rc = pass > 0 ? read_libyaml(&b, text, len)
             : yfast_read(text, len, take_event, &b) == YFAST_DONE ? GLINT_OK : GLINT_ERR_INPUT;
        names_free(&b.anchor_names);
        free(b.anchors);
        free(b.pending);
        free(b.scratch);
        free(b.sources);
        if (rc == GLINT_OK) {
            *out = d;
            return GLINT_OK;
        }
        ydoc_free(d);
        if (rc == GLINT_ERR_NOMEM)
            break;
    }
    return rc;
}

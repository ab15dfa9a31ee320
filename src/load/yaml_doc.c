#include "yaml_doc.h"

#include <limits.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "core/array.h"
#include "core/error.h"
#include "core/spare.h"
#include "core/text.h"
#include "load/names.h"
#include "load/yaml_fast.h"
#include "load/yaml_merge.h"

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
    ymerge merge;
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

/* Types an untagged plain scalar by its form; a plain << is a merge key. */
static void type_plain(ynode *n, const char *s, size_t len)
{
    bool is_true, is_int;
    n->kind = (uint8_t)ydoc_plain_kind(s, len, &is_true, &is_int);
    if (n->kind == YNODE_BOOL && is_true)
        n->flags |= YNODE_TRUE;
    if (len == 2 && s[0] == '<' && s[1] == '<')
        n->flags |= YNODE_MERGE_KEY;
}

/* Types a scalar by its tag, or for an untagged plain scalar by its form. */
static glint_rc resolve_scalar(builder *b, const yaml_event_t *ev, ynode *n)
{
    const char *s = (const char *)ev->data.scalar.value;
    size_t len = ev->data.scalar.length;
    const char *tag = (const char *)ev->data.scalar.tag;
    if (!tag && ev->data.scalar.style == YAML_PLAIN_SCALAR_STYLE) {
        type_plain(n, s, len);
        return GLINT_OK;
    }
    if (!tag || strcmp(tag, "!") == 0 || strcmp(tag, YAML_STR_TAG) == 0) {
        n->kind = YNODE_STRING;
        return GLINT_OK;
    }
    bool is_true, is_int;
    ynode_kind kind = ydoc_plain_kind(s, len, &is_true, &is_int);
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
    n->kind = (uint8_t)kind;
    if (kind == YNODE_BOOL && is_true)
        n->flags |= YNODE_TRUE;
    return GLINT_OK;
}

/* ---- tree building ---------------------------------------------------- */

/* array_reserve for an array of the tree: one that lies in the spare
 * block (reserve_for) is first copied to the heap, its room with it, since
 * growing frees the old block; false when memory runs out. */
static bool tree_reserve(ydoc *d, void **items, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return true;
    if (ydoc_borrowed(d, *items)) {
        size_t bytes = *cap * elem;
        void *q = malloc(bytes > 0 ? bytes : 1);
        if (!q)
            return false;
        memcpy(q, *items, bytes);
        *items = q;
    }
    return array_grow(items, cap, need, elem);
}

/* Room for one more node; the limit is met when the room, which never
 * grows past it, is full. */
static glint_rc grow_nodes(builder *b, yaml_mark_t m)
{
    ydoc *d = b->d;
    if (d->nnodes >= YDOC_MAX_NODES)
        return err_set(b->err, GLINT_ERR_INPUT, "%s:%u:%u: more than %u YAML nodes", b->name,
                       (uint32_t)m.line + 1, (uint32_t)m.column + 1, YDOC_MAX_NODES);
    size_t cap = d->cap_nodes;
    if (!tree_reserve(d, (void **)&d->nodes, &cap, (size_t)d->nnodes + 1, sizeof *d->nodes))
        return err_nomem(b->err);
    d->cap_nodes = cap > YDOC_MAX_NODES ? YDOC_MAX_NODES : (uint32_t)cap;
    return GLINT_OK;
}

static glint_rc new_node(builder *b, ynode_kind kind, yaml_mark_t m, uint32_t *out)
{
    ydoc *d = b->d;
    if (d->nnodes == d->cap_nodes) {
        glint_rc rc = grow_nodes(b, m);
        if (rc != GLINT_OK)
            return rc;
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
    if (!array_reserve((void **)&b->pending, &b->cap_pending, b->npending + 1, sizeof *b->pending))
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
            !array_reserve((void **)&b->anchors, &cap, (size_t)b->nanchors + 1, sizeof *b->anchors))
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

/* s[0 .. len) as scalar node n's text: copied to the end of the text,
 * NUL-terminated, where there is room for it. */
static inline void put_text(ydoc *d, ynode *n, const char *s, size_t len)
{
    n->first = (uint32_t)d->ntext;
    n->count = (uint32_t)len;
    memcpy(d->text + d->ntext, s, len);
    d->text[d->ntext + len] = '\0';
    d->ntext += len + 1;
}

/* A new scalar node at m holding a copy of s[0 .. len), NUL-terminated. */
static glint_rc new_scalar(builder *b, const char *s, size_t len, yaml_mark_t m, uint32_t *node)
{
    ydoc *d = b->d;
    if (len >= UINT32_MAX - d->ntext)
        return fail_mark(b, m, "the file is too large");
    glint_rc rc = new_node(b, YNODE_STRING, m, node);
    if (rc != GLINT_OK)
        return rc;
    if (!tree_reserve(d, (void **)&d->text, &d->cap_text, d->ntext + len + 1, 1))
        return err_nomem(b->err);
    put_text(d, &d->nodes[*node], s, len);
    return GLINT_OK;
}

static glint_rc on_scalar(builder *b, const yaml_event_t *ev)
{
    uint32_t node;
    int a;
    glint_rc rc = new_scalar(b, (const char *)ev->data.scalar.value, ev->data.scalar.length,
                             ev->start_mark, &node);
    if (rc == GLINT_OK)
        rc = resolve_scalar(b, ev, &b->d->nodes[node]);
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

/* A collection starting at m (tag and anchor_name may be NULL). */
static glint_rc open_collection(builder *b, ynode_kind kind, const yaml_char_t *tag,
                                const yaml_char_t *anchor_name, yaml_mark_t m)
{
    if (tag && strcmp((const char *)tag, "!") != 0 &&
        strcmp((const char *)tag, kind == YNODE_MAP ? YAML_MAP_TAG : YAML_SEQ_TAG) != 0) {
        char shown[YDOC_SHOW_MAX * 4 + 8];
        ydoc_show((const char *)tag, strlen((const char *)tag), shown, sizeof shown);
        return fail_mark(b, m, "unsupported tag '%s'", shown);
    }
    if (b->depth == YDOC_MAX_DEPTH)
        return fail_mark(b, m, "collections nested more than %d deep", YDOC_MAX_DEPTH);
    uint32_t node;
    glint_rc rc = new_node(b, kind, m, &node);
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
    if (!tree_reserve(d, (void **)&d->kids, &d->cap_kids, d->nkids + n, sizeof *d->kids))
        return err_nomem(b->err);
    *first = (uint32_t)d->nkids;
    if (n)
        memcpy(d->kids + d->nkids, ids, n * sizeof *ids);
    d->nkids += n;
    return GLINT_OK;
}

static glint_rc end_collection(builder *b)
{
    frame f = b->stack[--b->depth];
    ynode *n = &b->d->nodes[f.node];
    const uint32_t *kids = b->pending ? b->pending + f.start : NULL;
    size_t nkids = b->npending - f.start;
    size_t count = nkids; /* the items, or the mapping's pairs */
    glint_rc rc = GLINT_OK;
    if (n->kind == YNODE_MAP)
        rc = ymerge_pairs(&b->merge, b->d, b->name, b->err, &kids, &count);
    uint32_t first = 0;
    if (rc == GLINT_OK)
        rc = push_kids(b, kids, n->kind == YNODE_MAP ? 2 * count : count, &first);
    if (rc != GLINT_OK)
        return rc;
    n->first = first;
    n->count = (uint32_t)count;
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
        return open_collection(b, YNODE_SEQ, ev->data.sequence_start.tag,
                               ev->data.sequence_start.anchor, ev->start_mark);
    case YAML_MAPPING_START_EVENT:
        return open_collection(b, YNODE_MAP, ev->data.mapping_start.tag,
                               ev->data.mapping_start.anchor, ev->start_mark);
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT:
        return end_collection(b);
    }
    return GLINT_OK;
}

static glint_rc parser_error(builder *b, const yaml_parser_t *p)
{
    const char *problem = p->problem ? p->problem : "cannot parse the YAML";
    switch (p->error) {
    case YAML_MEMORY_ERROR:
        return err_nomem(b->err);
    case YAML_READER_ERROR: {
        uint32_t line, col;
        text_position(b->src, b->srclen, p->problem_offset, &line, &col);
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
    /* libyaml's words for a tab that indents do not say what is wrong */
    uint32_t tab = text_indent_tab(b->src, b->srclen, p->problem_mark.index);
    if (tab)
        return fail(b, line, tab, "tabs cannot indent YAML; use spaces");
    if (p->context)
        return fail(b, line, col, "%s (%s at line %u, column %u)", problem, p->context,
                    (uint32_t)p->context_mark.line + 1, (uint32_t)p->context_mark.column + 1);
    return fail(b, line, col, "%s", problem);
}

/* A plain scalar of the fast reader where the arrays have room and it
 * has a parent (nearly every one): new_scalar, type_plain and add_child
 * in one, less the growth and the checks that room makes needless, which
 * cost more than reading the scalar. False, having done nothing, when the
 * general way must take it. */
static bool fast_scalar(builder *b, const yfast_event *ev)
{
    ydoc *d = b->d;
    size_t len = ev->len;
    if (d->nnodes == d->cap_nodes || b->depth == 0 || b->npending == b->cap_pending ||
        d->cap_text - d->ntext <= len || d->ntext + len >= UINT32_MAX)
        return false;
    uint32_t node = d->nnodes++;
    ynode *n = &d->nodes[node];
    *n = (ynode){YNODE_STRING, 0, (uint32_t)ev->line + 1, (uint32_t)ev->column + 1, 0, 0};
    put_text(d, n, ev->text, len);
    type_plain(n, ev->text, len);
    b->expanded++;
    b->pending[b->npending++] = node;
    b->stack[b->depth - 1].size++;
    return true;
}

/* An event of the fast reader: plain scalars and collections with no tag
 * or anchor go straight into the tree; the stream's and the document's
 * events take libyaml's way. */
static glint_rc take_fast(void *ctx, const yfast_event *ev)
{
    builder *b = ctx;
    yaml_mark_t m = {0, ev->line, ev->column};
    uint32_t node;
    glint_rc rc;
    switch (ev->type) {
    case YAML_SCALAR_EVENT:
        if (fast_scalar(b, ev))
            return GLINT_OK;
        rc = new_scalar(b, ev->text, ev->len, m, &node);
        if (rc == GLINT_OK)
            type_plain(&b->d->nodes[node], ev->text, ev->len);
        return rc == GLINT_OK ? add_child(b, node, 1) : rc;
    case YAML_SEQUENCE_START_EVENT:
        return open_collection(b, YNODE_SEQ, NULL, NULL, m);
    case YAML_MAPPING_START_EVENT:
        return open_collection(b, YNODE_MAP, NULL, NULL, m);
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT:
        return end_collection(b);
    default:
        return on_event(b, &(yaml_event_t){.type = (yaml_event_type_t)ev->type, .start_mark = m});
    }
}

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

/* Room for n items of `elem` bytes in the empty array *items made up
 * front, where array_realloc gives that in huge pages; the room made, or
 * 0. */
static size_t reserve(void **items, size_t n, size_t elem)
{
    if (n * elem < ARRAY_HUGE_FROM)
        return 0;
    void *p = array_realloc(NULL, 0, n * elem);
    if (!p)
        return 0;
    *items = p;
    return n;
}

/* Room made up front for the tree of a big text of len bytes, from what
 * scenes hold (a node for every 6 bytes of bench/tori.awk's scene, text
 * for 0.8 of its bytes): a node and a child index for every 5 bytes, text
 * as long, each array at most 64 MiB. The arrays then start in huge pages
 * instead of passing through 4 KiB ones on their way up. Only a hint: an
 * array it leaves out, or that fills, grows as it goes. */
static void reserve_for(ydoc *d, size_t len)
{
    const size_t most = (size_t)64 << 20;
    size_t nodes = len / 5, kids = len / 5, text = len;
    nodes = nodes > most / sizeof *d->nodes ? most / sizeof *d->nodes : nodes;
    nodes = nodes > YDOC_MAX_NODES ? YDOC_MAX_NODES : nodes;
    kids = kids > most / sizeof *d->kids ? most / sizeof *d->kids : kids;
    text = text > most ? most : text;
    /* in the process's spare block when it has one (core/spare.h): the
     * film made after the load then takes the same pages; not under
     * AddressSanitizer, which sees overruns between heap blocks, not
     * between arrays carved from one mapping */
    size_t bn = (nodes * sizeof *d->nodes + 63) / 64 * 64;
    size_t bk = (kids * sizeof *d->kids + 63) / 64 * 64;
    if (!YDOC_SANITIZED && bn + bk + text >= ARRAY_HUGE_FROM &&
        (d->block = spare_take(bn + bk + text, NULL))) {
        d->block_bytes = bn + bk + text;
        d->nodes = (ynode *)(void *)d->block;
        d->kids = (uint32_t *)(void *)(d->block + bn);
        d->text = d->block + bn + bk;
        d->cap_nodes = (uint32_t)nodes, d->cap_kids = kids, d->cap_text = text;
        return;
    }
    d->cap_nodes = (uint32_t)reserve((void **)&d->nodes, nodes, sizeof *d->nodes);
    d->cap_kids = reserve((void **)&d->kids, kids, sizeof *d->kids);
    d->cap_text = reserve((void **)&d->text, text, 1);
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
        reserve_for(d, len);
        builder b = {.d = d, .name = name, .src = text, .srclen = len, .err = err};
        rc = pass > 0 ? read_libyaml(&b, text, len)
             : yfast_read(text, len, take_fast, &b) == YFAST_DONE ? GLINT_OK : GLINT_ERR_INPUT;
        names_free(&b.anchor_names);
        free(b.anchors);
        free(b.pending);
        ymerge_free(&b.merge);
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

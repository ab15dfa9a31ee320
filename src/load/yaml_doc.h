/* yaml_doc: one YAML document read with libyaml into a tree of nodes that
 * remember where they were written, so that every later complaint about the
 * scene can name a line and column. Text in the plain subset that most
 * scenes are written in is read by yaml_fast instead, which hands the tree
 * builder the events libyaml would (from 0.8 G instructions down to 0.25 G
 * for bench/tori.awk's 11,000 objects).
 *
 * What the tree guarantees, once ydoc_parse has succeeded:
 *  - Scalars are typed by the YAML 1.2 core schema: plain null, true/false
 *    and numbers are recognised; quoted scalars are strings; the standard
 *    tags !!str, !!int, !!float, !!bool, !!null, !!seq and !!map are
 *    honoured and any other tag is refused.
 *  - Aliases are resolved: an alias is the very node its anchor names, so
 *    the tree is a DAG sharing reused parts, never copying them.
 *  - Merge keys (<<) are applied: a mapping holds its own pairs, then the
 *    pairs of each merged mapping whose keys it does not already have
 *    (earlier merged mappings win over later ones), in that order.
 *  - No mapping has two keys with the same text, and every key is a scalar.
 *  - The document is no deeper than YDOC_MAX_DEPTH collections, has at most
 *    YDOC_MAX_NODES nodes, and walking it in full (following every alias)
 *    visits at most YDOC_EXPANSION_SLACK + YDOC_EXPANSION_RATIO times the
 *    number of nodes written: the defence against "billion laughs" files.
 *
 * Errors are one line, "NAME:LINE:COLUMN: what is wrong", with 1-based line
 * and column, and GLINT_ERR_INPUT (GLINT_ERR_NOMEM when memory runs out). */
#ifndef GLINT_LOAD_YAML_DOC_H
#define GLINT_LOAD_YAML_DOC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "glint.h"

#define YDOC_MAX_DEPTH 64
#define YDOC_MAX_NODES (1u << 27)
#define YDOC_EXPANSION_SLACK 1000000u
#define YDOC_EXPANSION_RATIO 4u

#define YDOC_NONE UINT32_MAX /* "no node" */

typedef enum ynode_kind {
    YNODE_NULL,
    YNODE_BOOL,
    YNODE_NUMBER, /* text matches the core schema's int or float forms */
    YNODE_STRING,
    YNODE_SEQ,
    YNODE_MAP,
} ynode_kind;

typedef struct ynode {
    uint8_t kind;   /* ynode_kind */
    uint8_t flags;  /* YNODE_TRUE, YNODE_MERGE_KEY */
    uint32_t line, col;
    /* Scalars: text[first .. first + count), NUL-terminated.
     * SEQ: kids[first .. first + count) are the items.
     * MAP: kids[first .. first + 2 * count) are key, value, key, value... */
    uint32_t first, count;
} ynode;

#define YNODE_TRUE 1u      /* YNODE_BOOL: the value is true */
#define YNODE_MERGE_KEY 2u /* a plain, untagged << */

typedef struct ydoc {
    ynode *nodes;
    uint32_t nnodes, cap_nodes;
    uint32_t *kids;
    size_t nkids, cap_kids;
    char *text;
    size_t ntext, cap_text;
    uint32_t root; /* YDOC_NONE when the stream holds no document */
    /* The process's spare block (core/spare.h) when the arrays were made
     * up front in it, block_bytes long; else NULL. An array that outgrows
     * its room there moves to the heap (ydoc_borrowed tells which). */
    char *block;
    size_t block_bytes;
} ydoc;

/* Built under AddressSanitizer: the tree keeps to the heap (yaml_doc.c). */
#if defined(__SANITIZE_ADDRESS__)
#define YDOC_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define YDOC_SANITIZED 1
#endif
#endif
#if !defined(YDOC_SANITIZED)
#define YDOC_SANITIZED 0
#endif

/* Whether the array at p lies in d's block rather than on the heap. */
static inline bool ydoc_borrowed(const ydoc *d, const void *p)
{
    uintptr_t a = (uintptr_t)p, b = (uintptr_t)d->block;
    return d->block && a >= b && a - b < d->block_bytes;
}

/* Parses text (len bytes, UTF-8/16 as libyaml detects) into *out; name is
 * used in messages only. A stream with more than one document is refused. */
glint_rc ydoc_parse(const char *text, size_t len, const char *name, ydoc **out,
                    glint_error *err);
void ydoc_free(ydoc *d);

static inline const ynode *ydoc_node(const ydoc *d, uint32_t i) { return &d->nodes[i]; }

/* Scalar text (NUL-terminated; its length is node->count). */
static inline const char *ydoc_text(const ydoc *d, const ynode *n) { return d->text + n->first; }

/* Item i of a sequence; key and value of pair i of a mapping. */
static inline uint32_t ydoc_item(const ydoc *d, const ynode *n, uint32_t i)
{
    return d->kids[n->first + i];
}
static inline uint32_t ydoc_key(const ydoc *d, const ynode *n, uint32_t i)
{
    return d->kids[n->first + 2 * (size_t)i];
}
static inline uint32_t ydoc_value(const ydoc *d, const ynode *n, uint32_t i)
{
    return d->kids[n->first + 2 * (size_t)i + 1];
}

/* The value under key in mapping n, or YDOC_NONE (also when n is no
 * mapping). */
uint32_t ydoc_get(const ydoc *d, const ynode *map, const char *key);

/* The kind a plain (unquoted, untagged) scalar has by its form in the core
 * schema: null, bool (*is_true), number (*is_int for the integer forms) or
 * string. */
ynode_kind ydoc_plain_kind(const char *s, size_t len, bool *is_true, bool *is_int);

/* "null", "a boolean", "a number", "a string", "a sequence", "a mapping". */
const char *ydoc_kind_name(ynode_kind kind);

/* A YNODE_NUMBER as the nearest float, rounded as a C compiler rounds a
 * literal (so "0.92" gives exactly 0.92f); +-INFINITY for .inf and for
 * values beyond the float range, NAN for .nan. Ignores the C locale. */
float ydoc_float(const ydoc *d, const ynode *n);
/* Whether a YNODE_NUMBER is written .inf, -.inf or .nan (any case form). */
bool ydoc_is_special(const ydoc *d, const ynode *n);
/* Whether a YNODE_NUMBER is written as an integer (decimal, 0x hex or 0o
 * octal) rather than in a float form. */
bool ydoc_is_integer(const ydoc *d, const ynode *n);
/* An integer-form YNODE_NUMBER's value; false when beyond long long. */
bool ydoc_int(const ydoc *d, const ynode *n, long long *out);

/* Describes a node's kind for "expected ..., got X" messages: "null",
 * "true", "a number", "the string 'abc'", "a sequence", "a mapping". */
void ydoc_describe(const ydoc *d, const ynode *n, char *buf, size_t cap);

/* Copies text (len bytes, any content) into buf as one printable line for
 * a message: control bytes escaped as \xNN, long text cut short with "...". */
void ydoc_show(const char *text, size_t len, char *buf, size_t cap);

/* Longest text ydoc_show keeps before cutting, in bytes. */
#define YDOC_SHOW_MAX 60

#endif

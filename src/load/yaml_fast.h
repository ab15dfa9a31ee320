/* yaml_fast: a reader for the plain subset of YAML that scene files are
 * mostly written in, which hands ydoc_parse the very events libyaml would
 * (type, start mark, plain scalar text) at a fraction of libyaml's cost:
 * libyaml allocates and frees every token and event and decodes its input
 * a character at a time, which made reading a scene of 11,000 one-line
 * objects take longer than building its tree.
 *
 * The subset: ASCII text with spaces, no tabs or carriage returns; block
 * mappings whose keys are words ([A-Za-z0-9_.+-]) followed by ": ";
 * block sequences whose items are on the dash's line; flow mappings and
 * sequences on one line, a flow sequence's "key: value" items included;
 * plain scalars on one line without quotes or flow indicators; comments
 * after a space. Anything else (quotes, anchors, aliases, tags, merge
 * keys, block scalars, multi-line scalars or flow collections, empty
 * values, document markers, directives) makes it decline, and the caller
 * reads the text with libyaml instead, which also gives every error its
 * message: what the reader accepts it reads exactly as libyaml does
 * (tests/test_yaml_fast.c compares the two event by event). */
#ifndef GLINT_LOAD_YAML_FAST_H
#define GLINT_LOAD_YAML_FAST_H

#include <stddef.h>
#include "glint.h"

/* One event, as much of it as the subset can hold: libyaml's event type,
 * where the node starts (0-based line and column, as in libyaml's marks),
 * and a scalar's text, which points into the text being read (it is not
 * NUL-terminated). Nothing is tagged or anchored and every scalar is
 * plain, so handing over a whole yaml_event_t, with the text copied out
 * to be NUL-terminated, cost more than the reading. */
typedef struct yfast_event {
    int type; /* a yaml_event_type_t */
    size_t line, column;
    const char *text; /* scalars only; NULL otherwise */
    size_t len;
} yfast_event;

/* Takes one event; anything but GLINT_OK stops the reading. */
typedef glint_rc (*yfast_emit)(void *ctx, const yfast_event *ev);

typedef enum yfast_result {
    YFAST_DONE,     /* the whole stream was read and every event taken */
    YFAST_DECLINED, /* the text leaves the subset (some events may have gone) */
    YFAST_REFUSED,  /* emit refused an event */
} yfast_result;

yfast_result yfast_read(const char *text, size_t len, yfast_emit emit, void *ctx);

#endif

#include "yaml_fast.h"

#include <stdbool.h>
#include <string.h>
#include <yaml.h>

/* Longest scalar read here (libyaml's simple keys stop at 1024). */
#define MAX_SCALAR 1000

typedef struct reader {
    const char *s;     /* NUL after the text stands for its end */
    size_t len, pos;   /* pos: the next byte */
    size_t line, bol;  /* 0-based line of pos, and where that line begins */
    yfast_emit emit;
    void *ctx;
    yfast_result stop; /* YFAST_DONE while reading goes on */
} reader;

/* Where a node starts: 0-based line and column. */
typedef struct spot {
    size_t line, column;
} spot;

/* What each byte is to the scanners, looked up once instead of compared
 * with a list of characters one by one (a flow scalar's bytes were a
 * sixth of the reading). NUL stands for the end of the text. */
enum {
    STARTS_NOT = 1, /* cannot start a plain scalar */
    FLOW_END = 2,   /* ends a plain scalar in a flow collection */
    FLOW_OUT = 4,   /* leaves the subset inside a flow scalar */
};
static const unsigned char byte_class[256] = {
    ['\0'] = STARTS_NOT | FLOW_OUT, ['\n'] = STARTS_NOT | FLOW_OUT, [' '] = STARTS_NOT,
    ['?'] = STARTS_NOT,  [':'] = STARTS_NOT | FLOW_END, [','] = STARTS_NOT | FLOW_END,
    ['['] = STARTS_NOT | FLOW_OUT, [']'] = STARTS_NOT | FLOW_END,
    ['{'] = STARTS_NOT | FLOW_OUT, ['}'] = STARTS_NOT | FLOW_END,
    ['#'] = STARTS_NOT | FLOW_OUT, ['&'] = STARTS_NOT, ['*'] = STARTS_NOT, ['!'] = STARTS_NOT,
    ['|'] = STARTS_NOT, ['>'] = STARTS_NOT, ['\''] = STARTS_NOT, ['"'] = STARTS_NOT,
    ['%'] = STARTS_NOT,  ['@'] = STARTS_NOT, ['`'] = STARTS_NOT,
};

static inline char peek(const reader *r, size_t k)
{
    return r->pos + k < r->len ? r->s[r->pos + k] : '\0';
}

static inline size_t column(const reader *r) { return r->pos - r->bol; }

static inline bool blank_or_end(char c) { return c == ' ' || c == '\n' || c == '\0'; }

static bool decline(reader *r)
{
    if (r->stop == YFAST_DONE)
        r->stop = YFAST_DECLINED;
    return false;
}

static spot mark(const reader *r) { return (spot){r->line, column(r)}; }

static bool send(reader *r, const yfast_event *ev)
{
    if (r->emit(r->ctx, ev) != GLINT_OK) {
        r->stop = YFAST_REFUSED;
        return false;
    }
    return true;
}

/* A start or end event at m. */
static bool event(reader *r, yaml_event_type_t type, spot m)
{
    yfast_event ev = {(int)type, m.line, m.column, NULL, 0};
    return send(r, &ev);
}

/* The plain scalar s[start .. end) that begins at m. */
static bool scalar(reader *r, size_t start, size_t end, spot m)
{
    size_t n = end - start;
    if (n == 0 || n > MAX_SCALAR)
        return decline(r);
    yfast_event ev = {YAML_SCALAR_EVENT, m.line, m.column, r->s + start, n};
    return send(r, &ev);
}

static void skip_spaces(reader *r)
{
    while (peek(r, 0) == ' ')
        r->pos++;
}

/* Whether a plain scalar may start here: not with an indicator, and with
 * '-' only as a number's sign. */
static bool plain_start(const reader *r)
{
    char c = peek(r, 0);
    if (c == '-')
        return (peek(r, 1) >= '0' && peek(r, 1) <= '9') || peek(r, 1) == '.';
    return !(byte_class[(unsigned char)c] & STARTS_NOT);
}

static bool key_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '_' || c == '.' || c == '+' || c == '-';
}

/* Whether a key (a word, then ':' and a blank) starts at pos; *end is
 * where the word ends. */
static bool key_ahead(const reader *r, size_t *end)
{
    if (!plain_start(r))
        return false;
    size_t i = r->pos;
    while (i < r->len && key_char(r->s[i]))
        i++;
    if (i == r->pos || i >= r->len || r->s[i] != ':')
        return false;
    *end = i;
    return i + 1 >= r->len || r->s[i + 1] == ' ' || r->s[i + 1] == '\n';
}

/* The rest of the line is spaces, then a comment after a space or nothing:
 * past it and its newline. */
static bool end_line(reader *r)
{
    skip_spaces(r);
    char c = peek(r, 0);
    if (c == '#' && (r->pos == r->bol || r->s[r->pos - 1] == ' ')) {
        while (peek(r, 0) != '\n' && peek(r, 0) != '\0')
            r->pos++;
        c = peek(r, 0);
    }
    if (c == '\0')
        return true;
    if (c != '\n')
        return decline(r);
    r->pos++;
    r->line++;
    r->bol = r->pos;
    return true;
}

/* Past blank lines and comment lines, to the first character of the next
 * line with content: its column, or -1 at the end of the text. Lines that
 * libyaml reads differently ("---", "...", directives) decline. */
static long next_content(reader *r)
{
    for (;;) {
        skip_spaces(r);
        char c = peek(r, 0);
        if (c == '\0')
            return -1;
        if (c == '\n' || c == '#') {
            while (peek(r, 0) != '\n' && peek(r, 0) != '\0')
                r->pos++;
            if (peek(r, 0) == '\0')
                return -1;
            r->pos++;
            r->line++;
            r->bol = r->pos;
            continue;
        }
        if (column(r) == 0 && (c == '%' || (c == '-' && peek(r, 1) == '-') ||
                               (c == '.' && peek(r, 1) == '.')))
            return decline(r) ? -1 : -2;
        return (long)column(r);
    }
}

/* A plain scalar in a flow collection: up to ',', ']', '}' or ':', its
 * trailing spaces dropped. */
static bool flow_scalar(reader *r, size_t *start, size_t *end, spot *m)
{
    if (!plain_start(r))
        return decline(r);
    *m = mark(r);
    *start = r->pos;
    const char *s = r->s;
    size_t i = r->pos, last = i, len = r->len;
    unsigned cls = 0;
    for (; i < len; i++) {
        cls = byte_class[(unsigned char)s[i]] & (FLOW_END | FLOW_OUT);
        if (cls)
            break;
        if (s[i] != ' ')
            last = i + 1;
    }
    if (i == len)
        cls = FLOW_OUT; /* the end of the text */
    r->pos = i;
    *end = last;
    return cls == FLOW_END || decline(r);
}

static bool flow_node(reader *r);

/* After a flow mapping's key or a flow sequence's "key" item: ": " and
 * the value. */
static bool flow_value(reader *r)
{
    if (peek(r, 0) != ':' || peek(r, 1) != ' ')
        return decline(r);
    r->pos += 2;
    skip_spaces(r);
    return flow_node(r);
}

/* Past the spaces after an entry, and its ',' (not a trailing one);
 * *closed when the collection ends with close instead. */
static bool flow_next(reader *r, char close, bool *closed)
{
    skip_spaces(r);
    char c = peek(r, 0);
    *closed = c == close;
    if (*closed) {
        r->pos++;
        return true;
    }
    if (c != ',')
        return decline(r);
    r->pos++;
    skip_spaces(r);
    return peek(r, 0) != close || decline(r);
}

static bool flow_mapping(reader *r)
{
    if (!event(r, YAML_MAPPING_START_EVENT, mark(r)))
        return false;
    r->pos++;
    skip_spaces(r);
    bool closed = peek(r, 0) == '}';
    if (closed)
        r->pos++;
    while (!closed) {
        size_t start, end;
        spot m;
        if (!flow_scalar(r, &start, &end, &m) || (end != r->pos && !decline(r)) ||
            !scalar(r, start, end, m) ||
            !flow_value(r) || !flow_next(r, '}', &closed))
            return false;
    }
    return event(r, YAML_MAPPING_END_EVENT, mark(r));
}

/* A flow sequence; an item "key: value" is a mapping of one pair. */
static bool flow_sequence(reader *r)
{
    if (!event(r, YAML_SEQUENCE_START_EVENT, mark(r)))
        return false;
    r->pos++;
    skip_spaces(r);
    bool closed = peek(r, 0) == ']';
    if (closed)
        r->pos++;
    while (!closed) {
        char c = peek(r, 0);
        if (c == '[' || c == '{') {
            if (!flow_node(r))
                return false;
        } else {
            size_t start, end;
            spot m;
            if (!flow_scalar(r, &start, &end, &m))
                return false;
            if (peek(r, 0) == ':') {
                if ((end != r->pos && !decline(r)) || !event(r, YAML_MAPPING_START_EVENT, m) ||
                    !scalar(r, start, end, m) || !flow_value(r) ||
                    !event(r, YAML_MAPPING_END_EVENT, mark(r)))
                    return false;
            } else if (!scalar(r, start, end, m)) {
                return false;
            }
        }
        if (!flow_next(r, ']', &closed))
            return false;
    }
    return event(r, YAML_SEQUENCE_END_EVENT, mark(r));
}

static bool flow_node(reader *r)
{
    char c = peek(r, 0);
    if (c == '{')
        return flow_mapping(r);
    if (c == '[')
        return flow_sequence(r);
    size_t start, end;
    spot m;
    return flow_scalar(r, &start, &end, &m) && scalar(r, start, end, m);
}

/* A plain scalar that runs to the end of its line (or a comment), in a
 * block: no ": ", no flow indicators, no '#' but a comment's. */
static bool block_scalar(reader *r)
{
    if (!plain_start(r))
        return decline(r);
    spot m = mark(r);
    size_t start = r->pos, last = r->pos;
    for (char c = peek(r, 0); c != '\n' && c != '\0'; c = peek(r, 0)) {
        if (c == '#' && r->s[r->pos - 1] == ' ')
            break;
        if (strchr("#,[]{}", c) || (c == ':' && blank_or_end(peek(r, 1))))
            return decline(r);
        r->pos++;
        if (c != ' ')
            last = r->pos;
    }
    return scalar(r, start, last, m);
}

/* A value on the line it starts on: a flow collection or a plain scalar,
 * then the end of the line and the next line with content, which must not
 * be indented past indent (it would continue the value). */
static bool inline_value(reader *r, long indent, long *next)
{
    char c = peek(r, 0);
    if (!((c == '[' || c == '{') ? flow_node(r) : block_scalar(r)) || !end_line(r))
        return false;
    *next = next_content(r);
    return (*next >= -1 && *next <= indent) || decline(r);
}

static bool block_node(reader *r, long parent, long *next);
static bool block_sequence(reader *r, long indent, long *next);

static bool dash_ahead(const reader *r)
{
    return peek(r, 0) == '-' && blank_or_end(peek(r, 1));
}

/* A block mapping whose first key starts at pos, in column indent; *next
 * is the column of the line with content after it (-1: the end). */
static bool block_mapping(reader *r, long indent, long *next)
{
    if (!event(r, YAML_MAPPING_START_EVENT, mark(r)))
        return false;
    for (;;) {
        size_t end;
        if (!key_ahead(r, &end) || !scalar(r, r->pos, end, mark(r)))
            return decline(r);
        r->pos = end + 1;
        skip_spaces(r);
        char c = peek(r, 0);
        if (c == '\n' || c == '\0' || c == '#') {
            if (!end_line(r))
                return false;
            long col = next_content(r);
            if (col > indent) {
                if (!block_node(r, indent, next))
                    return false;
            } else if (col == indent && dash_ahead(r)) {
                if (!block_sequence(r, indent, next))
                    return false;
            } else {
                return decline(r); /* an empty value */
            }
        } else if (!inline_value(r, indent, next)) {
            return false;
        }
        if (*next < indent)
            break;
        if (*next > indent || dash_ahead(r))
            return decline(r);
    }
    return event(r, YAML_MAPPING_END_EVENT, mark(r));
}

/* A block sequence whose first dash is at pos, in column indent; each item
 * on its dash's line. */
static bool block_sequence(reader *r, long indent, long *next)
{
    if (!event(r, YAML_SEQUENCE_START_EVENT, mark(r)))
        return false;
    for (;;) {
        r->pos++;
        if (peek(r, 0) != ' ')
            return decline(r);
        skip_spaces(r);
        char c = peek(r, 0);
        size_t end;
        if (c == '\n' || c == '\0' || c == '#' || dash_ahead(r))
            return decline(r);
        if (c != '[' && c != '{' && key_ahead(r, &end)) {
            if (!block_mapping(r, (long)column(r), next))
                return false;
        } else if (!inline_value(r, indent, next)) {
            return false;
        }
        if (*next == indent && dash_ahead(r))
            continue;
        if (*next > indent)
            return decline(r);
        break;
    }
    return event(r, YAML_SEQUENCE_END_EVENT, mark(r));
}

/* A node on a line of its own, at pos, indented past parent. */
static bool block_node(reader *r, long parent, long *next)
{
    long indent = (long)column(r);
    char c = peek(r, 0);
    size_t end;
    if (dash_ahead(r))
        return block_sequence(r, indent, next);
    if (c != '[' && c != '{' && key_ahead(r, &end))
        return block_mapping(r, indent, next);
    return inline_value(r, parent, next);
}

static bool plain_byte(unsigned char c) { return c == '\n' || (unsigned char)(c - 0x20) <= 0x5e; }

/* Whether every byte is printable ASCII or a newline. Blocks of 64 bytes
 * are judged whole, without a branch per byte, so that the compiler can
 * take 16 at a time: byte by byte, this took a sixteenth of the reading. */
static bool all_plain(const char *s, size_t len)
{
    size_t i = 0;
    for (; i + 64 <= len; i += 64) {
        unsigned bad = 0;
        for (int k = 0; k < 64; k++)
            bad |= !plain_byte((unsigned char)s[i + k]);
        if (bad)
            return false;
    }
    for (; i < len; i++)
        if (!plain_byte((unsigned char)s[i]))
            return false;
    return true;
}

static bool stream(reader *r)
{
    if (!all_plain(r->s, r->len))
        return decline(r);
    if (!event(r, YAML_STREAM_START_EVENT, mark(r)))
        return false;
    long col = next_content(r);
    if (col < -1)
        return false;
    if (col >= 0) {
        long next;
        if (!event(r, YAML_DOCUMENT_START_EVENT, mark(r)) || !block_node(r, -1, &next))
            return false;
        if (next != -1)
            return decline(r);
        if (!event(r, YAML_DOCUMENT_END_EVENT, mark(r)))
            return false;
    }
    return event(r, YAML_STREAM_END_EVENT, mark(r));
}

yfast_result yfast_read(const char *text, size_t len, yfast_emit emit, void *ctx)
{
    reader r = {.s = text, .len = len, .emit = emit, .ctx = ctx, .stop = YFAST_DONE};
    if (!stream(&r) && r.stop == YFAST_DONE)
        r.stop = YFAST_DECLINED; /* (every failure says why; this is a guard) */
    return r.stop;
}

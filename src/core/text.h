/* text: strings made safe to show. Messages name files and quote values
 * from untrusted input, and must stay on one line: control bytes are shown
 * as \xNN. */
#ifndef GLINT_CORE_TEXT_H
#define GLINT_CORE_TEXT_H

#include <stddef.h>
#include <stdint.h>

/* Writes the first len bytes of text into buf (cap bytes, always
 * terminated when cap > 0) with control bytes (below 0x20, and 0x7f) as
 * \xNN. After max input bytes it writes "..." and stops; output that does
 * not fit is cut at a whole character. Returns the bytes written. */
size_t text_escape(const char *text, size_t len, size_t max, char *buf, size_t cap);

/* Room text_escape needs for all of len bytes: 4 per byte, and the margin
 * it keeps for the widest character plus the terminator. */
static inline size_t text_escape_room(size_t len) { return len * 4 + 6; }

/* Line and column (1-based, the column in UTF-8 characters) of byte offset
 * in text (len bytes). */
void text_position(const char *text, size_t len, size_t offset, uint32_t *line, uint32_t *col);

/* The column (from 1) of the first tab in the indentation of the line
 * holding byte at, or 0 when it has none. */
uint32_t text_indent_tab(const char *text, size_t len, size_t at);

#endif

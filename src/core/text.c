#include "text.h"

#include <stdio.h>
#include <string.h>

size_t text_escape(const char *text, size_t len, size_t max, char *buf, size_t cap)
{
    if (cap == 0)
        return 0;
    size_t o = 0;
    for (size_t i = 0; i < len && o + 5 < cap; i++) {
        if (i == max) {
            if (o + 4 < cap) {
                memcpy(buf + o, "...", 3);
                o += 3;
            }
            break;
        }
        unsigned char c = (unsigned char)text[i];
        if (c < 0x20 || c == 0x7f)
            o += (size_t)snprintf(buf + o, cap - o, "\\x%02X", c);
        else
            buf[o++] = (char)c;
    }
    if (o >= cap)
        o = cap - 1;
    buf[o] = '\0';
    return o;
}

void text_position(const char *text, size_t len, size_t offset, uint32_t *line, uint32_t *col)
{
    uint32_t l = 1, c = 1;
    for (size_t i = 0; i < offset && i < len; i++) {
        unsigned char ch = (unsigned char)text[i];
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

uint32_t text_indent_tab(const char *text, size_t len, size_t at)
{
    if (at > len)
        return 0;
    size_t start = at;
    while (start > 0 && text[start - 1] != '\n' && text[start - 1] != '\r')
        start--;
    for (size_t i = start; i < len && (text[i] == ' ' || text[i] == '\t'); i++)
        if (text[i] == '\t')
            return (uint32_t)(i - start + 1);
    return 0;
}

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

/* bytelist: an encoded file as pieces (codec.h). */
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "core/array.h"

static bool add_piece(bytelist *l, bytepiece p)
{
    if (l->n > 0) { /* joined to the last piece where it follows on */
        bytepiece *last = &l->pieces[l->n - 1];
        if (last->from == p.from && last->at + last->n == p.at) {
            last->n += p.n;
            return true;
        }
    }
    int i = array_push((void **)&l->pieces, &l->n, &l->cap, sizeof *l->pieces);
    if (i < 0)
        return false;
    l->pieces[i] = p;
    return true;
}

bool bytelist_own(bytelist *l, const void *data, size_t n)
{
    size_t at = l->own.len;
    return n == 0 || (bytes_append(&l->own, data, n) && add_piece(l, (bytepiece){NULL, at, n}));
}

bool bytelist_ref(bytelist *l, const void *p, size_t n)
{
    /* pieces elsewhere are told apart by their start: at is 0 */
    if (n == 0)
        return true;
    if (l->n > 0) {
        bytepiece *last = &l->pieces[l->n - 1];
        if (last->from && last->from + last->n == (const uint8_t *)p) {
            last->n += n;
            return true;
        }
    }
    return add_piece(l, (bytepiece){p, 0, n});
}

bool bytelist_hold(bytelist *l, void *block)
{
    int i = array_push((void **)&l->held, &l->nheld, &l->cap_held, sizeof *l->held);
    if (i < 0) {
        free(block);
        return false;
    }
    l->held[i] = block;
    return true;
}

bool bytelist_of(bytelist *l, bytebuf *b)
{
    bytelist_free(l);
    l->own = *b;
    *b = (bytebuf){0};
    l->n = 0;
    return l->own.len == 0 || add_piece(l, (bytepiece){NULL, 0, l->own.len});
}

size_t bytelist_len(const bytelist *l)
{
    size_t n = 0;
    for (int i = 0; i < l->n; i++)
        n += l->pieces[i].n;
    return n;
}

const uint8_t *bytelist_at(const bytelist *l, int i)
{
    const bytepiece *p = &l->pieces[i];
    return p->from ? p->from : l->own.data + p->at;
}

bool bytelist_flatten(const bytelist *l, bytebuf *out)
{
    if (l->n == 0)
        return true;
    uint8_t *d = bytes_grow(out, bytelist_len(l));
    if (!d)
        return false;
    for (int i = 0; i < l->n; i++) {
        memcpy(d, bytelist_at(l, i), l->pieces[i].n);
        d += l->pieces[i].n;
    }
    return true;
}

void bytelist_free(bytelist *l)
{
    bytes_free(&l->own);
    for (int i = 0; i < l->nheld; i++)
        free(l->held[i]);
    free(l->held);
    free(l->pieces);
    *l = (bytelist){0};
}

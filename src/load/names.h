/* names: a table from strings to int values, for the names a scene file
 * gives to materials and textures, YAML anchors and loaded files. Keys are
 * byte strings with a length (they may hold NUL bytes) and are copied in.
 * Lookups are hashed (FNV-1a, open addressing with linear probing), so
 * files with many names load in linear time.
 *
 * Also home to the "did you mean" suggestions that error messages offer:
 * the nearest candidate by Levenshtein distance (ASCII case ignored), if it
 * is close enough. */
#ifndef GLINT_LOAD_NAMES_H
#define GLINT_LOAD_NAMES_H

#include <stdbool.h>
#include <stddef.h>

/* Suggestions are offered up to this edit distance, and only for words of
 * NAMES_SUGGEST_LONG characters or more; a shorter word gets one edit, so
 * a suggestion is a likely typo, not another word ('type' is not 'eye').
 * A swap of two neighbouring letters counts as one edit ('bleu', 'blue'). */
#define NAMES_SUGGEST_DISTANCE 2
#define NAMES_SUGGEST_LONG 5

typedef struct names_slot {
    char *key; /* NULL: empty slot */
    size_t len;
    int value;
} names_slot;

typedef struct names {
    names_slot *slots;
    size_t cap, count; /* cap is zero or a power of two */
} names;

/* The value stored for key, or -1 when absent. */
int names_find(const names *t, const char *key, size_t len);
/* Sets key to value, adding it when absent; false when out of memory. */
bool names_put(names *t, const char *key, size_t len, int value);
void names_free(names *t);

/* The key of t nearest to word within the edits above, or
 * NULL. Ties go to the key that sorts first, so answers do not depend on
 * the table's layout. */
const char *names_suggest(const names *t, const char *word, size_t len);
/* The same over a NULL-terminated list; ties go to the earlier entry. */
const char *names_suggest_list(const char *const *list, const char *word, size_t len);

#endif

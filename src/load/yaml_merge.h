/* yaml_merge: the pairs a mapping of the tree (yaml_doc.h) holds: its own
 * pairs in the order written, then those of the mappings its merge keys
 * (<<) name that it does not already have, earlier merged mappings winning
 * over later ones (YAML 1.1 merge key type,
 * https://yaml.org/type/merge.html). A key written twice in the mapping
 * itself is refused, and so is a key that is a collection. */
#ifndef GLINT_LOAD_YAML_MERGE_H
#define GLINT_LOAD_YAML_MERGE_H

#include <stddef.h>
#include <stdint.h>
#include "glint.h"
#include "load/yaml_doc.h"

struct ymerge_pair;

/* Scratch memory kept from one mapping to the next. */
typedef struct ymerge {
    struct ymerge_pair *pairs;
    size_t cap_pairs;
    uint32_t *ids; /* the merged mappings, then the key, value list */
    size_t cap_ids;
} ymerge;

/* *kids holds the ids of the mapping's key, value, key, value... as read
 * (*n of them); on success it points to the mapping's pairs as such a list
 * (into m, or the same list when it stands as read) and *n is the number
 * of pairs. Errors name the file name with the line and column. */
glint_rc ymerge_pairs(ymerge *m, const ydoc *d, const char *name, glint_error *err,
                      const uint32_t **kids, size_t *n);
void ymerge_free(ymerge *m);

#endif

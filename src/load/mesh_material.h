/* mesh_material: a model file's materials as assimp read them, into
 * mesh_data's plain form (inside the importer, mesh_assimp.c).
 *
 * Colour: the diffuse colour (glTF's base colour); with a diffuse texture the
 * texture is the colour (times the base colour factor in glTF, as its
 * specification says). Specular colour and shininess as given.
 *
 * Opacity, 1 opaque to 0 invisible, by each format's convention:
 *  - glTF: the base colour's alpha counts only in alphaMode BLEND; OPAQUE
 *    and MASK surfaces are opaque.
 *  - Collada: opacity is transparency times the alpha of <transparent>
 *    (A_ONE, the specification's default). Many exporters (3ds Max's among
 *    them) wrote the opposite, transparency 0 for an opaque surface: a file
 *    in which some material comes out wholly invisible is read with that
 *    convention throughout (opacity = 1 - transparency).
 *  - Everything else: the opacity assimp reports (OBJ's d, 3DS's and FBX's
 *    transparency turned around), except that a material nobody could see
 *    (opacity 0) is taken as an exporter's inverted convention and is opaque.
 *
 * Files without materials, or with only assimp's stand-in material
 * ("DefaultMaterial"; any in PLY, OFF and STL, which have none), are matte
 * white like the scene format's default. */
#ifndef GLINT_LOAD_MESH_MATERIAL_H
#define GLINT_LOAD_MESH_MATERIAL_H

#include "glint.h"
#include "load/mesh_data.h"

struct aiScene;

/* Fills md->mats, md->nmats, md->texs and md->ntexs from sc; name (the
 * model's) chooses the format's conventions by its extension. */
glint_rc mesh_material_gather(const struct aiScene *sc, const char *name, mesh_data *md,
                              glint_error *err);

#endif

/* assimp_load: assimp opened the first time a mesh is imported, not linked
 * into glint. A render without meshes never loads it and the libraries
 * behind it (the C++ runtime, draco, minizip), whose loading and static
 * initialisers took 2-3 ms at every start. mesh_assimp.c and
 * mesh_material.c call assimp's functions by their own names through the
 * table below (the macros at the end). */
#ifndef GLINT_LOAD_ASSIMP_LOAD_H
#define GLINT_LOAD_ASSIMP_LOAD_H

#include <stdbool.h>

#include <assimp/cimport.h>
#include <assimp/material.h>

#define ASSIMP_LOAD_FUNCTIONS(X)                                                               \
    X(aiCreatePropertyStore) X(aiReleasePropertyStore) X(aiImportFileFromMemoryWithProperties) \
    X(aiImportFileExWithProperties) X(aiGetErrorString) X(aiReleaseImport)                     \
    X(aiGetMaterialColor) X(aiGetMaterialFloatArray) X(aiGetMaterialString)                    \
    X(aiGetMaterialTexture) X(aiIdentityMatrix4)

typedef struct assimp_table {
#define ASSIMP_LOAD_FIELD(name) __typeof__(name) *name;
    ASSIMP_LOAD_FUNCTIONS(ASSIMP_LOAD_FIELD)
#undef ASSIMP_LOAD_FIELD
} assimp_table;

extern assimp_table assimp_fn;

/* Opens the library and finds every function (once; later calls return
 * the first answer). False with *why set when it cannot: the library's
 * own words (missing file, missing symbol). */
bool assimp_load(const char **why);

#if !defined(GLINT_ASSIMP_LOAD_NO_CALLS)
#define aiCreatePropertyStore (assimp_fn.aiCreatePropertyStore)
#define aiReleasePropertyStore (assimp_fn.aiReleasePropertyStore)
#define aiImportFileFromMemoryWithProperties (assimp_fn.aiImportFileFromMemoryWithProperties)
#define aiImportFileExWithProperties (assimp_fn.aiImportFileExWithProperties)
#define aiGetErrorString (assimp_fn.aiGetErrorString)
#define aiReleaseImport (assimp_fn.aiReleaseImport)
#define aiGetMaterialColor (assimp_fn.aiGetMaterialColor)
#define aiGetMaterialFloatArray (assimp_fn.aiGetMaterialFloatArray)
#define aiGetMaterialString (assimp_fn.aiGetMaterialString)
#define aiGetMaterialTexture (assimp_fn.aiGetMaterialTexture)
#define aiIdentityMatrix4 (assimp_fn.aiIdentityMatrix4)
#endif

#endif

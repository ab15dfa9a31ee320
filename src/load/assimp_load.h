/* assimp_load: assimp opened the first time a mesh is imported
 * (core/dynlib.h), not linked into glint. A render without meshes never
 * loads it and the libraries behind it (the C++ runtime, draco, minizip),
 * whose loading and static initialisers took 2-3 ms at every start.
 * mesh_assimp.c and mesh_material.c call assimp's functions by their own
 * names through the table below (the macros at the end). */
#ifndef GLINT_LOAD_ASSIMP_LOAD_H
#define GLINT_LOAD_ASSIMP_LOAD_H

#include <stdbool.h>

#include <assimp/cimport.h>
#include <assimp/material.h>

#include "core/dynlib.h"

#define ASSIMP_FUNCTIONS(X, t)                                                                 \
    X(t, aiCreatePropertyStore) X(t, aiReleasePropertyStore)                                   \
    X(t, aiImportFileFromMemoryWithProperties) X(t, aiImportFileExWithProperties)              \
    X(t, aiGetErrorString) X(t, aiReleaseImport) X(t, aiGetMaterialColor)                      \
    X(t, aiGetMaterialFloatArray) X(t, aiGetMaterialString) X(t, aiGetMaterialTexture)         \
    X(t, aiIdentityMatrix4)

typedef DYNLIB_STRUCT(ASSIMP_FUNCTIONS) assimp_table;

extern assimp_table assimp_fn;
extern dynlib assimp_lib;

/* Opens the library and finds every function (once; later calls return
 * the first answer). False with *why set when it cannot: the library's
 * own words (missing file, missing symbol). */
static inline bool assimp_load(const char **why) { return dynlib_open(&assimp_lib, why); }

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

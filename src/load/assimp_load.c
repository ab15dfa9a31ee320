#define GLINT_ASSIMP_LOAD_NO_CALLS
#include "assimp_load.h"

assimp_table assimp_fn;
dynlib assimp_lib = DYNLIB(GLINT_SONAME_ASSIMP, ASSIMP_FUNCTIONS, assimp_fn);

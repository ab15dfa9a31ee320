#define GLINT_ASSIMP_LOAD_NO_CALLS
#include "assimp_load.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stddef.h>

/* assimp's run-time library, as Debian names it (libassimp5). */
#define ASSIMP_LIBRARY "libassimp.so.5"

assimp_table assimp_fn;

static pthread_once_t once = PTHREAD_ONCE_INIT;
static const char *failure; /* NULL once everything is found */

/* dlerror's words, or these when it has none. */
static const char *why_not(const char *fallback)
{
    const char *e = dlerror();
    return e ? e : fallback;
}

static void load(void)
{
    void *lib = dlopen(ASSIMP_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        failure = why_not("cannot open " ASSIMP_LIBRARY);
        return;
    }
    /* dlsym's object pointer stored through a void * view of each
     * function pointer, as POSIX describes for dlsym. The library stays
     * open until the process ends. */
#define ASSIMP_LOAD_FIND(name)                                                                 \
    if (!failure && !(*(void **)&assimp_fn.name = dlsym(lib, #name)))                          \
        failure = why_not(ASSIMP_LIBRARY " has no " #name);
    ASSIMP_LOAD_FUNCTIONS(ASSIMP_LOAD_FIND)
#undef ASSIMP_LOAD_FIND
}

bool assimp_load(const char **why)
{
    pthread_once(&once, load);
    if (failure && why)
        *why = failure;
    return !failure;
}

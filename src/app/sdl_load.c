#define GLINT_SDL_LOAD_NO_CALLS
#include "sdl_load.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stddef.h>
#include <stdio.h>

/* SDL2's run-time library, as Debian and most systems name it. */
#define SDL_LIBRARY "libSDL2-2.0.so.0"

sdl_table sdl_fn;

static pthread_once_t once = PTHREAD_ONCE_INIT;
static const char *failure; /* NULL once everything is found */
static char failure_text[256];

/* dlerror's words, or these when it has none; copied, as dlerror's text
 * is its thread's and goes at its next call or when the thread ends. */
static const char *why_not(const char *fallback)
{
    const char *e = dlerror();
    snprintf(failure_text, sizeof failure_text, "%s", e ? e : fallback);
    return failure_text;
}

static void load(void)
{
    void *lib = dlopen(SDL_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        failure = why_not("cannot open " SDL_LIBRARY);
        return;
    }
    /* dlsym's object pointer stored through a void * view of each
     * function pointer, as POSIX describes for dlsym. The library stays
     * open until the process ends. */
#define SDL_LOAD_FIND(name)                                                                    \
    if (!failure && !(*(void **)&sdl_fn.name = dlsym(lib, #name)))                             \
        failure = why_not(SDL_LIBRARY " has no " #name);
    SDL_LOAD_FUNCTIONS(SDL_LOAD_FIND)
#undef SDL_LOAD_FIND
}

bool sdl_load(const char **why)
{
    pthread_once(&once, load);
    if (failure && why)
        *why = failure;
    return !failure;
}

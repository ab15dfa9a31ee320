#include "dynlib.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

/* dlsym's object pointer is copied into a function pointer of the table,
 * as POSIX allows where the two are the same size. */
_Static_assert(sizeof(void *) == sizeof(void (*)(void)), "function and object pointers differ");

enum { UNTRIED, OPEN, FAILED };

/* One lock for every library: a first use waits for another's (dlopen
 * takes the loader's own lock anyway). */
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

/* dlerror's words, copied (its text is the calling thread's, and is freed
 * at its next call or when the thread ends); words of ours should it have
 * none: the function missing, or (NULL) the library. */
static void keep_why(dynlib *lib, const char *missing)
{
    const char *e = dlerror();
    if (e)
        snprintf(lib->why, sizeof lib->why, "%s", e);
    else if (missing)
        snprintf(lib->why, sizeof lib->why, "%s: no function %s", lib->soname, missing);
    else
        snprintf(lib->why, sizeof lib->why, "%s: cannot be opened", lib->soname);
}

static bool load(dynlib *lib)
{
    dlerror(); /* a message left by an earlier call is not this one's */
    lib->handle = dlopen(lib->soname, RTLD_NOW | RTLD_LOCAL);
    if (!lib->handle) {
        keep_why(lib, NULL);
        return false;
    }
    for (const dynlib_symbol *s = lib->symbols; s->name; s++) {
        void *f = dlsym(lib->handle, s->name);
        if (!f) {
            keep_why(lib, s->name);
            dlclose(lib->handle);
            lib->handle = NULL;
            return false;
        }
        memcpy(s->slot, &f, sizeof f);
    }
    return true; /* open until the process ends */
}

bool dynlib_open(dynlib *lib, const char **why)
{
    int state = atomic_load_explicit(&lib->state, memory_order_acquire);
    if (state == UNTRIED) {
        pthread_mutex_lock(&lock);
        state = atomic_load_explicit(&lib->state, memory_order_relaxed);
        if (state == UNTRIED) {
            state = load(lib) ? OPEN : FAILED;
            atomic_store_explicit(&lib->state, state, memory_order_release);
        }
        pthread_mutex_unlock(&lock);
    }
    if (state != OPEN && why)
        *why = lib->why;
    return state == OPEN;
}

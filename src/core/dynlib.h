/* dynlib: a shared library opened when it is first needed instead of
 * linked, so that a process that never needs it never maps it. The
 * dynamic loader maps every library a program is linked to before main,
 * and most renders use none of the image codecs beyond libdeflate's PNG
 * (libjpeg, OpenEXR, stb_image, libspng, ISA-L: about 1.5 ms of every
 * start) or assimp (the C++ runtime behind it: 2-3 ms).
 *
 * The code that uses such a library is compiled against its headers (its
 * types, constants and macros) and calls its functions by their own names
 * through a table of pointers, one table per library:
 *
 *     #define JPEG_FUNCTIONS(X, t) X(t, jpeg_std_error) X(t, jpeg_CreateDecompress)
 *     static DYNLIB_STRUCT(JPEG_FUNCTIONS) jpeg_fn;
 *     static dynlib jpeg_lib = DYNLIB(GLINT_SONAME_JPEG, JPEG_FUNCTIONS, jpeg_fn);
 *     #define jpeg_std_error (jpeg_fn.jpeg_std_error)
 *     #define jpeg_CreateDecompress (jpeg_fn.jpeg_CreateDecompress)
 *
 * (the table first, the names made into macros after it; the Makefile
 * gives each library's soname, GLINT_SONAME_JPEG "libjpeg.so.62", read
 * from the library glint is built against), and before the first call, on
 * every path that reaches one:
 *
 *     const char *why;
 *     if (!dynlib_open(&jpeg_lib, &why))
 *         return err_set(err, ..., "%s: cannot read JPEG files (%s)", name, why);
 *
 * A function the code calls but the table lacks is an undefined reference
 * when the program is linked, as the library is not. */
#ifndef GLINT_CORE_DYNLIB_H
#define GLINT_CORE_DYNLIB_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>

/* A function to find: its name, and the table's pointer it goes into. */
typedef struct dynlib_symbol {
    const char *name;
    void *slot;
} dynlib_symbol;

typedef struct dynlib {
    const char *soname;           /* as the dynamic loader looks it up */
    const dynlib_symbol *symbols; /* ended by one with no name */
    /* dynlib_open's: whether it was tried, and how it went */
    atomic_int state;
    void *handle;
    char why[256];
} dynlib;

/* The table of a library's functions, as a struct type: a pointer for
 * each name FUNCTIONS gives (FUNCTIONS(X, t) is X(t, name) for each). */
#define DYNLIB_STRUCT(FUNCTIONS) struct { FUNCTIONS(DYNLIB_FIELD_, ~) }
/* A dynlib's initial value: soname, and the functions of the table fn. */
#define DYNLIB(soname, FUNCTIONS, fn)                                                          \
    {(soname), (const dynlib_symbol[]){FUNCTIONS(DYNLIB_SYMBOL_, fn){NULL, NULL}}, 0, NULL, ""}
#define DYNLIB_FIELD_(t, name) __typeof__(name) *name;
#define DYNLIB_SYMBOL_(t, name) {#name, (void *)&(t).name},

/* Opens the library and finds every function of its table, once; later
 * calls, from any thread, return the first answer (after a true one the
 * table is filled, and stays so until the process ends). False with *why
 * set when it cannot: dlerror's words, which name the library (cannot
 * open it; a function it lacks). Thread-safe. */
bool dynlib_open(dynlib *lib, const char **why);

#endif

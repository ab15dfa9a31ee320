/* sdl_load: SDL2 opened when the preview window opens, not linked into
 * glint. A batch render never loads it and the sixty libraries behind it
 * (sound, X11, Wayland, D-Bus), which took about 4 ms at every start, and
 * glint renders on machines where SDL2 is not installed. preview.c, the
 * one user, calls SDL's functions by their own names through the table
 * below (the macros at the end). */
#ifndef GLINT_APP_SDL_LOAD_H
#define GLINT_APP_SDL_LOAD_H

#include <SDL.h>
#include <stdbool.h>

#define SDL_LOAD_FUNCTIONS(X)                                                                  \
    X(SDL_Init) X(SDL_Quit) X(SDL_GetError) X(SDL_SetHint) X(SDL_GetDisplayUsableBounds)       \
    X(SDL_CreateWindow) X(SDL_CreateRenderer) X(SDL_CreateTexture) X(SDL_DestroyTexture)       \
    X(SDL_DestroyRenderer) X(SDL_DestroyWindow) X(SDL_UpdateTexture) X(SDL_SetWindowTitle)     \
    X(SDL_RenderClear) X(SDL_RenderCopy) X(SDL_RenderPresent) X(SDL_PollEvent)                 \
    X(SDL_WaitEventTimeout) X(SDL_Delay)

typedef struct sdl_table {
#define SDL_LOAD_FIELD(name) __typeof__(name) *name;
    SDL_LOAD_FUNCTIONS(SDL_LOAD_FIELD)
#undef SDL_LOAD_FIELD
} sdl_table;

extern sdl_table sdl_fn;

/* Opens the library and finds every function (once; later calls return
 * the first answer). False with *why set when it cannot: the library's
 * own words (missing file, missing symbol). */
bool sdl_load(const char **why);

#if !defined(GLINT_SDL_LOAD_NO_CALLS)
#define SDL_LOAD_CALL(name) (sdl_fn.name)
#define SDL_Init SDL_LOAD_CALL(SDL_Init)
#define SDL_Quit SDL_LOAD_CALL(SDL_Quit)
#define SDL_GetError SDL_LOAD_CALL(SDL_GetError)
#define SDL_SetHint SDL_LOAD_CALL(SDL_SetHint)
#define SDL_GetDisplayUsableBounds SDL_LOAD_CALL(SDL_GetDisplayUsableBounds)
#define SDL_CreateWindow SDL_LOAD_CALL(SDL_CreateWindow)
#define SDL_CreateRenderer SDL_LOAD_CALL(SDL_CreateRenderer)
#define SDL_CreateTexture SDL_LOAD_CALL(SDL_CreateTexture)
#define SDL_DestroyTexture SDL_LOAD_CALL(SDL_DestroyTexture)
#define SDL_DestroyRenderer SDL_LOAD_CALL(SDL_DestroyRenderer)
#define SDL_DestroyWindow SDL_LOAD_CALL(SDL_DestroyWindow)
#define SDL_UpdateTexture SDL_LOAD_CALL(SDL_UpdateTexture)
#define SDL_SetWindowTitle SDL_LOAD_CALL(SDL_SetWindowTitle)
#define SDL_RenderClear SDL_LOAD_CALL(SDL_RenderClear)
#define SDL_RenderCopy SDL_LOAD_CALL(SDL_RenderCopy)
#define SDL_RenderPresent SDL_LOAD_CALL(SDL_RenderPresent)
#define SDL_PollEvent SDL_LOAD_CALL(SDL_PollEvent)
#define SDL_WaitEventTimeout SDL_LOAD_CALL(SDL_WaitEventTimeout)
#define SDL_Delay SDL_LOAD_CALL(SDL_Delay)
#endif

#endif

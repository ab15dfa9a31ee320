/* The point-light kernels of light8.h for the avx2 path (accel/isa.h); the
 * Makefile compiles this file with the avx2 flags. */
#include "accel/isa.h"
#include "trace/light8_api.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
#include "trace/light8.h"
LIGHT8_KERNELS(avx2)
#else
typedef int lighting_avx2_unused; /* not x86-64: no kernels here */
#endif

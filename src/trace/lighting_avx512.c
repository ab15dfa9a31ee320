/* The point-light kernels of light8.h for the avx512 path (accel/isa.h); the
 * Makefile compiles this file with the avx512 flags. */
#include "accel/isa.h"
#include "trace/light8_api.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX512VL__)
#error "compile with the avx512 flags (Makefile: KERNEL_FLAGS_avx512)"
#endif
#include "trace/light8.h"
LIGHT8_KERNELS(avx512)
#else
typedef int lighting_avx512_unused; /* not x86-64: no kernels here */
#endif

/* The secondary-ray kernels of bounce8.h for the avx512 path (accel/isa.h);
 * the Makefile compiles this file with the avx512 flags. */
#include "accel/isa.h"
#include "trace/bounce8_api.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX512VL__)
#error "compile with the avx512 flags (Makefile: KERNEL_FLAGS_avx512)"
#endif
#include "trace/bounce8.h"
BOUNCE8_KERNELS(avx512)
#else
typedef int whitted_avx512_unused; /* not x86-64: no kernels here */
#endif

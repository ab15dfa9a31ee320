/* The secondary-ray kernels of bounce8.h for the avx2 path (accel/isa.h);
 * the Makefile compiles this file with the avx2 flags. */
#include "accel/isa.h"
#include "trace/bounce8_api.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
#include "trace/bounce8.h"
BOUNCE8_KERNELS(avx2)
#else
typedef int whitted_avx2_unused; /* not x86-64: no kernels here */
#endif

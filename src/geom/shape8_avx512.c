/* The packet shape tests of shape8.h and csg8.h for the avx512 path (accel/isa.h); the
 * Makefile compiles this file with the avx512 flags. */
#include "accel/isa.h"
#include "geom/shape.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX512VL__)
#error "compile with the avx512 flags (Makefile: KERNEL_FLAGS_avx512)"
#endif
#include "geom/csg8.h"
#include "geom/shape8.h"
SHAPE8_KERNELS(avx512)
CSG8_KERNELS(avx512)
#else
typedef int shape8_avx512_unused; /* not x86-64: no kernels here */
#endif

/* The packet shape tests of shape8.h and csg8.h for the avx2 path (accel/isa.h); the
 * Makefile compiles this file with the avx2 flags. */
#include "accel/isa.h"
#include "geom/shape.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
#include "geom/csg8.h"
#include "geom/shape8.h"
SHAPE8_KERNELS(avx2)
CSG8_KERNELS(avx2)
#else
typedef int shape8_avx2_unused; /* not x86-64: no kernels here */
#endif

/* The mesh kernels of mesh_trace.h for the avx512 path (accel/isa.h); the
 * Makefile compiles this file with the avx512 flags. */
#include "mesh_trace.h"
#if defined(GLINT_WIDE_KERNELS)
#include "mesh_packet.h"
#endif

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX512VL__)
#error "compile with the avx512 flags (Makefile: KERNEL_FLAGS_avx512)"
#endif
MESH_KERNELS(avx512, 8)
MESH_PACKET_KERNELS(avx512)
#else
typedef int mesh_avx512_unused; /* not x86-64: no kernels here */
#endif

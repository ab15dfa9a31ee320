/* The mesh kernels of mesh_trace.h for the avx2 path (accel/isa.h); the
 * Makefile compiles this file with the avx2 flags. */
#include "mesh_trace.h"
#if defined(GLINT_WIDE_KERNELS)
#include "mesh_packet.h"
#endif

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
MESH_KERNELS(avx2, 8)
MESH_PACKET_KERNELS(avx2)
#else
typedef int mesh_avx2_unused; /* not x86-64: no kernels here */
#endif

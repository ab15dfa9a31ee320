/* The scene kernels of scene_trace.h, scene_packet8.h and camera8.h for
 * the avx2 path (accel/isa.h); the Makefile compiles this file with the
 * avx2 flags. */
#include "camera8.h"
#include "scene_packet8.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX2__)
#error "compile with the avx2 flags (Makefile: KERNEL_FLAGS_avx2)"
#endif
SCENE_KERNELS(avx2, 8)
SCENE_PACKET_KERNELS(avx2)
CAMERA8_KERNELS(avx2)
#else
typedef int scene_avx2_unused; /* not x86-64: no kernels here */
#endif

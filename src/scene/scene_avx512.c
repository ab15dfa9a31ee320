/* The scene kernels of scene_trace.h, scene_packet8.h and camera8.h for
 * the avx512 path (accel/isa.h); the Makefile compiles this file with the
 * avx512 flags. */
#include "camera8.h"
#include "scene_packet8.h"

#if defined(GLINT_WIDE_KERNELS)
#if !defined(__AVX512VL__)
#error "compile with the avx512 flags (Makefile: KERNEL_FLAGS_avx512)"
#endif
SCENE_KERNELS(avx512, 8)
SCENE_PACKET_KERNELS(avx512)
CAMERA8_KERNELS(avx512)
#else
typedef int scene_avx512_unused; /* not x86-64: no kernels here */
#endif

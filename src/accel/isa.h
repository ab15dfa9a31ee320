/* isa: which SIMD kernels traverse the BVHs, chosen once per process from
 * what the CPU can run (Intel's CPUID flags, through GCC's
 * __builtin_cpu_supports, which also checks that the OS saves the wider
 * registers), or forced with the environment variable GLINT_SIMD:
 *
 *   avx512  eight-wide nodes, AVX-512 (F + VL) box tests     x86-64 with avx512f, avx512vl
 *   avx2    eight-wide nodes, AVX2 box tests                 x86-64 with avx2
 *   sse     four-wide nodes, SSE box tests                   every x86-64
 *   scalar  four-wide nodes, plain C                         everywhere
 *
 * A forced path the CPU cannot run falls back to the best one below it;
 * an unknown name, or "auto", means the best the CPU has. Every path
 * computes the same hits with the same arithmetic, so images are
 * byte-identical whichever runs (tests/test_simd.c renders the gallery
 * with each). A BVH is laid out for the path active when it is built and
 * remembers which that was, so switching paths takes a rebuild. */
#ifndef GLINT_ACCEL_ISA_H
#define GLINT_ACCEL_ISA_H

#include <stdbool.h>

/* The eight-wide kernels are compiled in on x86-64 only. */
#if defined(__x86_64__) && !defined(GLINT_NO_WIDE_KERNELS)
#define GLINT_WIDE_KERNELS 1
#endif

typedef enum accel_isa {
    ACCEL_SCALAR,
    ACCEL_SSE,
    ACCEL_AVX2,
    ACCEL_AVX512,
    ACCEL_AUTO, /* for accel_isa_force: back to GLINT_SIMD or the CPU's best */
} accel_isa;

/* The best path this CPU runs. */
accel_isa accel_isa_best(void);
/* The path in use: GLINT_SIMD (read once) or accel_isa_best(). */
accel_isa accel_isa_active(void);
/* Makes isa the active path for BVHs built from now on (tests, benchmarks);
 * returns the path actually set, which is lower when the CPU lacks isa. */
accel_isa accel_isa_force(accel_isa isa);
/* "scalar", "sse", "avx2", "avx512"; and back (false when unknown). */
const char *accel_isa_name(accel_isa isa);
bool accel_isa_parse(const char *name, accel_isa *out);
/* Children per node on that path: 4 or 8. */
int accel_isa_width(accel_isa isa);

#endif

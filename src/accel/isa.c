#include "isa.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static const char *const names[] = {"scalar", "sse", "avx2", "avx512"};

/* -1 until first asked. */
static atomic_int active = -1;

accel_isa accel_isa_best(void)
{
#if defined(GLINT_WIDE_KERNELS)
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl"))
        return ACCEL_AVX512;
    if (__builtin_cpu_supports("avx2"))
        return ACCEL_AVX2;
    return ACCEL_SSE;
#elif defined(__SSE2__)
    return ACCEL_SSE;
#else
    return ACCEL_SCALAR;
#endif
}

const char *accel_isa_name(accel_isa isa)
{
    return isa >= ACCEL_SCALAR && isa <= ACCEL_AVX512 ? names[isa] : "auto";
}

bool accel_isa_parse(const char *name, accel_isa *out)
{
    for (int i = ACCEL_SCALAR; i <= ACCEL_AVX512; i++)
        if (strcmp(name, names[i]) == 0) {
            *out = (accel_isa)i;
            return true;
        }
    if (strcmp(name, "auto") == 0) {
        *out = ACCEL_AUTO;
        return true;
    }
    return false;
}

int accel_isa_width(accel_isa isa)
{
    return isa == ACCEL_AVX2 || isa == ACCEL_AVX512 ? 8 : 4;
}

accel_isa accel_isa_force(accel_isa isa)
{
    accel_isa best = accel_isa_best();
    if (isa == ACCEL_AUTO) {
        const char *env = getenv("GLINT_SIMD");
        if (!env || !accel_isa_parse(env, &isa))
            isa = ACCEL_AUTO;
    }
    if (isa == ACCEL_AUTO || isa > best)
        isa = best;
    atomic_store(&active, (int)isa);
    return isa;
}

accel_isa accel_isa_active(void)
{
    int a = atomic_load(&active);
    return a >= 0 ? (accel_isa)a : accel_isa_force(ACCEL_AUTO);
}

/* The scene kernels of scene_trace.h for the scalar path (accel/isa.h). */
#define GLINT_NO_SIMD 1
#include "scene_trace.h"

SCENE_KERNELS(scalar, 4)

/* The mesh kernels of mesh_trace.h for the scalar path (accel/isa.h). */
#define GLINT_NO_SIMD 1
#include "mesh_trace.h"

MESH_KERNELS(scalar, 4)

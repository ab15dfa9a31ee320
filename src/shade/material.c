#include "material.h"

material material_default(void)
{
    return (material){
        .color = {1.0f, 1.0f, 1.0f},
        .texture = -1,
        .ambient = 1.0f,
        .diffuse = 1.0f,
        .specular = 0.0f,
        .shininess = 50.0f,
        .reflect = 0.0f,
        .transmit = 0.0f,
        .ior = 1.0f,
        .tint = {1.0f, 1.0f, 1.0f},
        .absorption = {0.0f, 0.0f, 0.0f},
        .emission = {0.0f, 0.0f, 0.0f},
        .fresnel = true,
        .bump = -1,
        .bump_strength = 0.0f,
    };
}

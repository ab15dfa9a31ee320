/* camera: a pinhole camera given by eye, target, up and horizontal field of
 * view. Pixels are square, so the vertical field follows from the image's
 * aspect ratio. A camera_frame is the camera prepared for one image size. */
#ifndef GLINT_SCENE_CAMERA_H
#define GLINT_SCENE_CAMERA_H

#include "core/ray.h"

typedef struct camera {
    vec3 eye, target, up;
    float hfov; /* degrees, in (0, 180) */
} camera;

typedef struct camera_frame {
    vec3 eye;
    vec3 corner;     /* direction to the top-left corner of the image window */
    vec3 dx, dy;     /* one pixel right, one pixel down */
} camera_frame;

camera_frame camera_frame_make(const camera *cam, int width, int height);

/* Primary ray through image position (x, y) in pixels from the top-left
 * corner (pixel i spans [i, i+1)). The direction is not normalised. */
static inline ray camera_ray(const camera_frame *f, float x, float y)
{
    vec3 d = v3_madd(v3_madd(f->corner, f->dx, x), f->dy, y);
    return ray_make(f->eye, d, INFINITY);
}

#endif

/* camera: where primary rays come from. Four projections — perspective
 * (a pinhole, or a thin lens), orthographic, equirectangular and fisheye —
 * given by eye, target and up, with the field of view across the image's
 * width; pixels are square. A camera_frame is the camera prepared for one
 * image size; camera_ray turns a position on the image and a position on
 * the lens into a ray.
 *
 * Thin lens (Cook, Porter and Carpenter, "Distributed Ray Tracing",
 * SIGGRAPH 1984; Pharr, Jakob and Humphreys, PBRT 3rd ed., 6.2.3): the ray
 * starts at a point of a disc of diameter `aperture` around the eye and
 * goes through the point the pinhole ray meets at the focus distance, so
 * everything at that distance is sharp for any lens position. The focus
 * surface is a plane for perspective and orthographic, a sphere around the
 * eye for the two panoramic projections. */
#ifndef GLINT_SCENE_CAMERA_H
#define GLINT_SCENE_CAMERA_H

#include <stdbool.h>
#include "accel/isa.h"
#include "core/ray.h"

typedef enum camera_projection {
    CAMERA_PERSPECTIVE,
    CAMERA_ORTHOGRAPHIC,
    CAMERA_EQUIRECTANGULAR,
    CAMERA_FISHEYE,
} camera_projection;

typedef struct camera {
    vec3 eye, target, up;
    float hfov;           /* degrees: perspective (0, 180), fisheye (0, 360] */
    float aperture;       /* lens diameter, >= 0; 0 a pinhole */
    float focus_distance; /* > 0; 0: the distance from eye to target */
    float width;          /* orthographic: the view's width in world units */
    float shutter;        /* share of a frame the shutter stays open, [0, 1] */
    camera_projection projection;
} camera;

typedef struct camera_frame {
    camera_projection projection;
    vec3 eye;
    vec3 u, v, w;    /* right, up, forward: unit and orthogonal */
    vec3 corner;     /* perspective: direction to the image's top-left corner */
    vec3 dx, dy;     /* perspective: one pixel right, one down; orthographic: the same
                        steps in world units */
    float width, height; /* the image, in pixels */
    float half_angle;    /* fisheye: half the field of view, radians */
    float lens_radius, focus;
} camera_frame;

camera_frame camera_frame_make(const camera *cam, int width, int height);

/* The ray through image position (x, y), in pixels from the top-left
 * corner (pixel i spans [i, i+1)), from lens position (lu, lv) in [0, 1)^2
 * (unused by a pinhole). The direction is not normalised; tmax is infinite
 * and time 0. False where no ray leaves: outside a fisheye's circle. */
bool camera_ray(const camera_frame *f, float x, float y, float lu, float lv, ray *out);

/* camera_ray for the n <= 8 image positions (x0 + i + fx, y) of a row,
 * all from lens position (lu, lv), at time `time`: ray i into lane i of
 * *p (idle lanes repeat a ray, as ray8_pack leaves them). Returns the
 * lanes with a ray. */
int camera_row8(const camera_frame *f, int x0, int n, float fx, float y, float lu, float lv,
                float time, ray8 *p);

/* camera_row8 on SIMD path isa: the same rays, a pinhole's made in
 * eight-wide registers on the paths that have them (scene/camera8.h). */
int camera_row8_on(accel_isa isa, const camera_frame *f, int x0, int n, float fx, float y,
                   float lu, float lv, float time, ray8 *p);
int camera_pinhole8_avx2(const camera_frame *f, int x0, int n, float fx, float y, float time,
                         ray8 *p);
int camera_pinhole8_avx512(const camera_frame *f, int x0, int n, float fx, float y, float time,
                           ray8 *p);

/* The unit direction the pinhole ray through (x, y) takes, as camera_ray
 * with aperture 0; false outside a fisheye's circle. */
bool camera_direction(const camera_frame *f, float x, float y, vec3 *out);

#endif

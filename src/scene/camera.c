#include "camera.h"

#include <math.h>

/* The image window sits at distance 1 along the view direction; its width
 * is 2 tan(hfov / 2) and its height keeps the pixels square. */
camera_frame camera_frame_make(const camera *cam, int width, int height)
{
    vec3 w = v3_norm(v3_sub(cam->target, cam->eye)); /* forward */
    vec3 u = v3_norm(v3_cross(w, cam->up));           /* right */
    vec3 v = v3_cross(u, w);                          /* up */
    float half_w = tanf(cam->hfov * (float)(M_PI / 360.0));
    float half_h = half_w * (float)height / (float)width;
    camera_frame f;
    f.eye = cam->eye;
    f.dx = v3_scale(u, 2.0f * half_w / (float)width);
    f.dy = v3_scale(v, -2.0f * half_h / (float)height);
    f.corner = v3_add(w, v3_sub(v3_scale(v, half_h), v3_scale(u, half_w)));
    return f;
}

#include "camera.h"

#include <math.h>

camera_frame camera_frame_make(const camera *cam, int width, int height)
{
    camera_frame f = {0};
    f.projection = cam->projection;
    f.eye = cam->eye;
    f.w = v3_norm(v3_sub(cam->target, cam->eye));
    f.u = v3_norm(v3_cross(f.w, cam->up));
    f.v = v3_cross(f.u, f.w);
    f.width = (float)width;
    f.height = (float)height;
    f.lens_radius = 0.5f * cam->aperture;
    f.focus = cam->focus_distance > 0.0f ? cam->focus_distance
                                         : v3_len(v3_sub(cam->target, cam->eye));
    switch (cam->projection) {
    case CAMERA_PERSPECTIVE: {
        /* the image window at distance 1: 2 tan(hfov / 2) wide */
        float fov = cam->hfov < 179.9f ? cam->hfov : 179.9f; /* keyed values may stray */
        float half_w = tanf(fov * (float)(M_PI / 360.0));
        float half_h = half_w * (float)height / (float)width;
        f.dx = v3_scale(f.u, 2.0f * half_w / (float)width);
        f.dy = v3_scale(f.v, -2.0f * half_h / (float)height);
        f.corner = v3_add(f.w, v3_sub(v3_scale(f.v, half_h), v3_scale(f.u, half_w)));
        break;
    }
    case CAMERA_ORTHOGRAPHIC: {
        float px = cam->width / (float)width; /* world units per pixel */
        f.dx = v3_scale(f.u, px);
        f.dy = v3_scale(f.v, -px);
        f.corner = v3_sub(v3_scale(f.v, 0.5f * px * (float)height),
                          v3_scale(f.u, 0.5f * cam->width));
        break;
    }
    case CAMERA_EQUIRECTANGULAR:
        break;
    case CAMERA_FISHEYE:
        f.half_angle = cam->hfov * (float)(M_PI / 360.0);
        break;
    }
    return f;
}

/* A point of the unit disc from (a, b) in [0, 1)^2, by Shirley and Chiu's
 * concentric map ("A Low Distortion Map Between Disk and Square", JGT 1997),
 * which keeps strata compact. */
static void concentric_disc(float a, float b, float *x, float *y)
{
    float sx = 2.0f * a - 1.0f, sy = 2.0f * b - 1.0f;
    if (sx == 0.0f && sy == 0.0f) {
        *x = *y = 0.0f;
        return;
    }
    float r, phi;
    if (fabsf(sx) > fabsf(sy)) {
        r = sx;
        phi = (float)(M_PI / 4.0) * (sy / sx);
    } else {
        r = sy;
        phi = (float)(M_PI / 2.0) - (float)(M_PI / 4.0) * (sx / sy);
    }
    *x = r * cosf(phi);
    *y = r * sinf(phi);
}

bool camera_direction(const camera_frame *f, float x, float y, vec3 *out)
{
    switch (f->projection) {
    case CAMERA_PERSPECTIVE:
        *out = v3_norm(v3_madd(v3_madd(f->corner, f->dx, x), f->dy, y));
        return true;
    case CAMERA_ORTHOGRAPHIC:
        *out = f->w;
        return true;
    case CAMERA_EQUIRECTANGULAR: {
        /* longitude -180..180 degrees across, latitude 90..-90 down; the
         * image's centre looks forward */
        float lon = (x / f->width - 0.5f) * (float)(2.0 * M_PI);
        float lat = (0.5f - y / f->height) * (float)M_PI;
        float c = cosf(lat);
        *out = v3_add(v3_add(v3_scale(f->u, c * sinf(lon)), v3_scale(f->v, sinf(lat))),
                      v3_scale(f->w, c * cosf(lon)));
        return true;
    }
    case CAMERA_FISHEYE: {
        /* equidistant: the angle from the axis is proportional to the
         * distance from the image's centre, half_angle at half the width */
        float px = x - 0.5f * f->width, py = 0.5f * f->height - y;
        float r = sqrtf(px * px + py * py) / (0.5f * f->width);
        if (r > 1.0f)
            return false;
        float theta = r * f->half_angle, phi = atan2f(py, px);
        float s = sinf(theta);
        *out = v3_add(v3_scale(f->w, cosf(theta)),
                      v3_add(v3_scale(f->u, s * cosf(phi)), v3_scale(f->v, s * sinf(phi))));
        return true;
    }
    }
    return false;
}

bool camera_ray(const camera_frame *f, float x, float y, float lu, float lv, ray *out)
{
    vec3 o = f->eye, d;
    if (f->projection == CAMERA_PERSPECTIVE) {
        d = v3_madd(v3_madd(f->corner, f->dx, x), f->dy, y); /* forward component 1 */
    } else if (f->projection == CAMERA_ORTHOGRAPHIC) {
        o = v3_add(f->eye, v3_madd(v3_madd(f->corner, f->dx, x), f->dy, y));
        d = f->w;
    } else if (!camera_direction(f, x, y, &d)) {
        return false;
    }
    if (f->lens_radius > 0.0f) {
        /* the point in focus: on the plane at the focus distance (d's
         * forward component is 1) or on the sphere of that radius */
        vec3 focal = v3_madd(o, d, f->focus);
        vec3 a = f->u, b = f->v;
        if (f->projection == CAMERA_EQUIRECTANGULAR || f->projection == CAMERA_FISHEYE)
            v3_basis(d, &a, &b); /* the lens faces the ray */
        float lx, ly;
        concentric_disc(lu, lv, &lx, &ly);
        o = v3_madd(v3_madd(o, a, lx * f->lens_radius), b, ly * f->lens_radius);
        d = v3_sub(focal, o);
    }
    *out = ray_make(o, d, INFINITY);
    return true;
}

int camera_row8(const camera_frame *f, int x0, int n, float fx, float y, float lu, float lv,
                float time, ray8 *p)
{
    if (f->projection != CAMERA_PERSPECTIVE || f->lens_radius > 0.0f) {
        ray out[8];
        int active = 0;
        for (int i = 0; i < n; i++) {
            if (camera_ray(f, (float)(x0 + i) + fx, y, lu, lv, &out[i]))
                active |= 1 << i;
            out[i].time = time;
        }
        if (active)
            ray8_pack(p, out, active);
        return active;
    }
    /* a pinhole's rays share their origin; each direction is camera_ray's,
     * lane by lane */
    for (int k = 0; k < 8; k++) {
        float x = (float)(x0 + (k < n ? k : 0)) + fx;
        p->dx[k] = f->corner.x + f->dx.x * x + f->dy.x * y;
        p->dy[k] = f->corner.y + f->dx.y * x + f->dy.y * y;
        p->dz[k] = f->corner.z + f->dx.z * x + f->dy.z * y;
        p->ox[k] = f->eye.x, p->oy[k] = f->eye.y, p->oz[k] = f->eye.z;
        p->tmin[k] = 0.0f, p->tmax[k] = INFINITY, p->time[k] = time;
    }
    return (1 << n) - 1;
}

int camera_row8_on(accel_isa isa, const camera_frame *f, int x0, int n, float fx, float y,
                   float lu, float lv, float time, ray8 *p)
{
#if defined(GLINT_WIDE_KERNELS)
    if (f->projection == CAMERA_PERSPECTIVE && f->lens_radius == 0.0f) {
        if (isa == ACCEL_AVX512)
            return camera_pinhole8_avx512(f, x0, n, fx, y, time, p);
        if (isa == ACCEL_AVX2)
            return camera_pinhole8_avx2(f, x0, n, fx, y, time, p);
    }
#endif
    (void)isa;
    return camera_row8(f, x0, n, fx, y, lu, lv, time, p);
}

/* Camera moves for the preview window: an orbit camera around look_at, as
 * in most 3D editors, and a free flight for WASD/QE. */
#include "preview.h"

#include <math.h>
#include <stdio.h>

typedef struct v3d {
    double x, y, z;
} v3d;

static v3d get(const double v[3]) { return (v3d){v[0], v[1], v[2]}; }
static void put(double v[3], v3d a) { v[0] = a.x, v[1] = a.y, v[2] = a.z; }
static v3d add(v3d a, v3d b) { return (v3d){a.x + b.x, a.y + b.y, a.z + b.z}; }
static v3d sub(v3d a, v3d b) { return (v3d){a.x - b.x, a.y - b.y, a.z - b.z}; }
static v3d scale(v3d a, double s) { return (v3d){a.x * s, a.y * s, a.z * s}; }
static double dot(v3d a, v3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static v3d cross(v3d a, v3d b)
{
    return (v3d){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static v3d norm(v3d a) { return scale(a, 1.0 / sqrt(dot(a, a))); }

/* Rodrigues' rotation of v about the unit axis k by angle a (radians). */
static v3d rotate(v3d v, v3d k, double a)
{
    double c = cos(a), s = sin(a);
    return add(add(scale(v, c), scale(cross(k, v), s)), scale(k, dot(k, v) * (1.0 - c)));
}

/* The view's right, true up and forward (unit), and the distance. */
static void frame(const glint_camera *c, v3d *right, v3d *up, v3d *fwd, double *dist)
{
    v3d d = sub(get(c->look_at), get(c->eye));
    *dist = sqrt(dot(d, d));
    *fwd = scale(d, 1.0 / *dist);
    *right = norm(cross(*fwd, get(c->up)));
    *up = cross(*right, *fwd);
}

void camera_orbit(glint_camera *c, double yaw, double pitch)
{
    v3d right, up, fwd, world_up = norm(get(c->up));
    double dist;
    frame(c, &right, &up, &fwd, &dist);
    v3d off = sub(get(c->eye), get(c->look_at));
    off = rotate(off, world_up, -yaw * M_PI / 180.0);
    /* pitch, stopped 1 degree short of the up axis either way */
    double now = acos(fmax(-1.0, fmin(1.0, dot(norm(off), world_up)))) * 180.0 / M_PI;
    double want = fmax(1.0, fmin(179.0, now - pitch));
    v3d axis = norm(cross(world_up, off));
    off = rotate(off, axis, (want - now) * M_PI / 180.0);
    put(c->eye, add(get(c->look_at), off));
}

void camera_pan(glint_camera *c, double r, double u)
{
    v3d right, up, fwd;
    double dist;
    frame(c, &right, &up, &fwd, &dist);
    v3d move = add(scale(right, r * dist), scale(up, u * dist));
    put(c->eye, add(get(c->eye), move));
    put(c->look_at, add(get(c->look_at), move));
}

void camera_dolly(glint_camera *c, double factor)
{
    v3d off = sub(get(c->eye), get(c->look_at));
    if (sqrt(dot(off, off)) * factor < 1e-3)
        return;
    put(c->eye, add(get(c->look_at), scale(off, factor)));
}

void camera_fly(glint_camera *c, double f, double r, double u)
{
    v3d right, up, fwd;
    double dist;
    frame(c, &right, &up, &fwd, &dist);
    v3d move = scale(add(add(scale(fwd, f), scale(right, r)), scale(up, u)), dist);
    put(c->eye, add(get(c->eye), move));
    put(c->look_at, add(get(c->look_at), move));
}

void camera_yaml(const glint_camera *c, char *buf, size_t size)
{
    snprintf(buf, size,
             "camera:\n"
             "  eye: [%.6g, %.6g, %.6g]\n"
             "  look_at: [%.6g, %.6g, %.6g]\n"
             "  up: [%.6g, %.6g, %.6g]\n"
             "  fov: %.6g\n",
             c->eye[0], c->eye[1], c->eye[2], c->look_at[0], c->look_at[1], c->look_at[2],
             c->up[0], c->up[1], c->up[2], c->fov);
}

/* mktextures: makes the two pictures the built-in scene uses, so that
 * nothing has to be downloaded: flag.png, a 3:2 red flag with five gold
 * stars (the construction of the flag the original assignment showed), and
 * globe.png, an equirectangular map of an imaginary planet drawn from 3D
 * noise sampled on the unit sphere, so the map has no seam and no pinching
 * at the poles. Output is the same byte for byte on every run.
 * Usage: mktextures OUTDIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>
#include <stb_perlin.h>

#define FLAG_W 600
#define FLAG_H 400
#define GLOBE_W 1024
#define GLOBE_H 512
#define AA 4 /* supersamples per axis for star edges */

/* Whether (x, y) lies inside a five-pointed star centred at (cx, cy) with
 * outer radius r and one point towards angle a (radians, y down). */
static int in_star(double x, double y, double cx, double cy, double r, double a)
{
    double inner = r * sin(M_PI / 10) / sin(7 * M_PI / 10);
    double px = x - cx, py = y - cy;
    /* Angle relative to the first point, folded into one tenth of a turn. */
    double ang = atan2(py, px) - a;
    double d = hypot(px, py);
    double sector = 2 * M_PI / 10;
    ang = fmod(ang, 2 * sector);
    if (ang < 0)
        ang += 2 * sector;
    if (ang > sector)
        ang = 2 * sector - ang;
    /* The edge runs from the point (r, 0) to the inner corner (inner, sector). */
    double ex = inner * cos(sector) - r, ey = inner * sin(sector);
    double qx = d * cos(ang) - r, qy = d * sin(ang);
    return ex * qy - ey * qx >= 0; /* on the centre's side of the edge */
}

static int make_flag(const char *path)
{
    static unsigned char px[FLAG_W * FLAG_H * 3];
    const double u = FLAG_W / 30.0; /* grid unit: the flag is 30 x 20 units */
    struct { double x, y, r; } stars[5] = {{5, 5, 3}, {10, 2, 1}, {12, 4, 1}, {12, 7, 1}, {10, 9, 1}};
    for (int y = 0; y < FLAG_H; y++)
        for (int x = 0; x < FLAG_W; x++) {
            int inside = 0;
            for (int sy = 0; sy < AA; sy++)
                for (int sx = 0; sx < AA; sx++) {
                    double fx = (x + (sx + 0.5) / AA) / u, fy = (y + (sy + 0.5) / AA) / u;
                    for (int s = 0; s < 5; s++) {
                        /* Small stars point at the large star's centre. */
                        double a = s == 0 ? -M_PI / 2
                                          : atan2(stars[0].y - stars[s].y, stars[0].x - stars[s].x);
                        if (in_star(fx, fy, stars[s].x, stars[s].y, stars[s].r, a)) {
                            inside++;
                            break;
                        }
                    }
                }
            double t = (double)inside / (AA * AA);
            unsigned char *p = px + (y * FLAG_W + x) * 3;
            p[0] = (unsigned char)lround(222 + t * (255 - 222));
            p[1] = (unsigned char)lround(41 + t * (222 - 41));
            p[2] = (unsigned char)lround(16 + t * (0 - 16));
        }
    return stbi_write_png(path, FLAG_W, FLAG_H, 3, px, FLAG_W * 3);
}

static void mix(double c[3], const double a[3], const double b[3], double t)
{
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    for (int i = 0; i < 3; i++)
        c[i] = a[i] + (b[i] - a[i]) * t;
}

static int make_globe(const char *path)
{
    static unsigned char px[GLOBE_W * GLOBE_H * 3];
    const double deep[3] = {8, 30, 90}, shallow[3] = {30, 90, 160};
    const double beach[3] = {194, 178, 128}, green[3] = {50, 120, 40}, dry[3] = {140, 110, 60};
    const double rock[3] = {110, 95, 80}, ice[3] = {240, 245, 250};
    for (int y = 0; y < GLOBE_H; y++) {
        double lat = M_PI / 2 - (y + 0.5) / GLOBE_H * M_PI; /* row 0: north */
        for (int x = 0; x < GLOBE_W; x++) {
            /* Longitude as the sphere mapping in src/geom/sphere.c reads it:
             * u = 0.5 faces +z. */
            double lon = ((x + 0.5) / GLOBE_W - 0.5) * 2 * M_PI;
            double sx = cos(lat) * sin(lon), sy = sin(lat), sz = cos(lat) * cos(lon);
            float k = 1.7f;
            double h = stb_perlin_fbm_noise3((float)sx * k, (float)sy * k, (float)sz * k, 2.0f, 0.5f, 6);
            double m = stb_perlin_fbm_noise3((float)sx * 3 + 11, (float)sy * 3 + 7, (float)sz * 3 + 3,
                                             2.0f, 0.5f, 4);
            double c[3];
            if (h < 0.02) {
                mix(c, deep, shallow, (h + 0.35) / 0.37);
            } else if (h < 0.05) {
                mix(c, beach, green, (h - 0.02) / 0.03);
            } else {
                double land[3];
                mix(land, green, dry, 0.5 + m * 1.5);
                mix(c, land, rock, (h - 0.25) / 0.2);
            }
            double polar = fabs(sin(lat)) + 0.15 * stb_perlin_noise3((float)sx * 6, (float)sy * 6,
                                                                      (float)sz * 6, 0, 0, 0);
            if (polar > 0.93)
                mix(c, c, ice, (polar - 0.93) / 0.03);
            unsigned char *p = px + (y * GLOBE_W + x) * 3;
            for (int i = 0; i < 3; i++)
                p[i] = (unsigned char)lround(c[i] < 0 ? 0 : c[i] > 255 ? 255 : c[i]);
        }
    }
    return stbi_write_png(path, GLOBE_W, GLOBE_H, 3, px, GLOBE_W * 3);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: mktextures OUTDIR\n");
        return 2;
    }
    /* Every row with the Up filter: the files come out a little larger
     * than with stb's choice per row (mostly Paeth), and decode about
     * twice as fast, which every render of the built-in scene pays. */
    stbi_write_force_png_filter = 2;
    char path[4096];
    snprintf(path, sizeof path, "%s/flag.png", argv[1]);
    if (!make_flag(path)) {
        fprintf(stderr, "mktextures: cannot write %s\n", path);
        return 1;
    }
    snprintf(path, sizeof path, "%s/globe.png", argv[1]);
    if (!make_globe(path)) {
        fprintf(stderr, "mktextures: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

/* Texture coordinates and lookups (src/shade/texture.h, with the (u, v) of
 * src/geom): the sphere's longitude/latitude mapping at known points
 * (poles, equator, u = 0.5 facing +z as docs/scene-format.md says, the seam
 * at -z), an image texture that stays continuous across that seam with
 * wrap repeat, quad corners landing on the image's corners (v = 0 is the
 * bottom row), the chequer's squares, and bilinear filtering of a 2x2
 * image at texel centres and midpoints.
 *
 * Colours use the identity decode table (value / 255), so expected values
 * are exact fractions; tolerance 1e-6 (float rounding of a lerp). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "glint.h"

#include "geom/shape.h"
#include "io/image.h"
#include "shade/texture.h"
#include "near.h"

#define TOL 1e-6

/* 2x2 image, row 0 at the top: TL TR / BL BR, one distinct value per
 * channel and texel. */
static uint8_t px2[2 * 2 * 3] = {
    0, 10, 250,   100, 20, 200, /* TL, TR */
    200, 30, 150, 40, 40, 100,  /* BL, BR */
};
enum { TL, TR, BL, BR };

static float decode[256];

/* The texture at surface coordinates (u, v). */
static vec3 eval_uv(const texture *t, const image *images, const float *dec, float u, float v)
{
    texture_point tp = {v3s(0.0f), v3(0, 0, 1), u, v};
    return texture_eval(t, images, dec, &tp);
}
static image img2;

static void setup(void)
{
    image_decode_table(GLINT_TRANSFER_NONE, decode);
    img2 = (image){2, 2, px2, NULL};
}

/* Expected colour: the mean of the listed texels (by index into px2). */
static vec3 mean_of(const int *texels, int n)
{
    double c[3] = {0, 0, 0};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            c[k] += px2[texels[i] * 3 + k] / 255.0 / n;
    return v3((float)c[0], (float)c[1], (float)c[2]);
}

static surface sphere_at(vec3 dir)
{
    shape s = shape_sphere(v3(1, 1, 1), 2);
    surface sf;
    sphere_surface(&s.sphere, v3_madd(v3(1, 1, 1), v3_norm(dir), 2), &sf);
    return sf;
}

Test(texture, sphere_uv_of_known_points)
{
    surface sf = sphere_at(v3(0, 1, 0));
    ASSERT_NEAR(sf.v, 1.0, TOL); /* north pole */
    sf = sphere_at(v3(0, -1, 0));
    ASSERT_NEAR(sf.v, 0.0, TOL); /* south pole */
    sf = sphere_at(v3(0, 0, 1));
    ASSERT_NEAR(sf.u, 0.5, TOL); /* +z faces u = 0.5 */
    ASSERT_NEAR(sf.v, 0.5, TOL); /* equator */
    sf = sphere_at(v3(1, 0, 0));
    ASSERT_NEAR(sf.u, 0.75, TOL);
    ASSERT_NEAR(sf.v, 0.5, TOL);
    sf = sphere_at(v3(-1, 0, 0));
    ASSERT_NEAR(sf.u, 0.25, TOL);
    sf = sphere_at(v3(0, 1, 1)); /* latitude 45 degrees */
    ASSERT_NEAR(sf.u, 0.5, TOL);
    ASSERT_NEAR(sf.v, 0.75, TOL);
    sf = sphere_at(v3(1, -1, 1)); /* longitude 45, latitude -asin(1/sqrt3) */
    ASSERT_NEAR(sf.u, 0.625, TOL);
    ASSERT_NEAR(sf.v, 0.5 - asin(1 / sqrt(3.0)) / M_PI, TOL);
}

/* The seam is at -z: a point a little towards +x of it has u near 1, a
 * point a little towards -x has u near 0 (delta = 1e-3 radians of
 * longitude: u = 1 - delta/2pi and delta/2pi). */
Test(texture, sphere_seam_at_minus_z)
{
    const double delta = 1e-3;
    surface east = sphere_at(v3((float)sin(delta), 0, (float)-cos(delta)));
    surface west = sphere_at(v3((float)-sin(delta), 0, (float)-cos(delta)));
    ASSERT_NEAR(east.u, 1.0 - delta / (2 * M_PI), 1e-5);
    ASSERT_NEAR(west.u, delta / (2 * M_PI), 1e-5);
    cr_assert(east.u <= 1.0f && west.u >= 0.0f);
}

/* With wrap repeat, u = 0 and u = 1 are the same place: both sample
 * halfway between the last and first columns. Points either side of the
 * sphere's seam get nearly the same colour. */
Test(texture, image_is_continuous_across_the_seam_with_repeat, .init = setup)
{
    /* 4x2 image with strongly different columns */
    static uint8_t px[4 * 2 * 3];
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++)
            for (int k = 0; k < 3; k++)
                px[(y * 4 + x) * 3 + k] = (uint8_t)(60 * x + 20 * y + 7 * k);
    image img = {4, 2, px, NULL};
    texture t = texture_image(0);
    cr_assert_eq(t.image.wrap_u, WRAP_REPEAT);
    for (float v = 0.0f; v <= 1.0f; v += 0.125f) {
        vec3 a = eval_uv(&t, &img, decode, 0.0f, v), b = eval_uv(&t, &img, decode, 1.0f, v);
        ASSERT_V3_NEAR(a, b.x, b.y, b.z, 0);
    }
    /* at v = 0.75 (centre of the top row): (column 3 + column 0) / 2 */
    vec3 c = eval_uv(&t, &img, decode, 0.0f, 0.75f);
    ASSERT_V3_NEAR(c, (180 + 0) / 2 / 255.0, (187 + 7) / 2 / 255.0, (194 + 14) / 2 / 255.0, TOL);
    /* just either side of u = 0 */
    vec3 lo = eval_uv(&t, &img, decode, 1e-4f, 0.75f), hi = eval_uv(&t, &img, decode, 1.0f - 1e-4f, 0.75f);
    ASSERT_V3_NEAR(lo, hi.x, hi.y, hi.z, 1e-3);
    /* and through the sphere's own coordinates either side of its seam */
    surface east = sphere_at(v3(1e-4f, 0.3f, -1)), west = sphere_at(v3(-1e-4f, 0.3f, -1));
    vec3 ce = eval_uv(&t, &img, decode, east.u, east.v);
    vec3 cw = eval_uv(&t, &img, decode, west.u, west.v);
    ASSERT_V3_NEAR(ce, cw.x, cw.y, cw.z, 1e-3);
    /* Clamped, the two ends are the edge columns instead. */
    t.image.wrap_u = WRAP_CLAMP;
    vec3 l = eval_uv(&t, &img, decode, 0.0f, 0.75f), r = eval_uv(&t, &img, decode, 1.0f, 0.75f);
    ASSERT_V3_NEAR(l, 0, 7 / 255.0, 14 / 255.0, TOL);
    ASSERT_V3_NEAR(r, 180 / 255.0, 187 / 255.0, 194 / 255.0, TOL);
}

/* A quad's (u, v) corners land on the image's corners, v = 0 at the bottom. */
Test(texture, quad_uv_corners_pick_image_corners, .init = setup)
{
    shape q = shape_quad(v3(-1, 0, 0), v3(2, 0, 0), v3(0, 1, 0));
    texture t = texture_image(0);
    t.image.wrap_u = t.image.wrap_v = WRAP_CLAMP;
    const float cu[4] = {0, 1, 0, 1}, cv[4] = {1, 1, 0, 0};
    const int want[4] = {TL, TR, BL, BR};
    for (int i = 0; i < 4; i++) {
        vec3 target = v3(-1 + 2 * cu[i], cv[i], 0);
        ray r = ray_make(v3_add(target, v3(0, 0, 2)), v3(0, 0, -1), INFINITY);
        shape_hit h;
        cr_assert(shape_intersect(&q, &r, &h));
        surface sf;
        shape_surface(&q, &r, &h, &sf);
        ASSERT_NEAR(sf.u, cu[i], TOL);
        ASSERT_NEAR(sf.v, cv[i], TOL);
        vec3 c = eval_uv(&t, &img2, decode, sf.u, sf.v);
        vec3 e = mean_of(&want[i], 1);
        ASSERT_V3_NEAR(c, e.x, e.y, e.z, TOL);
    }
}

/* A plane's (u, v) are world units: a unit chequer there has squares one
 * unit wide, alternating along each tangent. */
Test(texture, plane_uv_in_world_units)
{
    shape p = shape_plane(v3(0, 0, 0), v3(0, 1, 0));
    texture t = texture_checker(v3s(1), v3s(0), 1, 1);
    float prev = -1;
    for (int i = 0; i < 6; i++) {
        vec3 at = v3_madd(v3_scale(p.plane.tu, 0.5f + (float)i), p.plane.tv, 0.5f);
        surface sf;
        plane_surface(&p.plane, at, &sf);
        ASSERT_NEAR(sf.u, 0.5 + i, TOL);
        ASSERT_NEAR(sf.v, 0.5, TOL);
        vec3 c = eval_uv(&t, NULL, decode, sf.u, sf.v);
        cr_assert(c.x == 0.0f || c.x == 1.0f);
        cr_assert_neq(c.x, prev, "square %d has the colour of its neighbour", i);
        prev = c.x;
    }
}

/* The chequer: even where floor(u') + floor(v') is even. */
Test(texture, checker_values)
{
    vec3 even = v3(0.9f, 0.8f, 0.7f), odd = v3(0.1f, 0.2f, 0.3f);
    texture t = texture_checker(even, odd, 2, 2); /* 2 x 2 squares over [0, 1]^2 */
    const struct {
        float u, v;
        bool even;
    } cases[] = {
        {0.25f, 0.25f, true},  {0.75f, 0.25f, false}, {0.25f, 0.75f, false},
        {0.75f, 0.75f, true},  {1.25f, 0.25f, true},  {-0.25f, 0.25f, false},
        {-0.25f, -0.25f, true}, {0.0f, 0.0f, true},   {0.5f, 0.0f, false},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        vec3 c = eval_uv(&t, NULL, decode, cases[i].u, cases[i].v);
        vec3 e = cases[i].even ? even : odd;
        cr_assert(c.x == e.x && c.y == e.y && c.z == e.z, "(%g, %g): got %g, want %s",
                  (double)cases[i].u, (double)cases[i].v, (double)c.x,
                  cases[i].even ? "even" : "odd");
    }
    /* 8 x 4 squares, offset half a square in u (offset is applied after scale) */
    texture s = texture_checker(even, odd, 8, 4);
    s.offset.x = 0.5f;
    vec3 a = eval_uv(&s, NULL, decode, 0.01f, 0.1f); /* u' = 0.58: square 0 */
    vec3 b = eval_uv(&s, NULL, decode, 0.07f, 0.1f); /* u' = 1.06: square 1 */
    vec3 c = eval_uv(&s, NULL, decode, 0.07f, 0.3f); /* v' = 1.2: square (1, 1) */
    cr_assert(a.x == even.x && b.x == odd.x && c.x == even.x);
}

/* Bilinear filtering of the 2x2 image: exact texel values at texel centres,
 * means of two texels at edge midpoints, mean of four at the centre. */
Test(texture, bilinear_2x2_at_centres_and_midpoints, .init = setup)
{
    texture t = texture_image(0);
    t.image.wrap_u = t.image.wrap_v = WRAP_CLAMP;
    const struct {
        float u, v;
        int n, texels[4];
    } cases[] = {
        {0.25f, 0.75f, 1, {TL}},         {0.75f, 0.75f, 1, {TR}},
        {0.25f, 0.25f, 1, {BL}},         {0.75f, 0.25f, 1, {BR}},
        {0.5f, 0.75f, 2, {TL, TR}},      {0.5f, 0.25f, 2, {BL, BR}},
        {0.25f, 0.5f, 2, {TL, BL}},      {0.75f, 0.5f, 2, {TR, BR}},
        {0.5f, 0.5f, 4, {TL, TR, BL, BR}},
        /* clamped: beyond the outer centres the edge texels hold */
        {0.0f, 1.0f, 1, {TL}},           {1.0f, 0.0f, 1, {BR}},
        {0.1f, 0.9f, 1, {TL}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        vec3 c = eval_uv(&t, &img2, decode, cases[i].u, cases[i].v);
        vec3 e = mean_of(cases[i].texels, cases[i].n);
        cr_assert(fabs(c.x - e.x) <= TOL && fabs(c.y - e.y) <= TOL && fabs(c.z - e.z) <= TOL,
                  "(%g, %g): got (%g %g %g), want (%g %g %g)", (double)cases[i].u,
                  (double)cases[i].v, (double)c.x, (double)c.y, (double)c.z, (double)e.x,
                  (double)e.y, (double)e.z);
    }
    /* A quarter of the way from the TL centre to the TR centre. */
    vec3 q = eval_uv(&t, &img2, decode, 0.375f, 0.75f);
    ASSERT_NEAR(q.x, (0.75 * 0 + 0.25 * 100) / 255.0, TOL);
    /* Repeat: at u = 0 the left and right columns mix. */
    t.image.wrap_u = t.image.wrap_v = WRAP_REPEAT;
    vec3 r = eval_uv(&t, &img2, decode, 0.0f, 0.75f);
    vec3 e = mean_of((const int[]){TL, TR}, 2);
    ASSERT_V3_NEAR(r, e.x, e.y, e.z, TOL);
    r = eval_uv(&t, &img2, decode, 0.0f, 0.0f); /* all four corners meet */
    e = mean_of((const int[]){TL, TR, BL, BR}, 4);
    ASSERT_V3_NEAR(r, e.x, e.y, e.z, TOL);
}

/* Scale repeats the image; offset shifts it; decode tables apply. */
Test(texture, scale_offset_and_decode, .init = setup)
{
    texture t = texture_image(0);
    t.scale.x = 2.0f; /* u = 0.125 and 0.625 both land on the left column centre */
    vec3 a = eval_uv(&t, &img2, decode, 0.125f, 0.75f);
    vec3 b = eval_uv(&t, &img2, decode, 0.625f, 0.75f);
    ASSERT_V3_NEAR(a, 0, 10 / 255.0, 250 / 255.0, TOL);
    ASSERT_V3_NEAR(b, 0, 10 / 255.0, 250 / 255.0, TOL);
    t.scale.x = 1.0f;
    t.offset.x = 0.5f; /* u = 0.25 now samples u' = 0.75: TR */
    vec3 c = eval_uv(&t, &img2, decode, 0.25f, 0.75f);
    ASSERT_V3_NEAR(c, 100 / 255.0, 20 / 255.0, 200 / 255.0, TOL);

    float srgb[256];
    image_decode_table(GLINT_TRANSFER_SRGB, srgb);
    t.offset.x = 0.0f;
    vec3 d = eval_uv(&t, &img2, srgb, 0.25f, 0.75f); /* TL: 0, 10, 250 */
    ASSERT_NEAR(d.x, 0.0, TOL);
    ASSERT_NEAR(d.y, 10 / 255.0 / 12.92, TOL); /* linear segment */
    ASSERT_NEAR(d.z, pow((250 / 255.0 + 0.055) / 1.055, 2.4), 1e-6);
}

/* HDR textures were gamma-encoded to 8 bits and clamped (0.25 became
 * 0.533, 7.5 became 1): they are read as linear floats and looked up as
 * they are, whatever the decode table. A 2x2 Radiance file is written and
 * read back; RGBE keeps 8 bits of mantissa, so each value is within 1/128
 * of its pixel's brightest channel. */
Test(texture, hdr_texels_are_linear_and_unclamped)
{
    float rgb[2 * 2 * 3] = {0.25f, 0.25f, 0.25f, 7.5f, 7.5f, 7.5f,
                            1.0f / 64, 1.0f / 64, 1.0f / 64, 3.0f, 0.5f, 0.125f};
    glint_film film = {2, 2, rgb, NULL};
    char path[] = "/tmp/glint-hdr-XXXXXX.hdr";
    int fd = mkstemps(path, 4);
    cr_assert_geq(fd, 0);
    close(fd);
    glint_error err = {0};
    cr_assert_eq(glint_film_write(&film, path, NULL, &err), GLINT_OK, "%s", err.msg);
    image img;
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    remove(path);
    cr_assert_not_null(img.linear, "HDR images stay floats");
    float srgb[256];
    image_decode_table(GLINT_TRANSFER_SRGB, srgb);
    texture t = texture_image(0);
    /* texel centres: (0.25, 0.75) is the top-left texel, row 0 */
    vec3 c = eval_uv(&t, &img, srgb, 0.25f, 0.75f);
    ASSERT_NEAR(c.x, 0.25, (0.25) / 128);
    c = eval_uv(&t, &img, srgb, 0.75f, 0.75f);
    ASSERT_NEAR(c.x, 7.5, (7.5) / 128);
    c = eval_uv(&t, &img, srgb, 0.25f, 0.25f);
    ASSERT_NEAR(c.x, 1.0 / 64, (1.0 / 64) / 128);
    c = eval_uv(&t, &img, srgb, 0.75f, 0.25f);
    ASSERT_NEAR(c.x, 3.0, (3.0) / 128);
    ASSERT_NEAR(c.y, 0.5, 3.0 / 128); /* the exponent is the brightest channel's */
    ASSERT_NEAR(c.z, 0.125, 3.0 / 128);
    image_free(&img);
}

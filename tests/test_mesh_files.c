/* Model files as users have them (src/load/mesh_*.c): their materials,
 * textures and colours rendered, their normals, and what a bad file can do.
 *
 * Rendering: small files written here (an OBJ + MTL quad with a PNG
 * texture, a glTF quad with the PNG embedded, a PLY with vertex colours,
 * Collada quads with transparency 0, 1 and 0.25) are rendered face on with
 * ambient light 1 and transfer none, so each pixel is the surface's colour:
 * the texture's four quadrants in place, vertex colours, the scene's
 * material overriding the file's, Collada's opacity convention.
 *
 * Normals: a cube without normals keeps hard edges at the default crease
 * angle and is smooth at 180 degrees. Files without materials are matte white.
 *
 * Bad files: every 7th-byte truncation of each small file imports or fails
 * with one line naming the file (the importer runs in a child process, so
 * its aborts become errors); 2 * 10^9 declared vertices fail before any
 * allocation; a FIFO is refused without blocking; the limits' settings
 * bite; dropped triangles and short files are counted in warnings; the
 * files in tests/mesh-regress (found by fuzzing) stay harmless; the wire
 * form refuses a corrupted reply. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "film.h"
#include "glint.h"
#include "load/mesh_data.h"
#include "load/mesh_import.h"
#include "load/mesh_join.h"
#include "tmpdir.h"
#include "glint_run.h"

static void make_dir(void) { tmpdir_make("meshfiles"); }
static void remove_dir(void) { tmpdir_remove(); }

TestSuite(mesh_files, .init = make_dir, .fini = remove_dir, .timeout = 120);

static const char *put(const char *name, const void *data, size_t n)
{
    static char path[8][512];
    static int next;
    char *p = path[next++ % 8];
    snprintf(p, sizeof path[0], "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    cr_assert_not_null(f, "%s", p);
    if (n == 0)
        n = strlen(data);
    cr_assert_eq(fwrite(data, 1, n, f), n);
    cr_assert_eq(fclose(f), 0);
    return p;
}

static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s", path);
    static unsigned char buf[1 << 16];
    *n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    return buf;
}

/* ---- the files ------------------------------------------------------------- */

/* 8 x 8 texture in quadrants: red top left, green top right, blue bottom
 * left, white bottom right (bilinear samples inside a quadrant are pure). */
static const char *write_png(void)
{
    static const float quadrant[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    static float texels[8 * 8 * 3];
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++)
            memcpy(&texels[3 * (8 * y + x)], quadrant[(y >= 4) * 2 + (x >= 4)], 12);
    glint_film film = {.width = 8, .height = 8, .rgb = texels};
    glint_write_options o = {.format = GLINT_FORMAT_PNG};
    char path[512];
    snprintf(path, sizeof path, "%s/tex.png", dir);
    glint_error err = {0};
    cr_assert_eq(glint_film_write(&film, path, &o, &err), GLINT_OK, "%s", err.msg);
    return "tex.png";
}

/* The quad [-1, 1]^2 at z = 0, facing +z, texture upright (v = 0 at the bottom). */
static const char quad_obj[] = "mtllib quad.mtl\n"
                               "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "usemtl tex\nf 1/1 2/2 3/3 4/4\n";
static const char quad_mtl[] = "newmtl tex\nKd 0.5 0.5 0.5\nKs 0 0 0\nmap_Kd tex.png\n";

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) |
                     (i + 2 < n ? in[i + 2] : 0);
        out[o++] = abc[v >> 18 & 63];
        out[o++] = abc[v >> 12 & 63];
        out[o++] = i + 1 < n ? abc[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? abc[v & 63] : '=';
    }
    out[o] = '\0';
}

/* The same quad in glTF 2.0, its buffer and PNG inside as data URIs; glTF's
 * texture coordinates start at the image's top-left. */
static const char *write_gltf(void)
{
    float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    unsigned char buf[92];
    memcpy(buf, pos, 48);
    memcpy(buf + 48, uv, 32);
    memcpy(buf + 80, idx, 12);
    char b64buf[200], b64png[4096];
    base64(buf, sizeof buf, b64buf);
    write_png();
    char png[512];
    snprintf(png, sizeof png, "%s/tex.png", dir);
    size_t n;
    const unsigned char *bytes = slurp(png, &n);
    base64(bytes, n, b64png);
    static char text[8192];
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
             "{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,\"material\":0}]}],"
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0},"
             "\"metallicFactor\":0}}],\"textures\":[{\"source\":0}],"
             "\"images\":[{\"uri\":\"data:image/png;base64,%s\"}],"
             "\"buffers\":[{\"byteLength\":92,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32},"
             "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":"
             "\"VEC3\",\"min\":[-1,-1,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":"
             "5126,\"count\":4,\"type\":\"VEC2\"},{\"bufferView\":2,\"componentType\":5123,"
             "\"count\":6,\"type\":\"SCALAR\"}]}",
             b64png, b64buf);
    put("quad.gltf", text, 0);
    cr_assert_eq(unlink(png), 0); /* the embedded copy is the one used */
    return "quad.gltf";
}

static const char colored_ply[] = "ply\nformat ascii 1.0\nelement vertex 4\n"
                                  "property float x\nproperty float y\nproperty float z\n"
                                  "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                  "element face 2\nproperty list uchar int vertex_indices\n"
                                  "end_header\n-1 -1 0 0 255 0\n1 -1 0 0 255 0\n"
                                  "1 1 0 0 255 0\n-1 1 0 0 255 0\n3 0 1 2\n3 0 2 3\n";

static const char *dae(const char *name, const char *transparency)
{
    static char text[4096];
    snprintf(text, sizeof text,
             "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<COLLADA xmlns=\"http://www.collada.org/"
             "2005/11/COLLADASchema\" version=\"1.4.1\"><asset><up_axis>Y_UP</up_axis></asset>\n"
             "<library_effects><effect id=\"fx\"><profile_COMMON><technique sid=\"c\"><phong>"
             "<diffuse><color>0 0 1 1</color></diffuse><transparent opaque=\"A_ONE\"><color>1 1 1 1"
             "</color></transparent><transparency><float>%s</float></transparency></phong>"
             "</technique></profile_COMMON></effect></library_effects>\n<library_materials>"
             "<material id=\"mat\"><instance_effect url=\"#fx\"/></material></library_materials>\n"
             "<library_geometries><geometry id=\"g\"><mesh><source id=\"p\"><float_array id=\"pa\""
             " count=\"12\">-1 -1 0 1 -1 0 1 1 0 -1 1 0</float_array><technique_common><accessor "
             "source=\"#pa\" count=\"4\" stride=\"3\"><param name=\"X\" type=\"float\"/><param "
             "name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor>"
             "</technique_common></source><vertices id=\"v\"><input semantic=\"POSITION\" "
             "source=\"#p\"/></vertices><triangles material=\"m\" count=\"2\"><input semantic="
             "\"VERTEX\" source=\"#v\" offset=\"0\"/><p>0 1 2 0 2 3</p></triangles></mesh>"
             "</geometry></library_geometries>\n<library_visual_scenes><visual_scene id=\"s\">"
             "<node id=\"n\"><instance_geometry url=\"#g\"><bind_material><technique_common>"
             "<instance_material symbol=\"m\" target=\"#mat\"/></technique_common></bind_material>"
             "</instance_geometry></node></visual_scene></library_visual_scenes>\n<scene>"
             "<instance_visual_scene url=\"#s\"/></scene></COLLADA>\n",
             transparency);
    put(name, text, 0);
    return name;
}

/* A cube of 8 shared vertices and 12 triangles, no normals (binary PLY). */
static const char *cube_ply(void)
{
    static const char head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 8\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "element face 12\nproperty list uchar int vertex_indices\n"
                               "end_header\n";
    static const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5},
                                     {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6},
                                     {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    unsigned char buf[1024];
    size_t n = strlen(head);
    memcpy(buf, head, n);
    for (int v = 0; v < 8; v++) {
        float p[3] = {v & 4 ? 1.0f : -1.0f, v & 2 ? 1.0f : -1.0f, v & 1 ? 1.0f : -1.0f};
        memcpy(buf + n, p, 12);
        n += 12;
    }
    for (int f = 0; f < 12; f++) {
        buf[n++] = 3;
        memcpy(buf + n, faces[f], 12);
        n += 12;
    }
    put("cube.ply", buf, n);
    return "cube.ply";
}

/* ---- rendering ------------------------------------------------------------- */

/* The mesh file face on, filling the middle of a 32 x 32 image; each pixel
 * is the surface's colour (ambient 1, no lights, transfer none). */
static glint_film render_file(const char *file, const char *extra)
{
    char text[1024];
    snprintf(text, sizeof text,
             "image: {width: 32, height: 32, samples: 1, background: [0.5, 0.25, 0.125], "
             "transfer: none}\ncamera: {eye: [0, 0, 4], look_at: [0, 0, 0], up: [0, 1, 0], "
             "fov: 40}\nambient: 1\nobjects:\n  - {type: mesh, file: %s%s}\n",
             file, extra ? extra : "");
    const char *scene = put("scene.yaml", text, 0);
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_load(scene, &s, &err), GLINT_OK, "%s", err.msg);
    glint_film film = test_render(s, 32, 32, 1, 1);
    glint_scene_free(s);
    return film;
}

static void expect_pixel(const glint_film *f, int x, int y, float r, float g, float b,
                         const char *what)
{
    const float *p = f->rgb + 3 * ((size_t)y * f->width + x);
    cr_expect(fabsf(p[0] - r) < 0.02f && fabsf(p[1] - g) < 0.02f && fabsf(p[2] - b) < 0.02f,
              "%s: pixel (%d, %d) is (%.3f, %.3f, %.3f), want (%.3f, %.3f, %.3f)", what, x, y,
              (double)p[0], (double)p[1], (double)p[2], (double)r, (double)g, (double)b);
}

/* Red top left, green top right, blue bottom left, white bottom right. */
static void expect_texture(const glint_film *f, const char *what)
{
    expect_pixel(f, 12, 12, 1, 0, 0, what);
    expect_pixel(f, 19, 12, 0, 1, 0, what);
    expect_pixel(f, 12, 19, 0, 0, 1, what);
    expect_pixel(f, 19, 19, 1, 1, 1, what);
    expect_pixel(f, 1, 1, 0.5f, 0.25f, 0.125f, what); /* background around */
}

Test(mesh_files, obj_mtl_texture_is_used_upright)
{
    write_png();
    put("quad.mtl", quad_mtl, 0);
    put("quad.obj", quad_obj, 0);
    glint_film f = render_file("quad.obj", NULL);
    expect_texture(&f, "OBJ + MTL");
    glint_film_free(&f);
}

Test(mesh_files, gltf_embedded_png_is_used_upright)
{
    glint_film f = render_file(write_gltf(), NULL);
    expect_texture(&f, "glTF, embedded PNG");
    glint_film_free(&f);
}

Test(mesh_files, ply_vertex_colours_and_the_scene_material_overrides)
{
    put("colored.ply", colored_ply, 0);
    glint_film f = render_file("colored.ply", NULL);
    expect_pixel(&f, 16, 16, 0, 1, 0, "vertex colours");
    glint_film_free(&f);
    f = render_file("colored.ply", ", material: {color: [1, 0, 1]}");
    expect_pixel(&f, 16, 16, 1, 0, 1, "the scene's material");
    glint_film_free(&f);
}

Test(mesh_files, collada_transparency_0_and_1_are_opaque)
{
    /* 0: the exporters' inverted convention (a wholly invisible material);
     * 1: the specification's opaque */
    glint_film f = render_file(dae("t0.dae", "0"), NULL);
    expect_pixel(&f, 16, 16, 0, 0, 1, "transparency 0");
    glint_film_free(&f);
    f = render_file(dae("t1.dae", "1"), NULL);
    expect_pixel(&f, 16, 16, 0, 0, 1, "transparency 1");
    glint_film_free(&f);
    /* 0.25 alone follows the specification (A_ONE: opacity 0.25): three
     * quarters of the background shows through */
    mesh_file mf;
    glint_error err = {0};
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, dae("t25.dae", "0.25"));
    cr_assert_eq(mesh_import(path, NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_expect_float_eq(mf.materials[0].transmit, 0.75f, 1e-6f);
    mesh_file_free(&mf);
}

Test(mesh_files, files_without_materials_are_matte_white)
{
    const char *files[][2] = {{"plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
                              {"plain.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
                              {"plain.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"
                                            "property float x\nproperty float y\nproperty float z\n"
                                            "element face 1\nproperty list uchar int vertex_indices\n"
                                            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
                              {"plain.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                            "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                                            "endsolid t\n"}};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        mesh_file mf;
        glint_error err = {0};
        cr_assert_eq(mesh_import(put(files[i][0], files[i][1], 0), NULL, &mf, &err), GLINT_OK,
                     "%s", err.msg);
        for (int m = 0; m < mf.nmaterials; m++) {
            cr_expect(mf.materials[m].color.x == 1 && mf.materials[m].color.y == 1 &&
                          mf.materials[m].color.z == 1,
                      "%s: colour (%g, %g, %g)", files[i][0], (double)mf.materials[m].color.x,
                      (double)mf.materials[m].color.y, (double)mf.materials[m].color.z);
            cr_expect_eq(mf.materials[m].specular, 0.0f, "%s: specular %g", files[i][0],
                         (double)mf.materials[m].specular);
            cr_expect_eq(mf.materials[m].transmit, 0.0f, "%s", files[i][0]);
        }
        mesh_file_free(&mf);
    }
}

/* ---- normals --------------------------------------------------------------- */

/* The largest angle, in degrees, between a corner's normal and its triangle's. */
static double worst_corner(const mesh *m)
{
    double worst = 0;
    for (int t = 0; t < m->ntris; t++) {
        vec3 p0 = m->pos[m->tri[t][0]], p1 = m->pos[m->tri[t][1]], p2 = m->pos[m->tri[t][2]];
        vec3 n = v3_norm(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
        for (int k = 0; k < 3; k++) {
            double c = v3_dot(n, m->nrm[m->tri[t][k]]);
            double a = acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180 / M_PI;
            worst = a > worst ? a : worst;
        }
    }
    return worst;
}

Test(mesh_files, cube_without_normals_keeps_hard_edges)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, cube_ply());
    mesh_file mf;
    glint_error err = {0};
    cr_assert_eq(mesh_import(path, NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_assert_not_null(mf.mesh->nrm);
    cr_expect_eq(mf.mesh->nverts, 24, "a vertex per face corner: %d", mf.mesh->nverts);
    cr_expect_lt(worst_corner(mf.mesh), 1e-3, "30 degrees: corner %.3f degrees off its face",
                 worst_corner(mf.mesh));
    mesh_file_free(&mf);

    mesh_options smooth = {180, 0};
    cr_assert_eq(mesh_import(path, &smooth, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(mf.mesh->nverts, 8);
    /* each corner's normal is the cube's diagonal, 54.7 degrees off every face */
    cr_expect(fabs(worst_corner(mf.mesh) - 54.7356) < 0.01, "180 degrees: %.4f",
              worst_corner(mf.mesh));
    mesh_file_free(&mf);
}

Test(mesh_files, smooth_angle_is_checked_in_scenes)
{
    put("cube.yaml", "objects: [{type: mesh, file: cube.ply, smooth_angle: 200}]\n", 0);
    cube_ply();
    char path[512];
    snprintf(path, sizeof path, "%s/cube.yaml", dir);
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_load(path, &s, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "cube.yaml:1:54: smooth_angle must be at most 180 degrees"), "%s",
              err.msg);
}

/* ---- bad files --------------------------------------------------------------- */

/* OK, or GLINT_ERR_INPUT with one line starting with the path. */
static void expect_harmless(const char *path)
{
    mesh_file mf;
    glint_error err = {0};
    glint_rc rc = mesh_import(path, NULL, &mf, &err);
    if (rc == GLINT_OK) {
        cr_expect_gt(mf.mesh->ntris, 0);
        mesh_file_free(&mf);
        return;
    }
    cr_expect_eq(rc, GLINT_ERR_INPUT, "%s: %s", path, err.msg);
    cr_expect(strncmp(err.msg, path, strlen(path)) == 0 && !strchr(err.msg, '\n'), "%s", err.msg);
}

/* A triangle in glTF: the buffer inline, no image (kept short for the cuts). */
static const char tri_gltf[] =
    "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],\"buffers\":[{"
    "\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAA"
    "AAAAAAAAAAAAAAAAgD8AAAAA\"}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
    "\"min\":[0,0,0],\"max\":[1,1,0]}]}";

/* Each file cut at every 7th byte (every 21st under AddressSanitizer, which
 * makes each import several times slower). */
Test(mesh_files, truncations_never_crash_or_hang)
{
#ifdef __SANITIZE_ADDRESS__
    const size_t step = 21;
#else
    const size_t step = 7;
#endif
    write_png();
    put("quad.mtl", quad_mtl, 0);
    put("colored.ply", colored_ply, 0);
    put("tri.gltf", tri_gltf, 0);
    expect_harmless(put("tri.gltf", tri_gltf, 0)); /* whole, it imports */
    const char *names[] = {"quad.obj", "tri.gltf", "colored.ply", cube_ply(), dae("t0.dae", "0"),
                           "cube.off"};
    put("quad.obj", quad_obj, 0);
    put("cube.off", "OFF\n8 6 0\n-1 -1 -1\n-1 -1 1\n-1 1 -1\n-1 1 1\n1 -1 -1\n1 -1 1\n1 1 -1\n"
                    "1 1 1\n4 0 1 3 2\n4 4 6 7 5\n4 0 4 5 1\n4 2 3 7 6\n4 0 2 6 4\n4 1 5 7 3\n",
        0);
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char full[512], cut[512];
        snprintf(full, sizeof full, "%s/%s", dir, names[i]);
        size_t n;
        unsigned char *bytes = slurp(full, &n);
        unsigned char *copy = malloc(n);
        memcpy(copy, bytes, n);
        const char *dot = strrchr(names[i], '.');
        for (size_t k = 0; k < n; k += step) {
            snprintf(cut, sizeof cut, "cut%s", dot);
            expect_harmless(put(cut, copy, k ? k : 1));
        }
        free(copy);
    }
}

Test(mesh_files, two_billion_declared_vertices_fail_at_once)
{
    struct rusage before, after;
    getrusage(RUSAGE_SELF, &before);
    const char *ply = put("big.ply",
                          "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
                          "0 1 0\n3 0 1 2\n",
                          0);
    const char *off = put("big.off", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 0);
    const char *paths[] = {ply, off};
    for (int i = 0; i < 2; i++) {
        mesh_file mf;
        glint_error err = {0};
        cr_expect_eq(mesh_import(paths[i], NULL, &mf, &err), GLINT_ERR_INPUT);
        cr_expect(strstr(err.msg, "2000000000 vertices"), "%s", err.msg);
    }
    /* the size is refused from the header: no allocation, no importer */
    getrusage(RUSAGE_SELF, &after);
    cr_expect_lt(after.ru_maxrss - before.ru_maxrss, 64 * 1024, "grew by %ld KiB",
                 after.ru_maxrss - before.ru_maxrss);
    struct rusage kids;
    getrusage(RUSAGE_CHILDREN, &kids);
    cr_expect_lt(kids.ru_maxrss, 256 * 1024, "a child grew to %ld KiB", kids.ru_maxrss);
}

Test(mesh_files, fifo_is_refused_without_blocking)
{
    char path[512];
    snprintf(path, sizeof path, "%s/pipe.obj", dir);
    cr_assert_eq(mkfifo(path, 0600), 0);
    mesh_file mf;
    glint_error err = {0};
    cr_expect_eq(mesh_import(path, NULL, &mf, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "pipe.obj: cannot open mesh: not a regular file"), "%s", err.msg);
    /* and one named by a model (an OBJ's material library) is passed over */
    char mtl[512];
    snprintf(mtl, sizeof mtl, "%s/pipe.mtl", dir);
    cr_assert_eq(mkfifo(mtl, 0600), 0);
    expect_harmless(put("named.obj", "mtllib pipe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 0));
}

/* A PLY of n vertices at the origin in n / 3 triangles. */
static const char *big_ply(const char *name, uint32_t n)
{
    char head[256];
    int h = snprintf(head, sizeof head,
                     "ply\nformat binary_little_endian 1.0\nelement vertex %u\n"
                     "property float x\nproperty float y\nproperty float z\n"
                     "element face %u\nproperty list uchar int vertex_indices\nend_header\n",
                     n, n / 3);
    size_t size = (size_t)h + (size_t)n * 12 + (size_t)(n / 3) * 13;
    unsigned char *b = calloc(1, size);
    cr_assert_not_null(b);
    memcpy(b, head, (size_t)h);
    for (uint32_t f = 0; f < n / 3; f++) {
        unsigned char *at = b + h + (size_t)n * 12 + (size_t)f * 13;
        at[0] = 3;
        for (uint32_t k = 0; k < 3; k++)
            for (int i = 0; i < 4; i++) /* little-endian, as the header says */
                at[1 + 4 * k + i] = (unsigned char)((3 * f + k) >> (8 * i));
    }
    const char *path = put(name, b, size);
    free(b);
    return path;
}

Test(mesh_files, limits_come_from_the_environment)
{
    put("colored.ply", colored_ply, 0);
    char path[512];
    snprintf(path, sizeof path, "%s/colored.ply", dir);
    mesh_file mf;
    glint_error err = {0};
    setenv("GLINT_MESH_TRIANGLES", "1", 1);
    cr_expect_eq(mesh_import(path, NULL, &mf, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "colored.ply: mesh is too large") &&
                  strstr(err.msg, "GLINT_MESH_TRIANGLES raises it"),
              "%s", err.msg);
    setenv("GLINT_MESH_TRIANGLES", "2", 1);
    cr_expect_eq(mesh_import(path, NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    mesh_file_free(&mf);
    unsetenv("GLINT_MESH_TRIANGLES");
    setenv("GLINT_MESH_TRUSTED", "1", 1); /* in this process: the same result */
    cr_expect_eq(mesh_import(path, NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(mf.mesh->ntris, 2);
    mesh_file_free(&mf);
    unsetenv("GLINT_MESH_TRUSTED");
#ifndef __SANITIZE_ADDRESS__ /* AddressSanitizer's shadow memory rules out a memory limit */
    /* 300000 vertices in 100000 triangles. Forked from this process, which
     * has run other tests, the child may build them in heap it inherits
     * free; a mesh bigger than the limit is over it all the same (a fresh
     * glint's child runs out: the_memory_limit_stops_the_importer) */
    const char *large = big_ply("large.ply", 300000);
    setenv("GLINT_MESH_MEMORY", "1", 1);
    cr_expect_eq(mesh_import(large, NULL, &mf, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "large.ply: the importer ran out of its 1 MiB of memory "
                              "(GLINT_MESH_MEMORY raises the limit)"),
              "%s", err.msg);
    unsetenv("GLINT_MESH_MEMORY");
#endif
}

Test(mesh_files, dropped_triangles_and_short_files_are_counted)
{
    mesh_file mf;
    glint_error err = {0};
    const char *bad = put("bad.obj",
                          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nv 1e38 0 0\nv 0 1e38 0\n"
                          "v 2 0 0\nf 1 2 3\nf 4 2 3\nf 1 5 6\nf 1 2 7\n",
                          0);
    cr_assert_eq(mesh_import(bad, NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_expect(strstr(mf.warnings, "bad.obj: 3 of 4 triangles dropped (1 with NaN or infinite "
                                  "corners, 1 of zero area, 1 too large for single "
                                  "precision (overflow))\n"),
              "%s", mf.warnings);
    mesh_file_free(&mf);
    const char *shorter = put("short.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 2\n"
                              "property list uchar int vertex_indices\nend_header\n0 0 0\n"
                              "1 0 0\n0 1 0\n3 0 1 2\n",
                              0);
    cr_assert_eq(mesh_import(shorter, NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_expect(strstr(mf.warnings, "short.ply: the header declares 2 faces but the file holds 1"),
              "%s", mf.warnings);
    mesh_file_free(&mf);
}

Test(mesh_files, a_missing_texture_is_a_warning)
{
    put("quad.mtl", quad_mtl, 0); /* names tex.png, which is not there */
    put("quad.obj", quad_obj, 0);
    put("scene.yaml", "objects: [{type: mesh, file: quad.obj}]\n", 0);
    char path[512];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_load(path, &s, &err), GLINT_OK, "%s", err.msg);
    cr_expect(strstr(glint_scene_warnings(s), "quad.obj: texture not used: ") &&
                  strstr(glint_scene_warnings(s), "tex.png"),
              "%s", glint_scene_warnings(s));
    glint_scene_free(s);
}

/* Inputs that crashed, hung or leaked in the fuzz target (fuzz/fuzz_mesh.c):
 * assimp aborting in a PLY's post-processing or dereferencing bad pointers
 * on a Collada and a glTF file (contained by the child process), a PLY
 * header that spun the importer, a mesh too small for the BVH's bins, a
 * failure that leaked its materials. */
Test(mesh_files, fuzz_findings_stay_harmless)
{
    static const char *const files[] = {"abort-postprocess-1.ply", "abort-postprocess-2.ply",
                                        "abort-postprocess-3.ply", "segv-binary.ply",
                                        "header-spin.ply", "tiny-extent.stl",
                                        "no-usable-triangles.ply", "segv-collada.dae",
                                        "segv-gltf.gltf"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/tests/mesh-regress/%s", GLINT_SOURCE_DIR, files[i]);
        expect_harmless(path);
    }
    char path[512];
    snprintf(path, sizeof path, "%s/tests/mesh-regress/abort-postprocess-1.ply", GLINT_SOURCE_DIR);
    mesh_file mf;
    glint_error err = {0};
    cr_expect_eq(mesh_import(path, NULL, &mf, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "abort-postprocess-1.ply: the importer failed (truncated or "
                              "corrupt file?)"),
              "%s", err.msg);
}

Test(mesh_files, wire_form_refuses_a_corrupted_reply)
{
    mesh_data md = {.nverts = 3, .ntris = 1, .nmats = 1, .ntexs = 0, .flags = MESH_HAS_NORMALS};
    glint_error err = {0};
    cr_assert_eq(mesh_data_alloc(&md, &err), GLINT_OK);
    for (int k = 0; k < 3; k++)
        md.tri[0][k] = (uint32_t)k;
    md.pos[1][0] = 1;
    md.pos[2][1] = 1;
    md.mats[0].texture = -1;
    size_t n = mesh_data_wire_size(&md, SIZE_MAX);
    uint8_t *buf = malloc(n);
    mesh_data_encode(&md, buf);
    mesh_data back;
    cr_expect_eq(mesh_data_decode(buf, n, "m", &back, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(back.ntris, 1);
    mesh_data_free(&back);
    cr_expect_eq(mesh_data_decode(buf, n - 1, "m", &back, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, "m: the importer handed back a malformed mesh");
    md.tri[0][2] = 3; /* past the vertices */
    mesh_data_encode(&md, buf);
    cr_expect_eq(mesh_data_decode(buf, n, "m", &back, &err), GLINT_ERR_INPUT);
    md.tri[0][2] = 2;
    md.mats[0].texture = 0; /* no such texture */
    mesh_data_encode(&md, buf);
    cr_expect_eq(mesh_data_decode(buf, n, "m", &back, &err), GLINT_ERR_INPUT);
    free(buf);
    mesh_data_free(&md);
}

#ifndef __SANITIZE_ADDRESS__ /* AddressSanitizer's shadow memory rules out a memory limit */
/* A fresh glint's importer, given 1 MiB, runs out of it on 300000 vertices
 * and the user is told which limit to raise. */
Test(mesh_files, the_memory_limit_stops_the_importer)
{
    big_ply("big.ply", 300000);
    static const char scene[] = "objects:\n  - {type: mesh, file: big.ply}\n";
    put("big.yaml", scene, 0);
    char out[2048];
    int code = glint_run("GLINT_MESH_MEMORY=1", "-q -r 8x8 -o big.png big.yaml", out, sizeof out);
    cr_expect_eq(code, 2, "%s", out);
    cr_expect(strstr(out, "big.ply: the importer ran out of its 1 MiB of memory "
                          "(GLINT_MESH_MEMORY raises the limit)"),
              "%s", out);
    cr_expect(!dir_has("big.png"));
}
#endif

/* Corners equal in every attribute, bit for bit, become one vertex,
 * numbered in the order they first appear; a corner differing in anything
 * (a texture coordinate, the sign of a zero) stays its own. */
Test(mesh_files, corners_join_when_every_attribute_matches)
{
    mesh_data md = {.nverts = 7, .ntris = 2, .nmats = 1, .flags = MESH_HAS_NORMALS | MESH_HAS_UV};
    glint_error err = {0};
    cr_assert_eq(mesh_data_alloc(&md, &err), GLINT_OK);
    /* vertex 0 is before the range joined: left alone */
    static const float pos[7][3] = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                    {1, 0, 0}, {0, 1, 0}, {-0.0f, 0, 0}};
    static const float uv[7][2] = {{0, 0}, {0, 0}, {1, 0}, {0, 1}, {1, 0}, {0.5f, 1}, {0, 0}};
    for (int v = 0; v < 7; v++) {
        memcpy(md.pos[v], pos[v], sizeof pos[v]);
        memcpy(md.uv[v], uv[v], sizeof uv[v]);
        md.nrm[v][2] = 1;
    }
    static const uint32_t tri[2][3] = {{1, 2, 3}, {4, 5, 6}};
    memcpy(md.tri, tri, sizeof tri);
    uint32_t nv = 6;
    cr_assert(mesh_join_vertices(&md, 1, &nv, 0, 2));
    cr_expect_eq(nv, 5, "vertex 4 is vertex 2 again; 5 (another uv) and 6 (-0) are not: %u", nv);
    static const uint32_t want[2][3] = {{1, 2, 3}, {2, 4, 5}};
    for (int t = 0; t < 2; t++)
        for (int k = 0; k < 3; k++)
            cr_expect_eq(md.tri[t][k], want[t][k], "triangle %d corner %d: %u", t, k,
                         md.tri[t][k]);
    static const int from[6] = {0, 1, 2, 3, 5, 6}; /* where each kept vertex came from */
    for (int v = 0; v < 6; v++) {
        cr_expect(memcmp(md.pos[v], pos[from[v]], sizeof pos[0]) == 0, "position %d", v);
        cr_expect(memcmp(md.uv[v], uv[from[v]], sizeof uv[0]) == 0, "uv %d", v);
    }
    mesh_data_free(&md);
}

/* An OBJ gives assimp a vertex per face corner; a quad of two triangles
 * sharing an edge comes back with its 4 corners, with or without normals
 * in the file. */
Test(mesh_files, shared_corners_of_an_obj_are_one_vertex)
{
    static const char quad[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
                               "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n";
    static const char bare[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
    const char *files[] = {put("quad.obj", quad, 0), put("bare.obj", bare, 0)};
    for (int i = 0; i < 2; i++) {
        mesh_file mf;
        glint_error err = {0};
        cr_assert_eq(mesh_import(files[i], NULL, &mf, &err), GLINT_OK, "%s", err.msg);
        cr_expect_eq(mf.mesh->ntris, 2);
        cr_expect_eq(mf.mesh->nverts, 4, "%s: %d vertices", files[i], mf.mesh->nverts);
        mesh_file_free(&mf);
    }
}

/* Two objects of one OBJ, the first with texture coordinates and the
 * second without: the second's corners get (0, 0), not what the first
 * left in the slots they reuse, and its shared corners are one vertex. A
 * vertex no triangle uses is dropped. */
Test(mesh_files, a_mesh_without_uvs_gets_zeros_and_unused_vertices_go)
{
    static const char ab[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                             "vt 0.1 0.2\nvt 0.3 0.4\nvt 0.5 0.6\nvt 0.7 0.8\n"
                             "o A\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\no B\nf 1 2 3\nf 1 3 4\n";
    static const char unused[] = "ply\nformat ascii 1.0\nelement vertex 5\n"
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "property float nx\nproperty float ny\nproperty float nz\n"
                                 "element face 1\nproperty list uchar int vertex_indices\n"
                                 "end_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n"
                                 "7 7 7 0 0 1\n8 8 8 0 0 1\n3 0 1 2\n";
    mesh_file mf;
    glint_error err = {0};
    cr_assert_eq(mesh_import(put("ab.obj", ab, 0), NULL, &mf, &err), GLINT_OK, "%s", err.msg);
    cr_assert_not_null(mf.mesh->uv);
    cr_expect_eq(mf.mesh->nverts, 8, "4 corners each: %d", mf.mesh->nverts);
    int zero = 0;
    for (int v = 0; v < mf.mesh->nverts; v++)
        zero += mf.mesh->uv[v][0] == 0.0f && mf.mesh->uv[v][1] == 0.0f;
    cr_expect_eq(zero, 4, "B's 4 corners at (0, 0): %d", zero);
    mesh_file_free(&mf);
    cr_assert_eq(mesh_import(put("unused.ply", unused, 0), NULL, &mf, &err), GLINT_OK, "%s",
                 err.msg);
    cr_expect_eq(mf.mesh->nverts, 3, "%d", mf.mesh->nverts);
    mesh_file_free(&mf);
}

/* libFuzzer target for mesh import: everything glint does with a model
 * file's bytes, in one process so coverage guides the search.
 *
 * The first byte chooses what the rest is: a model file in one of the
 * formats below (the name's extension tells assimp and glint's conventions
 * the format), or, for the last choice, the wire form a child process hands
 * back (mesh_data.h), which the parent must survive whatever it holds. A
 * model goes through the header checks (mesh_precheck), assimp
 * (mesh_assimp_read, as in the child), the wire form and back, the parent's
 * checks (mesh_file_from_data) and its textures into a scene
 * (mesh_file_add, embedded images through the image readers).
 *
 * assimp itself is not instrumented, so coverage counts glint's code only;
 * a crash inside assimp is what the child process exists to contain, and
 * the campaign runs with -fork so it goes on after one. Seeds: the test
 * meshes in fuzz/seeds-mesh, each prefixed with its format's byte by
 * `make fuzz TARGET=mesh`. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "load/mesh_assimp.h"
#include "load/mesh_data.h"
#include "load/mesh_import.h"
#include "load/mesh_limits.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* In the order of the prefix byte; keep in step with the Makefile's seeds. */
static const char *const names[] = {"fuzz.ply", "fuzz.obj", "fuzz.off", "fuzz.stl",
                                    "fuzz.gltf", "fuzz.glb", "fuzz.dae", "fuzz.3ds",
                                    "fuzz.fbx", "fuzz.x", "fuzz.ac", "fuzz.3mf"};
#define NFORMATS (sizeof names / sizeof names[0])

static void use(mesh_data *md, const char *name)
{
    mesh_file mf = {0};
    glint_error err = {0};
    if (mesh_file_from_data(md, name, 1, &mf, &err) != GLINT_OK) {
        if (!err.msg[0] || mf.mesh)
            abort();
        return;
    }
    scene *s = scene_new();
    int index;
    if (s && mesh_file_add(s, &mf, &index, &err) == GLINT_OK &&
        scene_mesh(s, index)->ntris <= 0)
        abort();
    scene_free(s);
    mesh_file_free(&mf);
}

static void wire(const uint8_t *data, size_t size)
{
    mesh_data md;
    glint_error err = {0};
    if (mesh_data_decode(data, size, "fuzz", &md, &err) == GLINT_OK) {
        use(&md, "fuzz");
        mesh_data_free(&md);
    } else if (!err.msg[0]) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    unsigned pick = data[0] % (NFORMATS + 1);
    data++, size--;
    if (pick == NFORMATS) {
        wire(data, size);
        return 0;
    }
    const char *name = names[pick];
    mesh_limits lim = {MESH_DEFAULT_MEMORY_MIB, MESH_DEFAULT_SECONDS, 1u << 20, true};
    glint_error err = {0};
    size_t head = size < MESH_HEAD_BYTES ? size : MESH_HEAD_BYTES;
    mesh_header hdr;
    if (mesh_precheck(name, (const char *)data, head, size, &lim, &hdr, &err) != GLINT_OK)
        return 0;
    mesh_assimp_opts opts = {30.0f, lim.triangles};
    mesh_data md;
    if (mesh_assimp_read(name, data, size, &opts, &md, &err) != GLINT_OK) {
        if (!err.msg[0])
            abort();
        return 0;
    }
    size_t n = mesh_data_wire_size(&md, SIZE_MAX);
    uint8_t *buf = n ? malloc(n) : NULL;
    if (buf) {
        mesh_data_encode(&md, buf);
        wire(buf, n);
        /* a reply cut short, as from a child that died while writing */
        wire(buf, n - 1 - (size_t)(data[0] % (n < 64 ? n : 64)));
    }
    free(buf);
    mesh_data_free(&md);
    return 0;
}

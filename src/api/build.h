/* build: what the parts of building a scene in code share (build.c for
 * materials, lights, objects and meshes; build_shapes.c, build_csg.c,
 * build_textures.c, steps.c). Each checks its input with the scene
 * format's rules and says what is wrong in a GLINT_ERR_INPUT whose message
 * names the function and, inside a csg or a texture, where. */
#ifndef GLINT_API_BUILD_H
#define GLINT_API_BUILD_H

#include "glint.h"
#include "core/mat4.h"
#include "geom/shape.h"
#include "scene/scene.h"

/* The transform of nsteps steps, the first applied first (identity for
 * none); messages start with where ("" or "operands[1]."). */
glint_rc api_xform(const char *fn, const char *where, const glint_step *steps, int nsteps,
                   xform *out, glint_error *err);

/* The shape of an object (not a csg); a polyhedron joins the scene. */
glint_rc api_shape(glint_scene *s, const char *fn, const char *where, const glint_shape *in,
                   shape *out, glint_error *err);

/* A csg object: its tree joins the scene and the object places it with
 * the transform x (NULL: none), which joins the scene only once the tree
 * is whole; *index gets the object. */
glint_rc api_add_csg(glint_scene *s, const glint_object *in, const xform *x, int *index,
                     glint_error *err);

/* Stores the index of a new element, or says memory ran out (i < 0). */
glint_rc api_added(int i, int *index, glint_error *err);

#endif

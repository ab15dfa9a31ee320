#include "options.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli/rerun.h"

static const char usage_head[] =
    "usage: mpirun -n K glint-mpi [options] [SCENE.yaml]\n"
    "Renders SCENE.yaml, or with no scene the built-in nine-object scene, with K\n"
    "processes (K = 1 without mpirun); writes the same image as glint.\n"
    "\n";

static const char usage_tail[] =
    "\n"
    "glint's preview window (-p, --exit-when-done, --preview-bench) is not here.\n"
    "Exit status: 0 success, 1 runtime failure, 2 bad usage or bad input;\n"
    "130 or 143 after Ctrl-C or SIGTERM: the render so far is kept in OUTPUT.resume.\n";

/* The note of a resume file, read by rank 0 and sent to every process: its
 * length, or -1 after a failure and then the message. */
static glint_rc share_note(const char *path, int rank, char **note, size_t *len,
                           glint_error *err)
{
    glint_rc rc = rank == 0 ? rerun_note_read(path, note, len, err) : GLINT_OK;
    long long n[2] = {rc == GLINT_OK ? (long long)*len : -1, (long long)rc};
    MPI_Bcast(n, 2, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    if (n[0] < 0) {
        MPI_Bcast(err->msg, (int)sizeof err->msg, MPI_CHAR, 0, MPI_COMM_WORLD);
        return err->code = (glint_rc)n[1];
    }
    if (rank != 0 && !(*note = malloc((size_t)n[0])))
        MPI_Abort(MPI_COMM_WORLD, 1); /* a command line: the process is in no state to go on */
    *len = (size_t)n[0];
    MPI_Bcast(*note, (int)n[0], MPI_CHAR, 0, MPI_COMM_WORLD);
    return GLINT_OK;
}

/* 'glint-mpi --resume OUT.resume': the command line the file keeps, with
 * --resume. Returns -1 to go on. */
static int rerun(const cli_program *p, int rank, struct cli *c, char ***kept)
{
    glint_error err = {0};
    char *note = NULL;
    size_t len = 0;
    glint_rc rc = share_note(c->scene_path, rank, &note, &len, &err);
    int code = rerun_parse(p, c, rc, note, len, &err, kept);
    free(note);
    return code;
}

int dist_parse_options(int argc, char **argv, int rank, struct cli *c, char ***kept)
{
    /* rank 0's program speaks, the others' are silent */
    static const cli_program speaks = {"glint-mpi", CLI_MPI, usage_head, usage_tail, true};
    static const cli_program silent = {"glint-mpi", CLI_MPI, usage_head, usage_tail, false};
    const cli_program *p = rank == 0 ? &speaks : &silent;
    *kept = NULL;
    int code = cli_parse(p, argc, argv, c);
    if (code < 0 && rerun_wanted(c))
        code = rerun(p, rank, c, kept);
    if (code < 0 && c->frames && c->tile_costs)
        code = cli_usage_error(p, "--tile-costs records a single image, not --frames");
    return code;
}

glint_rc dist_settings(const glint_scene *scene, const struct cli *o, glint_settings *s,
                       glint_error *err)
{
    glint_rc rc = glint_scene_settings(scene, s, err);
    if (rc != GLINT_OK)
        return rc;
    cli_settings(o, s);
    if (s->threads == 0) /* the cores this process may run on: mpirun binds it to its share */
        s->threads = glint_default_threads();
    return glint_settings_check(s, err);
}

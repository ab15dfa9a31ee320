/* batch: helpers of the batch render shared with main.c: resume files
 * beside the output and the command line they keep. */
#ifndef GLINT_APP_BATCH_H
#define GLINT_APP_BATCH_H

#include "glint.h"

/* OUTPUT.resume, malloc'd; NULL for standard output ("-"). */
char *batch_resume_path(const char *output);

/* The command line a resume file keeps: its arguments (argv[0] first, a
 * NULL after the last, all in one allocation to free with free(*argv)),
 * after changing to the folder it was run from. */
glint_rc batch_resume_args(const char *path, int *argc, char ***argv, glint_error *err);

#endif

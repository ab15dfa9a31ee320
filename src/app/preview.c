#include "cli.h"

int preview_main(const struct cli *c) { return batch_main(c); }

/* SPDX-License-Identifier: MIT */
/* cli.c - the command line of periscope-render's 3D modes (render/cli.h). */
#include "render/cli.h"
#include "psc_io_cli.h"

#include <string.h>

/* Options whose value is a file the tool writes: never the model, whatever its name (--dump-obj tess.obj). */
static bool names_an_output(const char *option)
{
    static const char *const outputs[] = {"-o", "--dump-obj", "--dump-ao", "--depth", "--ids"};
    for (size_t k = 0; k < sizeof outputs / sizeof outputs[0]; k++)
        if (strcmp(option, outputs[k]) == 0)
            return true;
    return false;
}

bool psc_render_cli_has_file(int argc, char **argv, bool (*is)(const char *path))
{
    for (int i = 1; i < argc; i++)
        if (argv[i][0] != '-' && is(argv[i]) && !names_an_output(argv[i - 1]))
            return true;
    return false;
}

bool psc_render_cli_has_option(int argc, char **argv, const char *name)
{
    size_t n = strlen(name);
    for (int i = 1; i < argc; i++)
        if (strncmp(argv[i], name, n) == 0 && (argv[i][n] == '\0' || argv[i][n] == '='))
            return true;
    return false;
}

int psc_render_cli_parse(const psc_render_cli_t *cli, const char *prog, int argc, char **argv, psc_render_view_t *view,
                         const char **model, const char **out, void *args)
{
    static const struct option view_options[] = {PSC_RENDER_VIEW_OPTIONS}, common[] = {PSC_IO_CLI_COMMON_OPTIONS};
    enum { NVIEW = sizeof view_options / sizeof view_options[0], NCOMMON = sizeof common / sizeof common[0] };
    struct option table[NVIEW + PSC_RENDER_CLI_MAX_OPTIONS + NCOMMON];
    size_t n = 0;

    memcpy(table, view_options, sizeof view_options);
    n = NVIEW;
    for (const struct option *o = cli->options; o && o->name; o++) {
        if (n >= NVIEW + PSC_RENDER_CLI_MAX_OPTIONS)
            return psc_io_cli_usage_error(prog, "internal: more than %d options in%s", PSC_RENDER_CLI_MAX_OPTIONS,
                                          cli->mode);
        table[n++] = *o;
    }
    memcpy(&table[n], common, sizeof common);

    psc_io_cli_t c;
    int opt;
    *out = NULL;
    psc_io_cli_begin(&c, argc, argv, "ho:", table);
    while ((opt = psc_io_cli_next_option(&c, prog, cli->mode, cli->usage)) > 0) {
        int rc = psc_render_view_option(prog, c.name, c.arg, view);
        if (rc < 0)
            rc = strcmp(c.name, "-o") == 0 ? (*out = c.arg, 0) : cli->option(prog, c.name, c.arg, args);
        if (rc != 0)
            return rc;
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    int rc = psc_io_cli_one_file(&c, prog, cli->what, model);
    if (rc != 0)
        return rc;
    if (!*out)
        return psc_io_cli_usage_error(prog, "no output given (-o view.png)");
    return 0;
}

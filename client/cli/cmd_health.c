/*
 * cmd_health.c - `refract health`: asks refractd whether it is up and prints its
 * status JSON (version, GPU vendor, renderer and driver). The quickest check that
 * --url points at a working daemon.
 */
#include <stdlib.h>

#include "cli.h"

static int run_health(struct cli *cli, int argc, char **argv)
{
    struct cli_parsed p;
    char *json = NULL;
    int code = cli_parse_command(&cli_cmd_health, argc, argv, NULL, 0, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&cli_cmd_health, &p, 0, 0, NULL);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_health(cli->client, &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}

const struct cli_command cli_cmd_health = {
    .name = "health",
    .synopsis = "health",
    .summary = "show whether refractd is up, its version and its GPU",
    .usage = "usage: refract health\n"
             "\n"
             "Asks refractd for its status and prints the JSON reply on stdout: status,\n"
             "version and the GPU it renders with (vendor, renderer, version, device).\n"
             "\n"
             "Example:\n"
             "  refract --url http://127.0.0.1:8750 health\n",
    .run = run_health,
};

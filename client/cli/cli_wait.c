/*
 * cli_wait.c - waiting for a scene's irradiance volumes with a progress display, shared
 * by `refract light set` (after a pose change) and `refract irradiance wait`.
 */
#include <stdlib.h>
#include <unistd.h>

#include "cli.h"
#include "cli_irradiance.h"

#define WAIT_DEFAULT_MS 120000L

static void show_progress(const struct refract_irradiance *status, void *user)
{
    cli_progress_update(user, status);
}

int cli_wait_irradiance(struct cli *cli, const char *scene, struct refract_irradiance *status)
{
    struct cli_progress progress;
    struct refract_wait_options opts = {
        .timeout_ms = cli->timeout_ms >= 0 ? cli->timeout_ms : WAIT_DEFAULT_MS,
        .progress = show_progress,
        .user = &progress,
    };
    struct refract_irradiance final = {0};
    int code;

    if (refract_irradiance_settled(status))
        return REFRACT_E_OK;
    cli_progress_init(&progress, stderr, isatty(2), cli_terminal_columns(2));
    cli_progress_update(&progress, status);
    code = refract_irradiance_wait(cli->client, scene, &opts, &final);
    cli_progress_finish(&progress);
    if (code != REFRACT_E_OK) {
        refract_irradiance_free(&final);
        return code;
    }
    final.http_status = status->http_status; /* what the first answer said */
    refract_irradiance_free(status);
    *status = final;
    return REFRACT_E_OK;
}

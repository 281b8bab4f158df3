/*
 * cmd_events.c - `refract events`: prints refractd's Server-Sent Events as they happen,
 * one line each, "ID TYPE DATA", for scripts (`refract events S --type irradiance.ready
 * --count 1` waits for a volume) and for watching what a daemon does.
 *
 * Filtering by type happens here, not in refractd: the event stream has no such
 * parameter, and the events are small.
 */
#include <stdio.h>
#include <string.h>

#include "cli.h"

#define EVENTS_USAGE                                                                               \
    "usage: refract events [SCENE] [--count N] [--since ID] [--type TYPE[,TYPE...]]\n"             \
    "\n"                                                                                           \
    "Prints refractd's events as they happen, one line each: ID TYPE DATA, where DATA\n"           \
    "is one JSON object. Without SCENE every event; with SCENE that scene's (its\n"                \
    "scene.*, irradiance.* and job events). Runs until interrupted, until N events were\n"         \
    "printed (--count), or until refractd ends the stream (a scene's ends when the scene\n"        \
    "is deleted). Types: scene.created, scene.updated, scene.deleted, irradiance.progress,\n"      \
    "irradiance.ready, irradiance.failed, job.progress, and lost (some events after\n"             \
    "--since are no longer in refractd's history).\n"                                              \
    "\n"                                                                                           \
    "  --count N         exit after printing N events\n"                                           \
    "  --since ID        first the events after ID still in refractd's history\n"                  \
    "                    (0 = all of it), then the new ones\n"                                     \
    "  --type LIST       print only events of these types (comma-separated)\n"                     \
    "\n"                                                                                           \
    "--timeout bounds the silence (default 120 s; refractd sends a keep-alive every\n"             \
    "15 s; 0 = none).\n"                                                                           \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract events\n"                                                                           \
    "  refract events \"$ID\" --type irradiance.ready --count 1   # wait for a volume\n"

static int run_events(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_events = {
    .name = "events",
    .synopsis = "events [SCENE]",
    .summary = "print refractd's events as they happen",
    .usage = EVENTS_USAGE,
    .run = run_events,
};

enum events_opt { OPT_COUNT_N, OPT_SINCE, OPT_TYPE, OPT_COUNT };

struct events_run {
    long want; /* 0 = no limit */
    long printed;
    const char *types; /* comma-separated list, or NULL for all */
    int code;          /* set when printing failed */
};

/* True when type is one of the comma-separated list's entries. */
static bool type_listed(const char *list, const char *type)
{
    size_t len = strlen(type);

    for (const char *p = list; *p != '\0';) {
        size_t n = strcspn(p, ",");

        if (n == len && strncmp(p, type, len) == 0)
            return true;
        p += n;
        if (*p == ',')
            p++;
    }
    return false;
}

static int on_event(const struct refract_event *ev, void *user)
{
    struct events_run *r = user;

    if (r->types != NULL && !type_listed(r->types, ev->type))
        return 0;
    printf("%s %s %s\n", ev->id[0] != '\0' ? ev->id : "-", ev->type, ev->data);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        r->code = cli_fail(REFRACT_E_IO, "events: cannot write to stdout");
        return 1;
    }
    r->printed++;
    return r->want > 0 && r->printed >= r->want;
}

static int run_events(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"SCENE"};
    struct cli_opt opts[OPT_COUNT] = {
        [OPT_COUNT_N] = {.name = "--count", .takes_value = true},
        [OPT_SINCE] = {.name = "--since", .takes_value = true},
        [OPT_TYPE] = {.name = "--type", .takes_value = true},
    };
    struct events_run r = {0};
    struct cli_parsed p;
    char why[256] = "";
    long since = 0;
    int code = cli_parse_command(&cli_cmd_events, argc, argv, opts, OPT_COUNT, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&cli_cmd_events, &p, 0, 1, names);
    if (code != REFRACT_E_OK)
        return code;
    if (opts[OPT_COUNT_N].given &&
        !cli_parse_long(opts[OPT_COUNT_N].value, 1, 1000000000, &r.want, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_events, "events: --count: %s", why);
    if (opts[OPT_SINCE].given &&
        !cli_parse_long(opts[OPT_SINCE].value, 0, 2147483647, &since, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_events, "events: --since: %s", why);
    if (opts[OPT_TYPE].given && opts[OPT_TYPE].value[0] == '\0')
        return cli_usage_error(&cli_cmd_events, "events: --type: expected event types such as "
                                                "scene.updated,irradiance.ready");
    r.types = opts[OPT_TYPE].value;
    code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_events(cli->client, p.n_pos > 0 ? p.pos[0] : NULL,
                          opts[OPT_SINCE].given ? opts[OPT_SINCE].value : NULL, on_event, &r);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    if (r.code != REFRACT_E_OK)
        return r.code;
    if (r.want > 0 && r.printed < r.want)
        return cli_fail(REFRACT_E_NOT_FOUND,
                        "events: refractd ended the stream after %ld of %ld events%s", r.printed,
                        r.want, p.n_pos > 0 ? " (was the scene deleted?)" : "");
    return REFRACT_E_OK;
}

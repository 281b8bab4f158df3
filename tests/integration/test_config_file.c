/*
 * test_config_file.c - refractd's configuration as shipped and as documented:
 *   - every option `refractd --help` lists (bar help, version, config) has its line in
 *     deploy/refractd.conf, so the file documents every setting;
 *   - the daemon starts from deploy/refractd.conf as shipped;
 *   - values from a --config file take effect (health reports them, a render over the
 *     limit is refused naming the flag), and a later flag overrides the file;
 *   - a bad config file stops start-up with a message naming the file and line.
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"

/* True when conf has an uncommented line "name value". */
static bool conf_has_key(const char *conf, const char *name)
{
    size_t n = strlen(name);
    for (const char *line = conf; line && *line;
         line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        if (strncmp(line, name, n) == 0 && (line[n] == ' ' || line[n] == '\t'))
            return true;
    }
    return false;
}

static void every_option_is_in_the_shipped_config(void)
{
    char *help = NULL;
    CHECK_INT(test_run_refractd((const char *[]){"--help", NULL}, &help), 0);
    char *conf = test_read_source_file("deploy/refractd.conf", NULL);
    CHECK(conf != NULL);
    int options = 0;
    for (const char *p = help; conf && (p = strstr(p, "\n  --")) != NULL;) {
        p += 5;
        char name[64];
        size_t len = strcspn(p, " \n");
        snprintf(name, sizeof name, "%.*s", (int)len, p);
        if (!strcmp(name, "help") || !strcmp(name, "version") || !strcmp(name, "config"))
            continue;
        options++;
        /* Flags without a value (gl-debug) and per-run paths appear commented out. */
        bool commented = !strcmp(name, "gl-debug") || !strcmp(name, "port-file") ||
                         !strcmp(name, "scene-dir") || !strcmp(name, "shader-dir") ||
                         !strcmp(name, "token-file") || !strcmp(name, "allow-host") ||
                         !strcmp(name, "trusted-proxy") || !strcmp(name, "tls-cert") ||
                         !strcmp(name, "tls-key") || !strcmp(name, "batch") ||
                         !strcmp(name, "frames") || !strcmp(name, "task") || !strcmp(name, "out");
        char commented_line[80];
        snprintf(commented_line, sizeof commented_line, "# %s", name);
        if (commented ? strstr(conf, commented_line) == NULL : !conf_has_key(conf, name)) {
            fprintf(stderr, "deploy/refractd.conf lacks option %s\n", name);
            CHECK(false);
        } else {
            CHECK(true);
        }
    }
    CHECK(options >= 25);
    fprintf(stderr, "refractd --help lists %d settings\n", options);
    free(help);
    free(conf);
}

static void the_shipped_config_starts_the_daemon(void)
{
    char conf[512];
    snprintf(conf, sizeof conf, "%s/deploy/refractd.conf", getenv("REFRACT_SOURCE_DIR"));
    struct test_daemon d;
    bool up = test_daemon_start(&d, (const char *[]){"--config", conf, NULL});
    if (!up)
        fprintf(stderr, "refractd with deploy/refractd.conf: %s\n", d.why);
    CHECK(up);
    if (!up)
        return;
    char *body = NULL;
    CHECK_INT(test_request(&d, "GET", "/v1/health", NULL, &body), 200);
    CHECK_CONTAINS(body, "\"max_image_dim\":4096");
    CHECK_CONTAINS(body, "\"header_deadline_s\":30");
    free(body);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
}

static void config_values_take_effect_and_flags_override_them(void)
{
    char path[512];
    test_temp_template(path, sizeof path, "refract-conf");
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    const char text[] = "# test\nmax-image-dim 100\nmax-rays 7\n  max-steps 3000  \n"
                        "max-json-bytes 64K\nirradiance-gpu-budget 64M\n"
                        "light-position-tolerance 0.01\nlightsim-chunk-steps 3\n"
                        "header-deadline 7\nmax-queued-per-client 5\n";
    CHECK(write(fd, text, sizeof text - 1) == (ssize_t)(sizeof text - 1));
    close(fd);
    struct test_daemon d;
    bool up = test_daemon_start(&d, (const char *[]){"--config", path, "--max-rays", "9", NULL});
    CHECK(up);
    if (up) {
        char *body = NULL;
        CHECK_INT(test_request(&d, "GET", "/v1/health", NULL, &body), 200);
        CHECK_CONTAINS(body, "\"max_image_dim\":100");
        CHECK_CONTAINS(body, "\"max_steps\":3000");
        CHECK_CONTAINS(body, "\"max_json_bytes\":65536");
        CHECK_CONTAINS(body, "\"max_rays\":9"); /* the flag after --config wins */
        CHECK_CONTAINS(body, "\"gpu_budget_bytes\":67108864");
        CHECK_CONTAINS(body, "\"position_tolerance\":0.01");
        CHECK_CONTAINS(body, "\"direction_tolerance\":0.001");
        CHECK_CONTAINS(body, "\"chunk_steps\":3");
        CHECK_CONTAINS(body, "\"header_deadline_s\":7"); /* "fair_sharing" */
        CHECK_CONTAINS(body, "\"max_queued_per_client\":5");
        free(body);
        char id[REFRACT_ID_SIZE];
        CHECK(test_create_scene(&d,
                                "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, "
                                "1, 1]}, \"resolution\": 8, \"ior\": 1.2}]}",
                                id));
        char route[128];
        snprintf(route, sizeof route, "/v1/scenes/%s/render", id);
        CHECK_INT(test_request(&d, "POST", route, "{\"width\": 101, \"height\": 10}", &body), 422);
        CHECK(test_error_is(body, "limit_exceeded", "--max-image-dim"));
        free(body);
        CHECK_INT(test_daemon_stop(&d), 0);
        test_daemon_cleanup(&d);
    }
    unlink(path);
}

static void a_bad_config_file_names_file_and_line(void)
{
    char path[512];
    test_temp_template(path, sizeof path, "refract-conf");
    int fd = mkstemp(path);
    const char text[] = "max-rays 7\nmax-steps lots\n";
    CHECK(write(fd, text, sizeof text - 1) == (ssize_t)(sizeof text - 1));
    close(fd);
    char *out = NULL;
    CHECK_INT(test_run_refractd((const char *[]){"--config", path, NULL}, &out), REFRACT_E_USAGE);
    char where[600];
    snprintf(where, sizeof where, "%s:2:", path);
    CHECK_CONTAINS(out, where);
    CHECK_CONTAINS(out, "max-steps lots");
    free(out);

    fd = open(path, O_WRONLY | O_TRUNC);
    const char typo[] = "\nmax-image-dimm 7\n";
    CHECK(write(fd, typo, sizeof typo - 1) == (ssize_t)(sizeof typo - 1));
    close(fd);
    CHECK_INT(test_run_refractd((const char *[]){"--config", path, NULL}, &out), REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "unknown key \"max-image-dimm\"");
    free(out);

    fd = open(path, O_WRONLY | O_TRUNC);
    const char zero[] = "light-direction-tolerance 0\n";
    CHECK(write(fd, zero, sizeof zero - 1) == (ssize_t)(sizeof zero - 1));
    close(fd);
    CHECK_INT(test_run_refractd((const char *[]){"--config", path, NULL}, &out), REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "light-direction-tolerance 0: expected a number in (0, 1]");
    free(out);
    unlink(path);
}

int main(void)
{
    if (getenv("REFRACTD") == NULL)
        test_skip("test_config_file", "REFRACTD is not set (ctest sets it)");
    every_option_is_in_the_shipped_config();
    the_shipped_config_starts_the_daemon();
    config_values_take_effect_and_flags_override_them();
    a_bad_config_file_names_file_and_line();
    return test_summary("test_config_file");
}

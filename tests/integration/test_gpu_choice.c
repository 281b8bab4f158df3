/*
 * test_gpu_choice.c - which GPU refractd uses, and where its shaders come from:
 *   - --gpu software and REFRACT_GPU=software give Mesa's software device, reported by
 *     /v1/health (vendor, renderer, version, device);
 *   - --gpu hardware on a machine without a hardware EGL device stops start-up with a
 *     message that lists the devices and says what to do (on a GPU machine it succeeds
 *     and health says "hardware"); a misspelt REFRACT_GPU is a usage error;
 *   - --shader-dir with a copy of shaders/ works; a syntax error in it stops start-up
 *     with the compiler's message mapped to our file name and line.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"

/* Starts a daemon with args, returns its health JSON (caller frees) or NULL. */
static char *health_of(const char *const *args)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, args)) {
        fprintf(stderr, "refractd did not start: %s\n", d.why);
        return NULL;
    }
    char *body = NULL;
    if (test_request(&d, "GET", "/v1/health", NULL, &body) != 200) {
        free(body);
        body = NULL;
    }
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return body;
}

static void device_choice(void)
{
    char *autod = health_of(NULL);
    CHECK(autod != NULL);
    bool has_hardware = autod && strstr(autod, "\"device\":\"hardware\"") != NULL;
    printf("auto picked the %s device\n", has_hardware ? "hardware" : "software");
    CHECK_CONTAINS(autod ? autod : "", "\"renderer\":");
    CHECK_CONTAINS(autod ? autod : "", "\"vendor\":");
    CHECK_CONTAINS(autod ? autod : "", "\"version\":");
    free(autod);

    char *sw = health_of((const char *[]){"--gpu", "software", NULL});
    CHECK_CONTAINS(sw ? sw : "", "\"device\":\"software\"");
    free(sw);
    setenv("REFRACT_GPU", "software", 1);
    sw = health_of(NULL);
    CHECK_CONTAINS(sw ? sw : "", "\"device\":\"software\"");
    free(sw);

    setenv("REFRACT_GPU", "sofware", 1);
    char *out = NULL;
    CHECK_INT(test_run_refractd((const char *[]){"--port", "0", NULL}, &out), REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "REFRACT_GPU=sofware");
    free(out);
    unsetenv("REFRACT_GPU");

    if (has_hardware) {
        char *hw = health_of((const char *[]){"--gpu", "hardware", NULL});
        CHECK_CONTAINS(hw ? hw : "", "\"device\":\"hardware\"");
        free(hw);
    } else {
        CHECK_INT(
            test_run_refractd((const char *[]){"--gpu", "hardware", "--port", "0", NULL}, &out), 1);
        CHECK_CONTAINS(out, "a hardware GPU was required");
        CHECK_CONTAINS(out, "device 0: software");
        CHECK_CONTAINS(out, "--gpu software");
        free(out);
    }
}

static void shader_dir(void)
{
    char dir[512];
    test_temp_template(dir, sizeof dir, "refract-shaders");
    CHECK(mkdtemp(dir) != NULL);
    char cmd[1024];
    /* recursive: shaders/ has folders (geom/), read by their paths below it */
    snprintf(cmd, sizeof cmd, "cp -r '%s'/shaders/. '%s'/", getenv("REFRACT_SOURCE_DIR"), dir);
    CHECK_INT(system(cmd), 0);
    char *ok = health_of((const char *[]){"--shader-dir", dir, NULL});
    CHECK(ok != NULL);
    free(ok);

    /* Break ray_march.glsl at a known line: the error must name that file and line. */
    snprintf(cmd, sizeof cmd, "sed -i '20s/.*/this is not GLSL;/' '%s/ray_march.glsl'", dir);
    CHECK_INT(system(cmd), 0);
    char *out = NULL;
    CHECK_INT(test_run_refractd((const char *[]){"--shader-dir", dir, "--port", "0", NULL}, &out),
              1);
    CHECK_CONTAINS(out, "ray_march.glsl:20");
    CHECK_CONTAINS(out, "compiling");
    free(out);
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK_INT(system(cmd), 0);
}

int main(void)
{
    if (getenv("REFRACTD") == NULL || getenv("REFRACT_SOURCE_DIR") == NULL)
        test_skip("test_gpu_choice",
                  "REFRACTD and REFRACT_SOURCE_DIR are not set (ctest sets them)");
    device_choice();
    shader_dir();
    return test_summary("test_gpu_choice");
}

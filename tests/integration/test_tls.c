/*
 * test_tls.c - refractd speaks https with --tls-cert and --tls-key (libmicrohttpd's GnuTLS;
 * docs/api.md "Security"), and librefract and the refract CLI talk to it with the CA file
 * (--cacert). The test makes a self-signed certificate for 127.0.0.1 with openssl
 * (deploy/install-deps.sh installs it), so it is its own CA:
 *   - health, a scene's creation and listing over https through librefract with the CA;
 *   - a client without the CA refuses the unknown certificate (connect_failed);
 *   - plain http to the https port gets no answer;
 *   - the CLI with --url https://... --cacert and a token (REFRACT_TOKEN) works;
 *   - --tls-key that is not a key stops refractd at start-up with a message naming it.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "integration/daemon.h"
#include "integration/support_cli.h"
#include "test.h"

#define TOKEN "tls-test-token-0123456789abcdef"

static const char scene_json[] = "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": "
                                 "[1, 1, 1]}, \"resolution\": 8, \"ior\": 1.2}]}";

static bool make_certificate(const char *dir, char *cert, char *key, size_t size)
{
    snprintf(cert, size, "%s/cert.pem", dir);
    snprintf(key, size, "%s/key.pem", dir);
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes "
             "-keyout '%s' -out '%s' -days 2 -subj /CN=127.0.0.1 "
             "-addext subjectAltName=IP:127.0.0.1,DNS:localhost >'%s/openssl.log' 2>&1",
             key, cert, dir);
    if (system(cmd) != 0) {
        char log[600];
        snprintf(log, sizeof log, "%s/openssl.log", dir);
        char *text = cli_slurp(log);
        fprintf(stderr, "openssl failed (install it: deploy/install-deps.sh): %s\n", text);
        free(text);
        return false;
    }
    return true;
}

int main(void)
{
    if (getenv("REFRACTD") == NULL)
        test_skip("test_tls", "REFRACTD is not set (run through ctest)");
    char dir[512];
    test_temp_template(dir, sizeof dir, "refract-test-tls");
    if (mkdtemp(dir) == NULL) {
        test_setup_failed("test_tls", "mkdtemp failed");
        return test_summary("test_tls");
    }
    char cert[600], key[600], token_file[600];
    if (!make_certificate(dir, cert, key, sizeof cert)) {
        test_setup_failed("test_tls", "no certificate (openssl)");
        return test_summary("test_tls");
    }
    snprintf(token_file, sizeof token_file, "%s/token", dir);
    FILE *f = fopen(token_file, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(TOKEN "\n", f);
        fclose(f);
    }

    struct test_daemon d;
    if (!test_daemon_start(&d, (const char *[]){"--tls-cert", cert, "--tls-key", key,
                                                "--token-file", token_file, NULL})) {
        test_setup_failed("test_tls", d.why);
        return test_summary("test_tls");
    }
    CHECK(strncmp(d.url, "https://", 8) == 0);
    /* librefract over https, verified with the CA file, with the token. */
    CHECK_INT(refract_set_token(d.client, TOKEN), 0);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_json, id));
    char *body = NULL;
    CHECK_INT(test_request(&d, "GET", "/v1/scenes", NULL, &body), 200);
    CHECK_CONTAINS(body, id);
    free(body);

    /* Without the CA the self-signed certificate is refused. */
    refract_client *c = refract_client_create(d.url);
    CHECK(c != NULL);
    char *health = NULL;
    CHECK_INT(refract_health(c, &health), REFRACT_E_CONNECT_FAILED);
    CHECK_CONTAINS(refract_errmsg(c), "certificate");
    refract_free(health);
    health = NULL;
    CHECK_INT(refract_set_cacert(c, "/nonexistent/ca.pem"), REFRACT_E_IO);
    CHECK_INT(refract_set_cacert(c, cert), 0);
    CHECK_INT(refract_health(c, &health), 0);
    refract_free(health);
    refract_client_destroy(c);

    /* Plain http to the https port: no HTTP answer. */
    char plain_url[64];
    snprintf(plain_url, sizeof plain_url, "http://127.0.0.1:%d", d.port);
    c = refract_client_create(plain_url);
    refract_set_timeout_ms(c, 5000);
    health = NULL;
    CHECK(refract_health(c, &health) != REFRACT_E_OK);
    refract_free(health);
    refract_client_destroy(c);

    /* The CLI: https URL, --cacert, REFRACT_TOKEN. */
    setenv("REFRACT_TOKEN", TOKEN, 1);
    struct cli_run r =
        cli_run(&d, NULL, NULL, (const char *[]){"--cacert", cert, "scene", "list", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, id);
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL, (const char *[]){"scene", "list", NULL});
    CHECK_INT(r.status, REFRACT_E_CONNECT_FAILED);
    cli_run_free(&r);
    unsetenv("REFRACT_TOKEN");
    char *log = cli_slurp(d.log_path);
    CHECK_CONTAINS(log, "listening on https://");
    CHECK(strstr(log, TOKEN) == NULL);
    free(log);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);

    /* A --tls-key that is not a private key stops the start. */
    char *out = NULL;
    int status = test_run_refractd(
        (const char *[]){"--port", "0", "--tls-cert", cert, "--tls-key", cert, NULL}, &out);
    CHECK(status != 0);
    CHECK_CONTAINS(out, "--tls-key");
    free(out);

    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK_INT(system(cmd), 0);
    return test_summary("test_tls");
}

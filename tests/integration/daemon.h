/*
 * daemon.h - the integration tests' harness: a real refractd on an ephemeral loopback port
 * with a fresh temporary data directory, and a librefract client for it.
 *
 *     struct test_daemon d;
 *     if (!test_daemon_start(&d, NULL))
 *         test_setup_failed("test_x", d.why);
 *     ... refract_render(d.client, ...) ...
 *     CHECK_INT(test_daemon_stop(&d), 0);   // SIGTERM, clean exit expected
 *
 * The binary comes from $REFRACTD (ctest sets it), the repository from
 * $REFRACT_SOURCE_DIR. The daemon's log goes to <data dir>/refractd.log and is printed when
 * a test fails to start it.
 */
#ifndef REFRACT_TEST_DAEMON_H
#define REFRACT_TEST_DAEMON_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

#include "refract.h"

struct test_daemon {
    pid_t pid;
    int port;
    char url[64];
    char dir[256]; /* temporary directory: data/, refractd.log, port */
    char data_dir[300];
    char log_path[300];
    refract_client *client;
    char why[512]; /* why start failed */
};

/* Starts refractd with `extra_args` (NULL-terminated, may be NULL) and waits until
 * /v1/health answers. With "--tls-cert CERT" among them the URL is https and the client
 * verifies the daemon with CERT as its CA (a self-signed certificate). On failure returns false
 * with d->why filled. If data_dir is not NULL it is reused (restart tests); otherwise a new
 * temporary directory is made. */
bool test_daemon_start_in(struct test_daemon *d, const char *data_dir,
                          const char *const *extra_args);
bool test_daemon_start(struct test_daemon *d, const char *const *extra_args);
/* A restart: starts `next` on the data directory of `stopped` (stopped with
 * test_daemon_stop, not yet cleaned up). On failure removes stopped's directory and fails
 * the test `name` (test_setup_failed: does not return). */
void test_daemon_restart(const struct test_daemon *stopped, struct test_daemon *next,
                         const char *name);

/* SIGTERM, wait up to 20 s. Returns the exit status (0 = clean), or -1 if it had to be
 * killed. Keeps the directory (see test_daemon_cleanup). */
int test_daemon_stop(struct test_daemon *d);
/* Removes the temporary directory. */
void test_daemon_cleanup(struct test_daemon *d);

/* Writes "$TMPDIR/<stem>-XXXXXX" (TMPDIR defaults to /tmp): a template for mkstemp or
 * mkdtemp, so every temporary file of the tests lands where TMPDIR says. */
void test_temp_template(char *buf, size_t size, const char *stem);

/* Runs $REFRACTD with args to completion (for start-up failures and --help; killed after
 * 60 s) and returns its exit status (-1 if it did not exit normally); *output is a new
 * string (caller frees) with its stdout and stderr. */
int test_run_refractd(const char *const *args, char **output);

/* Reads a file under $REFRACT_SOURCE_DIR (e.g. "proto/examples/glass_sphere.json"):
 * a new NUL-terminated buffer the caller frees, or NULL. */
char *test_read_source_file(const char *relative, size_t *len);

/* Creates a scene from a JSON string; writes its id (REFRACT_ID_SIZE bytes). */
bool test_create_scene(struct test_daemon *d, const char *json, char *id);

/* A raw request with a JSON body; returns the status (or -1) and the body in *body (new
 * string; may be NULL). */
long test_request(struct test_daemon *d, const char *method, const char *path,
                  const char *json_body, char **body);

/* True when the body is {"error": {"code": code, "message": contains `needle`}}. */
bool test_error_is(const char *body, const char *code, const char *needle);

/* CLOCK_MONOTONIC in milliseconds. */
double test_now_ms(void);

/* Sends all len bytes on a socket (MSG_NOSIGNAL); false when a send fails. */
bool test_send_all(int fd, const void *data, size_t len);

#endif

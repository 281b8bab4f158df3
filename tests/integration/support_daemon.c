/*
 * support_daemon.c - starting and stopping a real refractd for integration tests; see
 * daemon.h.
 */
#include "daemon.h"
#include "test.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *temp_dir(void)
{
    const char *t = getenv("TMPDIR");
    return t && t[0] ? t : "/tmp";
}

void test_temp_template(char *buf, size_t size, const char *stem)
{
    snprintf(buf, size, "%s/%s-XXXXXX", temp_dir(), stem);
}

static void sleep_ms(int ms)
{
    struct timespec ts = {.tv_sec = ms / 1000, .tv_nsec = (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static void print_log(const struct test_daemon *d)
{
    FILE *f = fopen(d->log_path, "r");
    if (f == NULL)
        return;
    char line[1024];
    fprintf(stderr, "---- refractd log (%s) ----\n", d->log_path);
    while (fgets(line, sizeof line, f))
        fputs(line, stderr);
    fclose(f);
}

static int read_port(const char *path)
{
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return 0;
    int port = 0;
    if (fscanf(f, "%d", &port) != 1)
        port = 0;
    fclose(f);
    return port;
}

static void spawn(struct test_daemon *d, const char *bin, const char *port_file,
                  const char *const *extra)
{
    const char *argv[64];
    int n = 0;
    argv[n++] = bin;
    /* The caller's options first, so that a --config FILE among them cannot move the
     * daemon off the harness's ephemeral port and temporary data directory. */
    for (int i = 0; extra && extra[i] && n < 54; i++)
        argv[n++] = extra[i];
    argv[n++] = "--port";
    argv[n++] = "0";
    argv[n++] = "--bind";
    argv[n++] = "127.0.0.1";
    argv[n++] = "--port-file";
    argv[n++] = port_file;
    argv[n++] = "--data-dir";
    argv[n++] = d->data_dir;
    argv[n] = NULL;
    FILE *log = fopen(d->log_path, "a");
    if (log == NULL)
        _exit(127);
    dup2(fileno(log), STDOUT_FILENO);
    dup2(fileno(log), STDERR_FILENO);
    execv(bin, (char *const *)argv);
    fprintf(stderr, "exec %s failed: %s\n", bin, strerror(errno));
    _exit(127);
}

void test_daemon_restart(const struct test_daemon *stopped, struct test_daemon *next,
                         const char *name)
{
    char data_dir[sizeof stopped->data_dir];
    snprintf(data_dir, sizeof data_dir, "%s", stopped->data_dir);
    if (!test_daemon_start_in(next, data_dir, NULL)) {
        struct test_daemon old = *stopped;
        test_daemon_cleanup(&old);
        test_setup_failed(name, next->why);
    }
}

bool test_daemon_start_in(struct test_daemon *d, const char *data_dir,
                          const char *const *extra_args)
{
    memset(d, 0, sizeof *d);
    const char *bin = getenv("REFRACTD");
    if (bin == NULL || access(bin, X_OK) != 0) {
        snprintf(d->why, sizeof d->why, "REFRACTD (%s) is not an executable refractd",
                 bin ? bin : "unset");
        return false;
    }
    test_temp_template(d->dir, sizeof d->dir, "refract-test");
    if (mkdtemp(d->dir) == NULL) {
        snprintf(d->why, sizeof d->why, "mkdtemp failed: %s", strerror(errno));
        return false;
    }
    if (data_dir)
        snprintf(d->data_dir, sizeof d->data_dir, "%s", data_dir);
    else
        snprintf(d->data_dir, sizeof d->data_dir, "%s/data", d->dir);
    snprintf(d->log_path, sizeof d->log_path, "%s/refractd.log", d->dir);
    char port_file[300];
    snprintf(port_file, sizeof port_file, "%s/port", d->dir);
    d->pid = fork();
    if (d->pid == 0)
        spawn(d, bin, port_file, extra_args);
    if (d->pid < 0) {
        snprintf(d->why, sizeof d->why, "fork failed");
        return false;
    }
    for (int waited = 0; waited < 60000; waited += 50) {
        int status;
        if (waitpid(d->pid, &status, WNOHANG) == d->pid) {
            print_log(d);
            snprintf(d->why, sizeof d->why, "refractd exited during start-up (status %d)",
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1);
            d->pid = 0;
            return false;
        }
        d->port = read_port(port_file);
        if (d->port > 0)
            break;
        sleep_ms(50);
    }
    if (d->port <= 0) {
        print_log(d);
        snprintf(d->why, sizeof d->why, "refractd did not write its port within 60 s");
        test_daemon_stop(d);
        return false;
    }
    /* With --tls-cert CERT the daemon speaks https; the test's self-signed CERT is also
     * the CA that verifies it. */
    const char *tls_cert = NULL;
    for (int i = 0; extra_args && extra_args[i]; i++) {
        if (strcmp(extra_args[i], "--tls-cert") == 0 && extra_args[i + 1])
            tls_cert = extra_args[i + 1];
    }
    snprintf(d->url, sizeof d->url, "%s://127.0.0.1:%d", tls_cert ? "https" : "http", d->port);
    d->client = refract_client_create(d->url);
    if (d->client && tls_cert && refract_set_cacert(d->client, tls_cert) != REFRACT_E_OK) {
        snprintf(d->why, sizeof d->why, "refract_set_cacert: %s", refract_errmsg(d->client));
        test_daemon_stop(d);
        return false;
    }
    char *health = NULL;
    if (d->client == NULL || refract_health(d->client, &health) != REFRACT_E_OK) {
        print_log(d);
        snprintf(d->why, sizeof d->why, "health check failed: %s",
                 d->client ? refract_errmsg(d->client) : "no client");
        refract_free(health);
        test_daemon_stop(d);
        return false;
    }
    refract_free(health);
    return true;
}

bool test_daemon_start(struct test_daemon *d, const char *const *extra_args)
{
    return test_daemon_start_in(d, NULL, extra_args);
}

int test_daemon_stop(struct test_daemon *d)
{
    refract_client_destroy(d->client);
    d->client = NULL;
    if (d->pid <= 0)
        return -1;
    kill(d->pid, SIGTERM);
    int status = 0;
    for (int waited = 0; waited < 20000; waited += 20) {
        if (waitpid(d->pid, &status, WNOHANG) == d->pid) {
            d->pid = 0;
            if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
                print_log(d);
            return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        }
        sleep_ms(20);
    }
    kill(d->pid, SIGKILL);
    waitpid(d->pid, &status, 0);
    d->pid = 0;
    print_log(d);
    return -1;
}

static void remove_tree(const char *path)
{
    char cmd[600];
    if (strstr(path, "/refract-test-") == NULL)
        return; /* only ever our own temporary directories */
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", path);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", path);
}

void test_daemon_cleanup(struct test_daemon *d)
{
    if (d->dir[0])
        remove_tree(d->dir);
}

char *test_read_source_file(const char *relative, size_t *len)
{
    const char *root = getenv("REFRACT_SOURCE_DIR");
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", root ? root : ".", relative);
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf) {
        buf[n] = '\0';
        if (len)
            *len = (size_t)n;
    }
    return buf;
}

bool test_create_scene(struct test_daemon *d, const char *json, char *id)
{
    int rc = refract_scene_create(d->client, json, strlen(json), id, REFRACT_ID_SIZE);
    if (rc != REFRACT_E_OK)
        fprintf(stderr, "scene create failed: %s\n", refract_errmsg(d->client));
    return rc == REFRACT_E_OK;
}

long test_request(struct test_daemon *d, const char *method, const char *path,
                  const char *json_body, char **body)
{
    struct refract_response r;
    if (body)
        *body = NULL;
    int rc = refract_request(d->client, method, path, json_body, json_body ? strlen(json_body) : 0,
                             json_body ? "application/json" : NULL, &r);
    if (rc != REFRACT_E_OK)
        return -1;
    long status = r.status;
    if (body) {
        *body = r.body;
        r.body = NULL;
    }
    refract_response_free(&r);
    return status;
}

bool test_error_is(const char *body, const char *code, const char *needle)
{
    if (body == NULL)
        return false;
    cJSON *root = cJSON_Parse(body);
    const cJSON *err = cJSON_GetObjectItemCaseSensitive(root, "error");
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(err, "code");
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(err, "message");
    bool ok = cJSON_IsString(c) && cJSON_IsString(m) && strcmp(c->valuestring, code) == 0 &&
              (needle == NULL || strstr(m->valuestring, needle) != NULL);
    if (!ok)
        fprintf(stderr, "expected error %s containing \"%s\", got: %s\n", code,
                needle ? needle : "", body);
    cJSON_Delete(root);
    return ok;
}

int test_run_refractd(const char *const *args, char **output)
{
    *output = calloc(1, 65536);
    char path[512];
    test_temp_template(path, sizeof path, "refract-run");
    int fd = mkstemp(path);
    if (fd < 0 || *output == NULL)
        return -1;
    const char *argv[24];
    int n = 0;
    argv[n++] = getenv("REFRACTD");
    for (int i = 0; args[i] && n < 23; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    pid_t pid = fork();
    if (pid == 0) {
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        alarm(60);                               /* a start-up that does not fail runs forever */
        setenv("XDG_STATE_HOME", temp_dir(), 1); /* and must not write under $HOME */
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int st = 0, status = -1;
    if (pid > 0 && waitpid(pid, &st, 0) == pid && WIFEXITED(st))
        status = WEXITSTATUS(st);
    close(fd);
    FILE *f = fopen(path, "rb");
    if (f) {
        size_t got = fread(*output, 1, 65535, f);
        (*output)[got] = '\0';
        fclose(f);
    }
    unlink(path);
    return status;
}

double test_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

bool test_send_all(int fd, const void *data, size_t len)
{
    const char *p = data;
    while (len > 0) {
        ssize_t n = send(fd, p, len, MSG_NOSIGNAL);
        if (n <= 0)
            return false;
        p += n;
        len -= (size_t)n;
    }
    return true;
}

/*
 * config.h - refractd's settings: command-line flags, an optional config file with the
 * same keys (deploy/refractd.conf documents every one), and their defaults.
 *
 * Precedence: defaults, then the config file (--config FILE), then the other flags in
 * the order given. The config read at start-up is the only global state refractd has, and
 * it is passed by pointer, never reached for.
 */
#ifndef REFRACT_CONFIG_H
#define REFRACT_CONFIG_H

#include <stdbool.h>
#include <stddef.h>

#include "cache/irradiance_cache.h"
#include "core/err.h"
#include "gpu/queue.h"
#include "http/http.h"
#include "scene/scene.h"
#include "view/view.h"

#define CONFIG_MAX_ALLOW_HOSTS 16

struct config {
    struct http_config http;
    struct gpu_desc gpu;
    size_t gpu_scene_budget_bytes;
    struct irradiance_cache_desc irradiance; /* data_dir is set from data_dir at start-up */
    struct view_registry_desc views;         /* the limits; the borrowed parts at start-up */
    char data_dir[512];
    bool data_dir_given; /* --data-dir was set (batch mode uses a private one otherwise) */
    /* One-shot batch mode (--batch; docs/slurm.md): "" = serve HTTP as usual. */
    char batch[512];       /* the job specification file */
    char batch_frames[64]; /* "A-B" or "" */
    char batch_task[64];   /* "I/N" or "" */
    char batch_out[512];   /* the output directory */
    char scene_dir[512];   /* "" = none */
    char shader_dir[512];  /* "" = embedded */
    char port_file[512];   /* "" = none */
    int max_scenes;
    int max_job_frames;   /* frames of one batch job (--max-job-frames) */
    size_t event_history; /* events the hub keeps (events.h ring capacity) */
    long long max_env_pixels;
    unsigned long long max_storage_bytes; /* 0 = unlimited */
    int log_level;
    bool help, version;
    /* Access control (docs/api.md "Security"). The files are read by config_load_secrets. */
    char token_file[512]; /* "" = no token */
    char token[1025];     /* the token read from token_file */
    char allow_host_names[CONFIG_MAX_ALLOW_HOSTS][256];
    const char *allow_hosts[CONFIG_MAX_ALLOW_HOSTS]; /* -> allow_host_names; http.allow_hosts */
    bool trusted_proxy;               /* a non-loopback --bind without a token is meant */
    char tls_cert[512], tls_key[512]; /* PEM files; both or neither */
    char *tls_cert_pem, *tls_key_pem; /* their text (config_load_secrets; config_free) */
};

/* Fills defaults (data dir: $XDG_STATE_HOME/refract, else ~/.local/state/refract). */
void config_defaults(struct config *c);

/* Applies argv (and a --config file if named). REFRACT_E_USAGE with a message that names
 * the flag and what it accepts. */
enum refract_code config_parse_args(struct config *c, int argc, char **argv, struct err *e);

/* Reads the token file and the TLS files named by the flags into c (http.token,
 * http.tls_*_pem), and refuses what would expose refractd unguarded: a --bind that is not
 * loopback without a token, unless --trusted-proxy. REFRACT_E_USAGE with a message that
 * says what to do. Call after config_parse_args. */
enum refract_code config_load_secrets(struct config *c, struct err *e);
/* Frees what config_load_secrets allocated. */
void config_free(struct config *c);

/* The --help text. */
void config_print_usage(const char *argv0);

#endif

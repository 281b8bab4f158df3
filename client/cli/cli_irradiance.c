/*
 * cli_irradiance.c - the irradiance status as people read it (see cli_irradiance.h).
 *
 * The states are refractd's words, printed as they come, so a state this client does not
 * know still shows. Progress is refractd's "progress" (the fraction of the light
 * domain the wavefront has swept, docs/lightsim.md), not a time estimate: a simulation
 * that culls most of its patches early finishes sooner than its sweep suggests.
 */
#include "cli_irradiance.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static bool is_state(const struct refract_light_status *l, const char *state)
{
    return strcmp(l->state, state) == 0;
}

/* A photon map is "ready" from its first pass and refining until its last
 * (docs/photons.md "The cache"): not settled until then. */
static bool is_settled(const struct refract_light_status *l)
{
    return (is_state(l, "ready") && !l->refining) || is_state(l, "failed") ||
           is_state(l, "not_needed");
}

/* The state as printed: refractd's word, "refining" for a ready map still refining. */
static const char *state_word(const struct refract_light_status *l)
{
    return is_state(l, "ready") && l->refining ? "refining" : l->state;
}

/* A light's own progress, 0..1. */
static double light_fraction(const struct refract_light_status *l)
{
    if (is_settled(l))
        return 1.0;
    if (is_state(l, "queued") || !(l->progress >= 0))
        return 0.0;
    return l->progress > 1.0 ? 1.0 : l->progress;
}

double cli_irradiance_fraction(const struct refract_irradiance *s)
{
    double sum = 0;
    size_t n = 0;

    for (size_t i = 0; i < s->light_count; i++) {
        if (is_state(&s->lights[i], "not_needed"))
            continue;
        sum += light_fraction(&s->lights[i]);
        n++;
    }
    return n > 0 ? sum / (double)n : 1.0;
}

/* Appends to buf (size bytes, used so far) like snprintf; never overruns. */
static size_t append(char *buf, size_t size, size_t used, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static size_t append(char *buf, size_t size, size_t used, const char *fmt, ...)
{
    va_list ap;
    int n;

    if (used >= size)
        return used;
    va_start(ap, fmt);
    n = vsnprintf(buf + used, size - used, fmt, ap);
    va_end(ap);
    if (n < 0)
        return used;
    return used + (size_t)n < size ? used + (size_t)n : size - 1;
}

void cli_irradiance_summary(char *buf, size_t size, const struct refract_irradiance *s, int step)
{
    size_t used = 0;

    if (size == 0)
        return;
    buf[0] = '\0';
    if (s->light_count == 0) {
        append(buf, size, 0, "no lights");
        return;
    }
    for (size_t i = 0; i < s->light_count; i++) {
        const struct refract_light_status *l = &s->lights[i];

        used = append(buf, size, used, "%s%s %s", i > 0 ? ", " : "", l->name, state_word(l));
        if (!is_settled(l) && !is_state(l, "queued") && l->progress >= 0) {
            int pct = (int)(100.0 * (l->progress > 1 ? 1 : l->progress));

            if (step > 0)
                pct -= pct % step;
            used = append(buf, size, used, " %d%%", pct);
        }
        if (is_state(l, "computing") && l->patches_live >= 0 && step <= 0)
            used = append(buf, size, used, " (%lld patches)", l->patches_live);
    }
}

/* The PROGRESS cell of a light: "100%", "45%", "-" when it needs no volume. */
static void progress_cell(char *buf, size_t size, const struct refract_light_status *l)
{
    if (is_state(l, "not_needed"))
        snprintf(buf, size, "-");
    else if (is_state(l, "ready") && !l->refining)
        snprintf(buf, size, "100%%");
    else if (l->progress >= 0)
        snprintf(buf, size, "%.0f%%", 100.0 * (l->progress > 1 ? 1 : l->progress));
    else
        snprintf(buf, size, "-");
}

void cli_irradiance_table(FILE *f, const struct refract_irradiance *s)
{
    int name_w = 5; /* "LIGHT" */
    bool any_failed = false;

    bool maps = false;
    for (size_t i = 0; i < s->light_count; i++)
        maps = maps || s->lights[i].photon_map;
    fprintf(f, "scene %s: %s", s->scene[0] != '\0' ? s->scene : "?",
            !s->needed ? "needs no light simulation"
            : maps     ? "needs a photon map per light"
                       : "needs light simulation");
    if (s->transport_hash[0] != '\0')
        fprintf(f, ", transport hash %s", s->transport_hash);
    fprintf(f, ", %zu light%s\n", s->light_count, s->light_count == 1 ? "" : "s");
    if (s->light_count == 0)
        return;
    for (size_t i = 0; i < s->light_count; i++) {
        int n = (int)strlen(s->lights[i].name);

        name_w = n > name_w ? n : name_w;
    }
    fprintf(f, "%-*s  %-10s  %8s  %8s  %10s  %10s  %10s  %s\n", name_w, "LIGHT", "STATE",
            "PROGRESS", "PATCHES", "GPU MEM", "HOST MEM", "COMPUTE", "USING");
    for (size_t i = 0; i < s->light_count; i++) {
        const struct refract_light_status *l = &s->lights[i];
        char progress[16], patches[24], gpu[24], host[24], compute[24];

        progress_cell(progress, sizeof(progress), l);
        if (l->patches_live >= 0)
            snprintf(patches, sizeof(patches), "%lld", l->patches_live);
        else
            snprintf(patches, sizeof(patches), "-");
        cli_format_bytes(gpu, sizeof(gpu), l->gpu_bytes);
        cli_format_bytes(host, sizeof(host), l->host_bytes);
        cli_format_ms(compute, sizeof(compute), l->compute_ms);
        fprintf(f, "%-*s  %-10s  %8s  %8s  %10s  %10s  %10s  %s\n", name_w, l->name, state_word(l),
                progress, patches, gpu, host, compute,
                l->using_volume[0] != '\0' ? l->using_volume : "-");
        any_failed = any_failed || is_state(l, "failed");
    }
    if (!any_failed)
        return;
    fputs("failed:\n", f);
    for (size_t i = 0; i < s->light_count; i++) {
        if (is_state(&s->lights[i], "failed"))
            fprintf(f, "  %s: %s\n", s->lights[i].name,
                    s->lights[i].message[0] != '\0' ? s->lights[i].message : "(no message)");
    }
}

void cli_progress_update(struct cli_progress *p, const struct refract_irradiance *s)
{
    char summary[400];
    char line[512];

    if (!p->tty) {
        cli_irradiance_summary(summary, sizeof(summary), s, 10);
        snprintf(line, sizeof(line), "irradiance: %s", summary);
        cli_progress_show(p, -1.0, line);
        return;
    }
    cli_irradiance_summary(summary, sizeof(summary), s, 0);
    cli_progress_show(p, cli_irradiance_fraction(s), summary);
}

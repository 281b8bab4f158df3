/*
 * refract_wait.c - refract_irradiance_wait(): polls a scene's irradiance status until
 * no light's volume is still to come, or a deadline passes.
 *
 * Polling, not a push channel: refractd's API is plain request/response, and a status
 * read is a few hundred bytes answered without touching the GPU thread, so reading it
 * four to ten times a second costs nothing next to a light simulation that takes from
 * tens of milliseconds (a GPU) to seconds (llvmpipe). The interval is clamped to
 * 100..250 ms: faster adds load and no information, slower makes a progress bar jerk.
 * Time is measured on CLOCK_MONOTONIC so a clock change cannot end or stretch the wait.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "refract_internal.h"
#include "refract_status.h"

#define WAIT_INTERVAL_DEFAULT_MS 200L
#define WAIT_INTERVAL_MIN_MS 100L
#define WAIT_INTERVAL_MAX_MS 250L

static double now_ms(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static void sleep_ms(double ms)
{
    struct timespec ts;

    if (ms <= 0)
        return;
    ts.tv_sec = (time_t)(ms / 1e3);
    ts.tv_nsec = (long)((ms - (double)ts.tv_sec * 1e3) * 1e6);
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

static long clamp_interval(long interval_ms)
{
    if (interval_ms <= 0)
        return WAIT_INTERVAL_DEFAULT_MS;
    if (interval_ms < WAIT_INTERVAL_MIN_MS)
        return WAIT_INTERVAL_MIN_MS;
    return interval_ms > WAIT_INTERVAL_MAX_MS ? WAIT_INTERVAL_MAX_MS : interval_ms;
}

/* Sets c's message for a wait that timed out: which lights are still to come. */
static int timed_out(refract_client *c, const char *scene_id, long timeout_ms,
                     const struct refract_irradiance *s)
{
    char pending[1024] = "";
    size_t used = 0;

    for (size_t i = 0; i < s->light_count && used < sizeof(pending); i++) {
        const struct refract_light_status *l = &s->lights[i];
        int n;

        if (refract_state_is_settled(l->state))
            continue;
        if (l->progress >= 0)
            n = snprintf(pending + used, sizeof(pending) - used, "%s%s %s %.0f%%",
                         used > 0 ? ", " : "", l->name, l->state, 100.0 * l->progress);
        else
            n = snprintf(pending + used, sizeof(pending) - used, "%s%s %s", used > 0 ? ", " : "",
                         l->name, l->state);
        if (n < 0)
            break;
        used += (size_t)n;
    }
    return refract_fail(c, REFRACT_E_TIMEOUT,
                        "scene %s: irradiance not ready after %.1f s (%s); raise the timeout "
                        "(refract --timeout SECONDS, 0 = none) or look again later with "
                        "'refract irradiance status %s'",
                        scene_id, (double)timeout_ms / 1e3, pending, scene_id);
}

int refract_irradiance_wait(refract_client *c, const char *scene_id,
                            const struct refract_wait_options *opts,
                            struct refract_irradiance *final_out)
{
    const struct refract_wait_options none = {0};
    const struct refract_wait_options *o = opts != NULL ? opts : &none;
    long interval = clamp_interval(o->interval_ms);
    double start = now_ms();
    struct refract_irradiance s = {0};
    int code;

    if (final_out != NULL)
        memset(final_out, 0, sizeof(*final_out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    code = refract_check_segment(c, "refract_irradiance_wait", "scene id", scene_id);
    if (code == REFRACT_E_OK && o->timeout_ms < 0)
        code = refract_fail(c, REFRACT_E_USAGE,
                            "refract_irradiance_wait: timeout_ms is %ld; "
                            "give 0 for none or a positive number",
                            o->timeout_ms);
    for (;;) {
        double poll_start = now_ms();

        if (code != REFRACT_E_OK)
            break;
        refract_irradiance_free(&s);
        code = refract_irradiance_status(c, scene_id, &s);
        if (code != REFRACT_E_OK)
            break;
        if (o->progress != NULL)
            o->progress(&s, o->user);
        if (refract_irradiance_settled(&s))
            break;
        if (o->timeout_ms > 0 && now_ms() - start >= (double)o->timeout_ms) {
            code = timed_out(c, scene_id, o->timeout_ms, &s);
            break;
        }
        /* The interval is measured from the start of the read, so a slow reply does not
         * slow the polling further; the last sleep ends at the deadline. */
        double wake = poll_start + (double)interval;

        if (o->timeout_ms > 0 && wake > start + (double)o->timeout_ms)
            wake = start + (double)o->timeout_ms;
        sleep_ms(wake - now_ms());
    }
    if (final_out != NULL && (code == REFRACT_E_OK || code == REFRACT_E_TIMEOUT))
        *final_out = s; /* ownership moves to the caller */
    else
        refract_irradiance_free(&s);
    return code;
}

/*
 * test_view_backpressure.c - a slow frame-stream client costs the daemon nothing but the
 * one frame it is sending (docs/views.md "Backpressure"):
 *   - a client whose socket stops reading (a small receive buffer, never read) while 150
 *     frames are made does not grow refractd's resident memory by anything like those
 *     frames' bytes (VmRSS from /proc/<pid>/status, before and after);
 *   - when it reads again it gets the newest frame, having skipped some of those in between.
 * Frames are 256x192 JPEGs at quality 100 (about 35 KB each: 5 MB in all). The kernel's
 * socket buffers take the first few megabytes (the loopback send buffer grows to
 * net.ipv4.tcp_wmem's maximum, 4 MiB by default: about 80 of these frames), which is why
 * so many frames are made; a stream that queued the rest would grow by megabytes and
 * deliver every frame.
 */
#include "view_util.h"

#define FRAMES 150

static long vm_rss_kib(pid_t pid)
{
    char path[64], line[256];
    snprintf(path, sizeof path, "/proc/%d/status", (int)pid);
    FILE *f = fopen(path, "r");
    long kib = -1;
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "VmRSS:", 6) == 0)
            kib = atol(line + 6);
    }
    if (f)
        fclose(f);
    return kib;
}

static double frame_bytes(const cJSON *status)
{
    const cJSON *frame = cJSON_GetObjectItemCaseSensitive(status, "frame");
    const cJSON *bytes = cJSON_GetObjectItemCaseSensitive(frame, "bytes");
    return cJSON_IsNumber(bytes) ? bytes->valuedouble : 0;
}

/* Makes `count` new frames one after the other (each PATCH changes the exposure a little);
 * returns the sum of their sizes and sets *last_seq. */
static double make_frames(struct test_daemon *d, const char *vid, int count, int first,
                          double *last_seq)
{
    double total = 0, seq = view_wait_seq(d, vid, 1, 30000);
    for (int i = 0; i < count; i++) {
        char body[64];
        snprintf(body, sizeof body, "{\"exposure\": %.3f}", 0.01 * ((first + i) % 50));
        if (view_patch(d, vid, body) != 200)
            break;
        seq = view_wait_seq(d, vid, seq + 1, 30000);
        cJSON *st = view_status(d, vid);
        total += frame_bytes(st);
        cJSON_Delete(st);
    }
    *last_seq = seq;
    return total;
}

int main(void)
{
    /* Under AddressSanitizer freed memory waits in a quarantine, which would count as
     * growth; the daemon gets none (harmless without ASan). */
    const char *asan = getenv("ASAN_OPTIONS");
    char opts[512];
    snprintf(opts, sizeof opts,
             "%s%squarantine_size_mb=0:thread_local_quarantine_size_kb=0:allocator_release_to_os_"
             "interval_ms=0",
             asan ? asan : "", asan && asan[0] ? ":" : "");
    setenv("ASAN_OPTIONS", opts, 1);
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_view_backpressure", d.why);
    char scene[REFRACT_ID_SIZE], vid[32];
    CHECK(test_create_scene(&d, view_sphere_scene, scene));
    CHECK_INT(view_open(&d, scene,
                        "{\"width\": 256, \"height\": 192, \"jpeg_quality\": 100, "
                        "\"progressive\": false, \"max_fps\": 120}",
                        vid, NULL),
              201);
    struct mjpeg_stream slow;
    CHECK_INT(mjpeg_open(&d, vid, 4096, &slow), 200); /* and then it stops reading */

    double seq = 0;
    make_frames(&d, vid, 10, 0, &seq); /* warm up the daemon's allocator arenas */
    long before = vm_rss_kib(d.pid);
    double made_bytes = make_frames(&d, vid, FRAMES, 10, &seq);
    long after = vm_rss_kib(d.pid);
    CHECK(before > 0 && after > 0);
    double growth = (double)(after - before) * 1024.0;
    printf("  %d frames, %.0f KiB of JPEG made; VmRSS %ld -> %ld KiB (%+.0f KiB)\n", FRAMES,
           made_bytes / 1024, before, after, growth / 1024);
    CHECK_MSG(made_bytes > 2e6, "the frames made only %.0f bytes: too few to see growth",
              made_bytes);
    CHECK_MSG(growth < made_bytes / 5,
              "VmRSS grew by %.0f KiB while %.0f KiB of frames were "
              "made for a stalled client",
              growth / 1024, made_bytes / 1024);

    /* Reading again: the newest frame arrives, the ones in between were skipped. */
    int received = 0;
    long long last = 0;
    for (int guard = 0; guard < FRAMES + 20 && last < (long long)seq; guard++) {
        struct mjpeg_frame f;
        if (mjpeg_next(&slow, &f, 10000) != 1)
            break;
        received++;
        last = f.seq;
        free(f.jpeg);
    }
    printf("  the slow client then received %d frames, the last seq %lld of %.0f\n", received, last,
           seq);
    CHECK(last == (long long)seq);
    CHECK_MSG(received <= FRAMES + 10 - 20, "%d frames received of %d made: too few were skipped",
              received, FRAMES + 10);
    mjpeg_close(&slow);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_view_backpressure");
}

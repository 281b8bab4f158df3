/*
 * cli_progress.c - the CLI's progress display and its formatting (see cli_progress.h).
 */
#include "cli_progress.h"

#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

void cli_format_bytes(char *buf, size_t size, long long bytes)
{
    static const char *const units[] = {"KiB", "MiB", "GiB", "TiB"};
    double v;
    int u = 0;

    if (bytes < 0) {
        snprintf(buf, size, "-");
        return;
    }
    if (bytes < 1024) {
        snprintf(buf, size, "%lld B", bytes);
        return;
    }
    /* At least 1 KiB here: u indexes units from 0 (KiB) up to 3 (TiB). */
    v = (double)bytes / 1024.0;
    while (v >= 1024.0 && u < 3) {
        v /= 1024.0;
        u++;
    }
    snprintf(buf, size, v < 10.0 && u >= 2 ? "%.2f %s" : "%.1f %s", v, units[u]);
}

void cli_format_ms(char *buf, size_t size, double ms)
{
    if (!(ms >= 0)) {
        snprintf(buf, size, "-");
    } else if (ms < 1000.0) {
        snprintf(buf, size, "%.0f ms", ms);
    } else if (ms < 60000.0) {
        snprintf(buf, size, "%.1f s", ms / 1000.0);
    } else {
        /* Unsigned and capped at 999,999,999 s (31 years; an ETA beyond that means
         * "forever"): the conversion is defined for any finite ms and the printed
         * length is bounded (at most "16666666 min 39 s"). */
        unsigned long long s =
            ms / 1000.0 < 999999999.0 ? (unsigned long long)(ms / 1000.0) : 999999999ull;
        unsigned min = (unsigned)(s / 60u), sec = (unsigned)(s % 60u);

        snprintf(buf, size, "%u min %02u s", min, sec);
    }
}

void cli_progress_bar(char *buf, size_t size, double fraction, int bar_width)
{
    int filled;
    size_t used = 0;

    if (size == 0)
        return;
    if (!(fraction >= 0))
        fraction = 0;
    if (fraction > 1)
        fraction = 1;
    if (bar_width < 1)
        bar_width = 1;
    filled = (int)(fraction * bar_width);
    buf[0] = '\0';
    if ((size_t)bar_width + 8 > size) {
        snprintf(buf, size, "%3d%%", (int)(fraction * 100.0));
        return;
    }
    buf[used++] = '[';
    for (int i = 0; i < bar_width; i++)
        buf[used++] = i < filled ? '#' : '-';
    snprintf(buf + used, size - used, "] %3d%%", (int)(fraction * 100.0));
}

void cli_transfer_text(char *buf, size_t size, long long sent, long long total, double elapsed_s,
                       bool with_percent)
{
    char done[32], all[32], eta[32], pct[16] = "";
    /* bytes per second; unknown until something went */
    double rate = elapsed_s > 0 && sent > 0 ? (double)sent / elapsed_s : -1.0;

    cli_format_bytes(done, sizeof(done), sent);
    if (total < 0) {
        if (rate >= 0)
            snprintf(buf, size, "%s  %.1f MB/s", done, rate / 1e6);
        else
            snprintf(buf, size, "%s", done);
        return;
    }
    cli_format_bytes(all, sizeof(all), total);
    if (with_percent)
        snprintf(pct, sizeof(pct), "%d%%  ",
                 total > 0 ? (int)(100.0 * (double)sent / (double)total) : 100);
    if (rate < 0) {
        snprintf(buf, size, "%s%s of %s", pct, done, all);
    } else if (sent >= total) {
        cli_format_ms(eta, sizeof(eta), 1000.0 * elapsed_s);
        snprintf(buf, size, "%s%s of %s  %.1f MB/s  in %s", pct, done, all, rate / 1e6, eta);
    } else {
        cli_format_ms(eta, sizeof(eta), rate > 0 ? 1000.0 * (double)(total - sent) / rate : -1.0);
        snprintf(buf, size, "%s%s of %s  %.1f MB/s  ETA %s", pct, done, all, rate / 1e6, eta);
    }
}

void cli_progress_init(struct cli_progress *p, FILE *f, bool tty, int width)
{
    memset(p, 0, sizeof(*p));
    p->f = f;
    p->tty = tty;
    p->width = width >= 20 ? width : 80;
}

void cli_progress_show(struct cli_progress *p, double fraction, const char *text)
{
    char bar[64];
    char line[512];

    if (!p->tty) {
        if (strcmp(text, p->last) == 0)
            return;
        snprintf(p->last, sizeof(p->last), "%s", text);
        fprintf(p->f, "%s\n", text);
        fflush(p->f);
        return;
    }
    if (fraction >= 0) {
        cli_progress_bar(bar, sizeof(bar), fraction, 24);
        snprintf(line, sizeof(line), "%s  %s", bar, text);
    } else {
        snprintf(line, sizeof(line), "%s", text);
    }
    if ((int)strlen(line) > p->width - 1)
        line[p->width - 1] = '\0';
    if (p->drawn && strcmp(line, p->last) == 0)
        return; /* unchanged: redrawing would only flicker */
    snprintf(p->last, sizeof(p->last), "%s", line);
    fprintf(p->f, "\r%s\033[K", line);
    fflush(p->f);
    p->drawn = true;
}

void cli_progress_finish(struct cli_progress *p)
{
    if (p->tty && p->drawn)
        fputc('\n', p->f);
    p->drawn = false;
    fflush(p->f);
}

int cli_terminal_columns(int fd)
{
    struct winsize ws;
    const char *columns = getenv("COLUMNS");

    if (ioctl(fd, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0)
        return ws.ws_col;
    return columns != NULL && atoi(columns) > 0 ? atoi(columns) : 80;
}

/*
 * plot.c - see plot.h.
 */
#include "plot.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/io_image.h"
#include "scene/font5x7.h"

struct canvas {
    uint8_t *px; /* RGBA8, row 0 at the top */
    int w, h;
};

static const uint8_t palette[PLOT_MAX_SERIES][3] = {
    {31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
    {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127},
};

static void put(struct canvas *c, int x, int y, const uint8_t rgb[3])
{
    if (x < 0 || y < 0 || x >= c->w || y >= c->h)
        return;
    uint8_t *p = c->px + ((size_t)y * c->w + x) * 4;
    p[0] = rgb[0];
    p[1] = rgb[1];
    p[2] = rgb[2];
    p[3] = 255;
}

/* Bresenham, `thick` pixels square brush. */
static void line(struct canvas *c, int x0, int y0, int x1, int y1, int thick, const uint8_t rgb[3])
{
    int dx = abs(x1 - x0), dy = -abs(y1 - y0);
    int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1, err = dx + dy;
    for (;;) {
        for (int a = 0; a < thick; a++)
            for (int b = 0; b < thick; b++)
                put(c, x0 + a - thick / 2, y0 + b - thick / 2, rgb);
        if (x0 == x1 && y0 == y1)
            break;
        int e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            x0 += sx;
        }
        if (e2 <= dx) {
            err += dx;
            y0 += sy;
        }
    }
}

/* Marker shapes by series: disc, square, triangle, diamond (then again). */
static void marker(struct canvas *c, int x, int y, int r, int shape, const uint8_t rgb[3])
{
    for (int j = -r; j <= r; j++)
        for (int i = -r; i <= r; i++) {
            bool in;
            switch (shape % 4) {
            case 0:
                in = i * i + j * j <= r * r;
                break;
            case 1:
                in = true;
                break;
            case 2:
                in = j >= -r && 2 * abs(i) <= j + r;
                break;
            default:
                in = abs(i) + abs(j) <= r;
                break;
            }
            if (in)
                put(c, x + i, y + j, rgb);
        }
}

/* Text with the 5x7 font at integer scale; (x, y) is the top-left corner. Returns the
 * width drawn. */
static int text(struct canvas *c, int x, int y, int scale, const char *s, const uint8_t rgb[3])
{
    int x0 = x;
    for (; *s; s++) {
        for (int col = 0; col < FONT5X7_COLS; col++)
            for (int row = 0; row < FONT5X7_ROWS; row++)
                if (scene_font5x7_lit((unsigned char)*s, col, row))
                    for (int a = 0; a < scale; a++)
                        for (int b = 0; b < scale; b++)
                            put(c, x + col * scale + a, y + row * scale + b, rgb);
        x += FONT5X7_CELL_COLS * scale;
    }
    return x - x0;
}

static int text_width(const char *s, int scale)
{
    return (int)strlen(s) * FONT5X7_CELL_COLS * scale;
}

/* Text rotated a quarter turn anticlockwise (for the y label), bottom-left at (x, y). */
static void text_up(struct canvas *c, int x, int y, int scale, const char *s, const uint8_t rgb[3])
{
    for (; *s; s++) {
        for (int col = 0; col < FONT5X7_COLS; col++)
            for (int row = 0; row < FONT5X7_ROWS; row++)
                if (scene_font5x7_lit((unsigned char)*s, col, row))
                    for (int a = 0; a < scale; a++)
                        for (int b = 0; b < scale; b++)
                            put(c, x + row * scale + b, y - col * scale - a, rgb);
        y -= FONT5X7_CELL_COLS * scale;
    }
}

static bool usable(const struct plot_point *p)
{
    return isfinite(p->x) && isfinite(p->y) && p->x > 0.0 && p->y > 0.0;
}

struct axes {
    int left, right, top, bottom; /* plot area, pixels */
    double lx0, lx1, ly0, ly1;    /* log10 range, whole decades */
};

static int map_x(const struct axes *a, double x)
{
    return a->left + (int)lround((log10(x) - a->lx0) / (a->lx1 - a->lx0) * (a->right - a->left));
}

static int map_y(const struct axes *a, double y)
{
    return a->bottom - (int)lround((log10(y) - a->ly0) / (a->ly1 - a->ly0) * (a->bottom - a->top));
}

static void decade_label(char *buf, size_t n, int e)
{
    if (e >= 0 && e <= 3)
        snprintf(buf, n, "%g", pow(10.0, e));
    else
        snprintf(buf, n, "1e%d", e);
}

static void draw_axes(struct canvas *c, const struct axes *a, const struct plot_desc *d)
{
    static const uint8_t grid[3] = {225, 225, 225}, ink[3] = {40, 40, 40};
    char buf[32];
    for (int e = (int)a->lx0; e <= (int)a->lx1; e++) {
        for (int m = 1; m < 10; m++) {
            double v = log10(m) + e;
            if (v > a->lx1 + 1e-9)
                break;
            int x = a->left + (int)lround((v - a->lx0) / (a->lx1 - a->lx0) * (a->right - a->left));
            line(c, x, a->top, x, a->bottom, 1, m == 1 ? (const uint8_t[3]){200, 200, 200} : grid);
        }
        int x = map_x(a, pow(10.0, e));
        decade_label(buf, sizeof buf, e);
        text(c, x - text_width(buf, 1) / 2, a->bottom + 6, 1, buf, ink);
    }
    for (int e = (int)a->ly0; e <= (int)a->ly1; e++) {
        for (int m = 1; m < 10; m++) {
            double v = log10(m) + e;
            if (v > a->ly1 + 1e-9)
                break;
            int y =
                a->bottom - (int)lround((v - a->ly0) / (a->ly1 - a->ly0) * (a->bottom - a->top));
            line(c, a->left, y, a->right, y, 1, m == 1 ? (const uint8_t[3]){200, 200, 200} : grid);
        }
        int y = map_y(a, pow(10.0, e));
        decade_label(buf, sizeof buf, e);
        text(c, a->left - 6 - text_width(buf, 1), y - 3, 1, buf, ink);
    }
    line(c, a->left, a->bottom, a->right, a->bottom, 1, ink);
    line(c, a->left, a->top, a->left, a->bottom, 1, ink);
    line(c, a->right, a->top, a->right, a->bottom, 1, ink);
    line(c, a->left, a->top, a->right, a->top, 1, ink);
    text(c, (a->left + a->right - text_width(d->x_label, 1)) / 2, a->bottom + 22, 1, d->x_label,
         ink);
    text_up(c, 12, (a->top + a->bottom + text_width(d->y_label, 1)) / 2, 1, d->y_label, ink);
    text(c, (c->w - text_width(d->title, 2)) / 2, 8, 2, d->title, ink);
}

static int cmp_x(const void *pa, const void *pb)
{
    const struct plot_point *a = pa, *b = pb;
    return (a->x > b->x) - (a->x < b->x);
}

/* The front points joined in order of x: one line through all of them, or one per series. */
static void draw_front(struct canvas *c, const struct axes *a, const struct plot_desc *d)
{
    struct plot_point *f = malloc(sizeof *f * (size_t)(d->count ? d->count : 1));
    static const uint8_t front_ink[3] = {0, 0, 0};
    int groups = d->front_across_series ? 1 : PLOT_MAX_SERIES;
    for (int s = 0; f && s < groups; s++) {
        int n = 0;
        for (int i = 0; i < d->count; i++)
            if (d->points[i].front && (d->front_across_series || d->points[i].series == s) &&
                usable(&d->points[i]))
                f[n++] = d->points[i];
        qsort(f, (size_t)n, sizeof *f, cmp_x);
        for (int i = 1; i < n; i++)
            line(c, map_x(a, f[i - 1].x), map_y(a, f[i - 1].y), map_x(a, f[i].x), map_y(a, f[i].y),
                 2, front_ink);
    }
    free(f);
}

static void draw_legend(struct canvas *c, const struct axes *a, const struct plot_desc *d)
{
    static const uint8_t ink[3] = {40, 40, 40}, black[3] = {0, 0, 0};
    int x = a->right + 14, y = a->top + 4;
    for (int s = 0; s < d->series_count && s < PLOT_MAX_SERIES; s++) {
        marker(c, x + 4, y + 3, 4, s, palette[s]);
        text(c, x + 14, y, 1, d->series_names[s] ? d->series_names[s] : "?", ink);
        y += 16;
    }
    line(c, x, y + 4, x + 9, y + 4, 2, black);
    text(c, x + 14, y + 1, 1, "Pareto front", ink);
}

enum refract_code plot_write_png(const struct plot_desc *d, const char *path, struct err *e)
{
    struct canvas c = {.w = d->width ? d->width : 720, .h = d->height ? d->height : 460};
    c.px = malloc((size_t)c.w * c.h * 4);
    if (c.px == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a %dx%d plot", c.w, c.h);
    memset(c.px, 255, (size_t)c.w * c.h * 4);
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int i = 0; i < d->count; i++) {
        if (!usable(&d->points[i]))
            continue;
        x0 = fmin(x0, d->points[i].x);
        x1 = fmax(x1, d->points[i].x);
        y0 = fmin(y0, d->points[i].y);
        y1 = fmax(y1, d->points[i].y);
    }
    if (!(x0 <= x1))
        x0 = x1 = y0 = y1 = 1.0;
    struct axes a = {.left = 78, .right = c.w - 150, .top = 34, .bottom = c.h - 44};
    a.lx0 = floor(log10(x0));
    a.lx1 = fmax(ceil(log10(x1)), a.lx0 + 1);
    a.ly0 = floor(log10(y0));
    a.ly1 = fmax(ceil(log10(y1)), a.ly0 + 1);
    draw_axes(&c, &a, d);
    draw_front(&c, &a, d);
    for (int i = 0; i < d->count; i++) {
        const struct plot_point *p = &d->points[i];
        if (!usable(p) || p->series < 0 || p->series >= PLOT_MAX_SERIES)
            continue;
        int x = map_x(&a, p->x), y = map_y(&a, p->y);
        if (p->front)
            marker(&c, x, y, 6, p->series, (const uint8_t[3]){0, 0, 0});
        marker(&c, x, y, 4, p->series, palette[p->series]);
    }
    draw_legend(&c, &a, d);
    void *png = NULL;
    size_t len = 0;
    enum refract_code rc = io_encode_png(c.px, c.w, c.h, &png, &len, e);
    free(c.px);
    if (rc != REFRACT_E_OK)
        return rc;
    FILE *f = fopen(path, "wb");
    if (f == NULL || fwrite(png, 1, len, f) != len) {
        if (f)
            fclose(f);
        free(png);
        return err_set(e, REFRACT_E_IO, "cannot write %s; check that its directory exists", path);
    }
    fclose(f);
    free(png);
    return REFRACT_E_OK;
}

/*
 * plot.h - scatter plots with log axes, drawn into an RGBA8 canvas by a small rasterizer
 * (lines, markers, the 5x7 font of server/scene/font5x7) and written as PNG with
 * io_encode_png: the figures of docs/accuracy.md, without a plotting library.
 *
 * Ownership: everything borrowed for the call. Thread: any.
 */
#ifndef REFRACT_BENCH_PLOT_H
#define REFRACT_BENCH_PLOT_H

#include <stdbool.h>

#include "core/err.h"

#define PLOT_MAX_SERIES 8

struct plot_point {
    double x, y; /* data units; both > 0 (log axes) */
    int series;  /* 0..series_count-1: colour, marker and legend entry */
    bool front;  /* on the Pareto front: drawn larger; a series' front points are joined */
};

struct plot_desc {
    const char *title;
    const char *x_label, *y_label;
    const char *series_names[PLOT_MAX_SERIES];
    int series_count;
    const struct plot_point *points;
    int count;
    bool front_across_series; /* one front over all series (else one per series) */
    int width, height;        /* pixels; 0 = 720 x 460 */
};

/* Draws the plot (log10 x and y axes over the points' range, decade grid, legend, the
 * front points joined in order of x) and writes it to path as PNG. Points that are not
 * finite and positive are left out. */
enum refract_code plot_write_png(const struct plot_desc *d, const char *path, struct err *e);

#endif

/*
 * irradiance_index.h - where the irradiance cache records which volumes it keeps on disk:
 * the data directory's SQLite database (the store implements it: store_irradiance.c).
 *
 * The volumes themselves stay files, <data>/irradiance/<key>.exr + <key>.json, written
 * atomically by cache_disk.c; the index holds one row per complete pair (key, bytes, when
 * made, when last used), so that the daemon knows after a restart what it has, which
 * volumes were used least recently, and how much disk the cache takes
 * (`--irradiance-disk-budget`, GET /v1/storage). A row is committed after its files are
 * in place; at start-up rows without files are dropped and files without a row (a crash
 * between the rename and the commit) are adopted (cache_disk.c, irr_disk_index).
 *
 * The cache calls these from its worker thread and at start-up, never holding its own
 * lock, so the store's lock (and SQLite's fsync) never sits inside the cache's.
 */
#ifndef REFRACT_IRRADIANCE_INDEX_H
#define REFRACT_IRRADIANCE_INDEX_H

#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"

struct irradiance_index_row {
    uint64_t key;         /* the cache key (irradiance_cache_key) */
    uint64_t transport;   /* the scene half of the key (0 when adopted from files) */
    uint64_t bytes;       /* <key>.exr + <key>.json */
    int64_t created_unix; /* seconds */
    int64_t last_used_ms; /* unix milliseconds of the last use (read back or rendered) */
};

struct irradiance_index {
    void *ctx;
    /* Inserts or replaces the row. */
    enum refract_code (*put)(void *ctx, const struct irradiance_index_row *row, struct err *e);
    /* Sets last_used_ms of the rows that exist (keys[i], used_ms[i]). */
    enum refract_code (*touch)(void *ctx, const uint64_t *keys, const int64_t *used_ms,
                               size_t count, struct err *e);
    /* Deletes the row (no error when absent). */
    enum refract_code (*remove)(void *ctx, uint64_t key, struct err *e);
    /* Every row, least recently used first; *rows is malloc'd (caller frees). */
    enum refract_code (*list)(void *ctx, struct irradiance_index_row **rows, size_t *count,
                              struct err *e);
};

#endif

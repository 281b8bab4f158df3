/*
 * store_irradiance.c - the irradiance cache's index in the data directory's database
 * (server/cache/irradiance_index.h): one row per volume the cache keeps on disk.
 *
 *   irradiance(key TEXT PRIMARY KEY (16 hex digits, the file name), transport TEXT,
 *              bytes INTEGER, created INTEGER (unix s), last_used INTEGER (unix ms))
 *
 * The files are written before their row is committed (cache_disk.c), so a row always
 * names a complete pair; the start-up reconciliation handles the other order. Each call
 * takes the store's lock for one statement or one transaction.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cache/irradiance_index.h"
#include "store_internal.h"

static enum refract_code fail(struct store *s, struct err *e, const char *what)
{
    return err_set(e, REFRACT_E_STORAGE, "data directory database (%s/refract.db): %s: %s",
                   s->data_dir, what, sqlite3_errmsg(s->db));
}

static void key_text(uint64_t key, char out[17])
{
    snprintf(out, 17, "%016" PRIx64, key);
}

static enum refract_code put(void *ctx, const struct irradiance_index_row *row, struct err *e)
{
    struct store *s = ctx;
    char key[17], transport[17];
    key_text(row->key, key);
    key_text(row->transport, transport);
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = REFRACT_E_OK;
    sqlite3_stmt *q = NULL;
    if (sqlite3_prepare_v2(s->db,
                           "INSERT OR REPLACE INTO irradiance(key, transport, bytes, created,"
                           " last_used) VALUES (?1, ?2, ?3, ?4, ?5)",
                           -1, &q, NULL) != SQLITE_OK) {
        rc = fail(s, e, "preparing an irradiance row");
    } else {
        sqlite3_bind_text(q, 1, key, -1, SQLITE_STATIC);
        sqlite3_bind_text(q, 2, transport, -1, SQLITE_STATIC);
        sqlite3_bind_int64(q, 3, (sqlite3_int64)row->bytes);
        sqlite3_bind_int64(q, 4, row->created_unix);
        sqlite3_bind_int64(q, 5, row->last_used_ms);
        if (sqlite3_step(q) != SQLITE_DONE)
            rc = fail(s, e, "recording an irradiance volume");
    }
    sqlite3_finalize(q);
    pthread_mutex_unlock(&s->lock);
    return rc;
}

/* One transaction for the batch: one fsync however many volumes were used. */
static enum refract_code touch(void *ctx, const uint64_t *keys, const int64_t *used_ms,
                               size_t count, struct err *e)
{
    struct store *s = ctx;
    if (count == 0)
        return REFRACT_E_OK;
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = store_db_begin_locked(s, e);
    sqlite3_stmt *q = NULL;
    if (rc == REFRACT_E_OK &&
        sqlite3_prepare_v2(s->db, "UPDATE irradiance SET last_used = ?2 WHERE key = ?1", -1, &q,
                           NULL) != SQLITE_OK)
        rc = fail(s, e, "preparing an irradiance update");
    for (size_t i = 0; rc == REFRACT_E_OK && i < count; i++) {
        char key[17];
        key_text(keys[i], key);
        sqlite3_bind_text(q, 1, key, -1, SQLITE_TRANSIENT);
        sqlite3_bind_int64(q, 2, used_ms[i]);
        if (sqlite3_step(q) != SQLITE_DONE)
            rc = fail(s, e, "updating an irradiance row");
        sqlite3_reset(q);
    }
    sqlite3_finalize(q);
    if (rc == REFRACT_E_OK)
        rc = store_db_commit_locked(s, e);
    else
        store_db_rollback_locked(s);
    pthread_mutex_unlock(&s->lock);
    return rc;
}

static enum refract_code remove_row(void *ctx, uint64_t key, struct err *e)
{
    struct store *s = ctx;
    char k[17];
    key_text(key, k);
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = REFRACT_E_OK;
    sqlite3_stmt *q = NULL;
    if (sqlite3_prepare_v2(s->db, "DELETE FROM irradiance WHERE key = ?1", -1, &q, NULL) !=
        SQLITE_OK) {
        rc = fail(s, e, "preparing an irradiance delete");
    } else {
        sqlite3_bind_text(q, 1, k, -1, SQLITE_STATIC);
        if (sqlite3_step(q) != SQLITE_DONE)
            rc = fail(s, e, "deleting an irradiance row");
    }
    sqlite3_finalize(q);
    pthread_mutex_unlock(&s->lock);
    return rc;
}

static uint64_t hex_column(sqlite3_stmt *q, int col)
{
    const unsigned char *t = sqlite3_column_text(q, col);
    return t ? strtoull((const char *)t, NULL, 16) : 0;
}

static enum refract_code list(void *ctx, struct irradiance_index_row **rows, size_t *count,
                              struct err *e)
{
    struct store *s = ctx;
    *rows = NULL;
    *count = 0;
    size_t cap = 0;
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = REFRACT_E_OK;
    sqlite3_stmt *q = NULL;
    if (sqlite3_prepare_v2(s->db,
                           "SELECT key, transport, bytes, created, last_used FROM irradiance"
                           " ORDER BY last_used, key",
                           -1, &q, NULL) != SQLITE_OK)
        rc = fail(s, e, "preparing the irradiance list");
    int step;
    while (rc == REFRACT_E_OK && (step = sqlite3_step(q)) == SQLITE_ROW) {
        if (*count == cap) {
            size_t grown_cap = cap ? 2 * cap : 64;
            struct irradiance_index_row *grown = realloc(*rows, grown_cap * sizeof *grown);
            if (grown == NULL) {
                rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory listing irradiance rows");
                break;
            }
            *rows = grown;
            cap = grown_cap;
        }
        struct irradiance_index_row *r = &(*rows)[(*count)++];
        r->key = hex_column(q, 0);
        r->transport = hex_column(q, 1);
        r->bytes = (uint64_t)sqlite3_column_int64(q, 2);
        r->created_unix = sqlite3_column_int64(q, 3);
        r->last_used_ms = sqlite3_column_int64(q, 4);
    }
    if (rc == REFRACT_E_OK && step != SQLITE_DONE)
        rc = fail(s, e, "listing irradiance rows");
    sqlite3_finalize(q);
    pthread_mutex_unlock(&s->lock);
    if (rc != REFRACT_E_OK) {
        free(*rows);
        *rows = NULL;
        *count = 0;
    }
    return rc;
}

void store_irradiance_index(struct store *s, struct irradiance_index *out)
{
    *out = (struct irradiance_index){
        .ctx = s, .put = put, .touch = touch, .remove = remove_row, .list = list};
}

void store_irradiance_usage(struct store *s, long long *volumes, unsigned long long *bytes)
{
    *volumes = 0;
    *bytes = 0;
    pthread_mutex_lock(&s->lock);
    sqlite3_stmt *q = NULL;
    if (sqlite3_prepare_v2(s->db, "SELECT count(*), coalesce(sum(bytes), 0) FROM irradiance", -1,
                           &q, NULL) == SQLITE_OK &&
        sqlite3_step(q) == SQLITE_ROW) {
        *volumes = sqlite3_column_int64(q, 0);
        *bytes = (unsigned long long)sqlite3_column_int64(q, 1);
    }
    sqlite3_finalize(q);
    pthread_mutex_unlock(&s->lock);
}

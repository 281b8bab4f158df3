/*
 * store_db.c - the data directory's metadata in SQLite: <data>/refract.db in WAL mode
 * with synchronous=FULL, so a commit is on disk when it returns and a kill -9 or a power
 * cut keeps every committed transaction. One connection, used under the store's lock
 * (SQLite's own mutexes stay on: a cheap second line of defence).
 *
 * SCHEMA (version 1; `meta.schema_version`):
 *   scenes(id, document, generation, created)
 *   uploads(scene -> scenes.id, kind, name, dims, type, components, min/max, checksum,
 *           blob, bytes, info JSON, created); one row per (scene, kind, name)
 *   jobs(id, scene, spec JSON, state, frames_total, frames_done, created, updated,
 *        message, started, finished) and job_frames(job, frame, blob, bytes): batch jobs
 *        (server/jobs/, store_jobs.c); job_frames' blobs count as references
 *   irradiance(key, transport, bytes, created, last_used): the irradiance cache's index
 *        of the volume files it keeps under <data>/irradiance (store_irradiance.c; added
 *        after version 1 shipped: CREATE IF NOT EXISTS adds it to older databases)
 *   meta(key, value)
 */
#include <cjson/cJSON.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "store_internal.h"

static const char schema_sql[] =
    "CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS scenes("
    " id TEXT PRIMARY KEY, document TEXT NOT NULL, generation INTEGER NOT NULL,"
    " created INTEGER NOT NULL);"
    "CREATE TABLE IF NOT EXISTS uploads("
    " scene TEXT NOT NULL REFERENCES scenes(id) ON DELETE CASCADE,"
    " kind TEXT NOT NULL CHECK (kind IN ('volume', 'environment', 'mesh')),"
    " name TEXT NOT NULL, dims_x INTEGER NOT NULL, dims_y INTEGER NOT NULL,"
    " dims_z INTEGER NOT NULL, type TEXT NOT NULL, components INTEGER NOT NULL,"
    " min REAL NOT NULL, max REAL NOT NULL, checksum TEXT NOT NULL, blob TEXT NOT NULL,"
    " bytes INTEGER NOT NULL, info TEXT NOT NULL, created INTEGER NOT NULL,"
    " PRIMARY KEY (scene, kind, name));"
    "CREATE INDEX IF NOT EXISTS uploads_blob ON uploads(blob);"
    "CREATE TABLE IF NOT EXISTS jobs("
    " id TEXT PRIMARY KEY, scene TEXT, spec TEXT NOT NULL,"
    " state TEXT NOT NULL CHECK (state IN ('queued', 'running', 'done', 'failed',"
    " 'cancelled')),"
    " frames_total INTEGER NOT NULL DEFAULT 0, frames_done INTEGER NOT NULL DEFAULT 0,"
    " created INTEGER NOT NULL, updated INTEGER NOT NULL, message TEXT,"
    " started INTEGER, finished INTEGER);"
    "CREATE TABLE IF NOT EXISTS job_frames("
    " job TEXT NOT NULL REFERENCES jobs(id) ON DELETE CASCADE, frame INTEGER NOT NULL,"
    " blob TEXT NOT NULL, bytes INTEGER NOT NULL, PRIMARY KEY (job, frame));"
    "CREATE INDEX IF NOT EXISTS job_frames_blob ON job_frames(blob);"
    "CREATE TABLE IF NOT EXISTS irradiance("
    " key TEXT PRIMARY KEY, transport TEXT NOT NULL, bytes INTEGER NOT NULL,"
    " created INTEGER NOT NULL, last_used INTEGER NOT NULL);"
    "INSERT OR IGNORE INTO meta(key, value) VALUES ('schema_version', '1');";

static enum refract_code db_fail(struct store *s, struct err *e, const char *what)
{
    return err_set(e, REFRACT_E_STORAGE, "data directory database (%s/refract.db): %s: %s",
                   s->data_dir, what, sqlite3_errmsg(s->db));
}

static enum refract_code exec(struct store *s, const char *sql, struct err *e)
{
    char *msg = NULL;
    if (sqlite3_exec(s->db, sql, NULL, NULL, &msg) == SQLITE_OK)
        return REFRACT_E_OK;
    err_set(e, REFRACT_E_STORAGE, "data directory database (%s/refract.db): %s", s->data_dir,
            msg ? msg : "error");
    sqlite3_free(msg);
    return REFRACT_E_STORAGE;
}

enum refract_code store_db_open(struct store *s, struct err *e)
{
    char path[STORE_PATH_MAX];
    snprintf(path, sizeof path, "%s/refract.db", s->data_dir);
    int rc = sqlite3_open_v2(
        path, &s->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, NULL);
    if (rc != SQLITE_OK) {
        err_set(e, REFRACT_E_STORAGE, "cannot open %s: %s (check the permissions of --data-dir)",
                path, s->db ? sqlite3_errmsg(s->db) : sqlite3_errstr(rc));
        sqlite3_close(s->db);
        s->db = NULL;
        return REFRACT_E_STORAGE;
    }
    sqlite3_busy_timeout(s->db, 5000);
    /* WAL: readers never block the writer; FULL: the WAL is fsynced at every commit, so
     * a commit that returned survives power loss, not only a process crash. */
    enum refract_code code = exec(s,
                                  "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;"
                                  " PRAGMA foreign_keys=ON;",
                                  e);
    if (code == REFRACT_E_OK)
        code = exec(s, schema_sql, e);
    char version[16] = "";
    if (code == REFRACT_E_OK &&
        store_db_meta_get_locked(s, "schema_version", version, sizeof version) &&
        strcmp(version, "1") != 0)
        code = err_set(e, REFRACT_E_STORAGE,
                       "%s has schema version %s; this refractd reads version 1 (a newer "
                       "refractd made it?)",
                       path, version);
    if (code != REFRACT_E_OK) {
        sqlite3_close(s->db);
        s->db = NULL;
    }
    return code;
}

void store_db_close(struct store *s)
{
    if (s->db) {
        /* A clean close checkpoints the WAL into the database file. */
        sqlite3_close(s->db);
        s->db = NULL;
    }
}

enum refract_code store_db_begin_locked(struct store *s, struct err *e)
{
    return exec(s, "BEGIN IMMEDIATE", e);
}

enum refract_code store_db_commit_locked(struct store *s, struct err *e)
{
    return exec(s, "COMMIT", e);
}

void store_db_rollback_locked(struct store *s)
{
    sqlite3_exec(s->db, "ROLLBACK", NULL, NULL, NULL);
}

static sqlite3_stmt *prepare(struct store *s, const char *sql, struct err *e)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(s->db, sql, -1, &st, NULL) != SQLITE_OK) {
        db_fail(s, e, "prepare");
        return NULL;
    }
    return st;
}

/* Steps a statement that returns no rows and finalizes it. */
static enum refract_code step_done(struct store *s, sqlite3_stmt *st, const char *what,
                                   struct err *e)
{
    int rc = sqlite3_step(st);
    enum refract_code code = rc == SQLITE_DONE ? REFRACT_E_OK : db_fail(s, e, what);
    sqlite3_finalize(st);
    return code;
}

enum refract_code store_db_scene_put_locked(struct store *s, const struct store_scene *v,
                                            struct err *e)
{
    sqlite3_stmt *st = prepare(s,
                               "INSERT INTO scenes(id, document, generation, created)"
                               " VALUES (?1, ?2, ?3, ?4) ON CONFLICT(id) DO UPDATE SET"
                               " document = excluded.document, generation = excluded.generation",
                               e);
    if (st == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(st, 1, v->id, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, v->json, (int)v->json_len, SQLITE_STATIC);
    sqlite3_bind_int64(st, 3, (sqlite3_int64)v->generation);
    sqlite3_bind_int64(st, 4, v->created_unix);
    return step_done(s, st, "saving a scene", e);
}

enum refract_code store_db_scene_delete_locked(struct store *s, const char *id, bool keep_scene_row,
                                               char (**blobs)[SHA256_HEX_SIZE], size_t *count,
                                               struct err *e)
{
    if (blobs) {
        *blobs = NULL;
        *count = 0;
        sqlite3_stmt *q = prepare(s, "SELECT DISTINCT blob FROM uploads WHERE scene = ?1", e);
        if (q == NULL)
            return REFRACT_E_STORAGE;
        sqlite3_bind_text(q, 1, id, -1, SQLITE_STATIC);
        size_t cap = 0;
        while (sqlite3_step(q) == SQLITE_ROW) {
            if (*count == cap) {
                cap = cap ? cap * 2 : 8;
                char(*grown)[SHA256_HEX_SIZE] = realloc(*blobs, cap * sizeof *grown);
                if (grown == NULL)
                    break; /* the sweep at the next start-up collects the rest */
                *blobs = grown;
            }
            snprintf((*blobs)[(*count)++], SHA256_HEX_SIZE, "%s",
                     (const char *)sqlite3_column_text(q, 0));
        }
        sqlite3_finalize(q);
    }
    sqlite3_stmt *st = prepare(s, "DELETE FROM uploads WHERE scene = ?1", e);
    if (st == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    enum refract_code rc = step_done(s, st, "deleting a scene's uploads", e);
    if (rc != REFRACT_E_OK || keep_scene_row)
        return rc;
    st = prepare(s, "DELETE FROM scenes WHERE id = ?1", e);
    if (st == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    return step_done(s, st, "deleting a scene", e);
}

static char *info_json(const struct store_upload_info *in)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "format", in->format);
    cJSON_AddStringToObject(o, "sha256", in->sha256);
    cJSON_AddItemToObject(o, "min", cJSON_CreateDoubleArray(in->min, 3));
    cJSON_AddItemToObject(o, "max", cJSON_CreateDoubleArray(in->max, 3));
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

static void info_from_json(const char *text, struct store_upload_info *out)
{
    cJSON *o = cJSON_Parse(text ? text : "");
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(o, "format");
    if (cJSON_IsString(f))
        snprintf(out->format, sizeof out->format, "%s", f->valuestring);
    const char *keys[2] = {"min", "max"};
    double *dst[2] = {out->min, out->max};
    for (int k = 0; k < 2; k++) {
        const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, keys[k]);
        for (int c = 0; c < 3 && cJSON_IsArray(a); c++) {
            const cJSON *x = cJSON_GetArrayItem(a, c);
            if (cJSON_IsNumber(x))
                dst[k][c] = x->valuedouble;
        }
    }
    cJSON_Delete(o);
}

enum refract_code store_db_upload_put_locked(struct store *s, const struct store_upload_row *row,
                                             char old_blob[SHA256_HEX_SIZE], struct err *e)
{
    old_blob[0] = '\0';
    sqlite3_stmt *q =
        prepare(s, "SELECT blob FROM uploads WHERE scene = ?1 AND kind = ?2 AND name = ?3", e);
    if (q == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(q, 1, row->scene, -1, SQLITE_STATIC);
    sqlite3_bind_text(q, 2, row->kind, -1, SQLITE_STATIC);
    sqlite3_bind_text(q, 3, row->name, -1, SQLITE_STATIC);
    if (sqlite3_step(q) == SQLITE_ROW)
        snprintf(old_blob, SHA256_HEX_SIZE, "%s", (const char *)sqlite3_column_text(q, 0));
    sqlite3_finalize(q);
    sqlite3_stmt *st =
        prepare(s,
                "INSERT OR REPLACE INTO uploads(scene, kind, name, dims_x, dims_y, dims_z, type,"
                " components, min, max, checksum, blob, bytes, info, created)"
                " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15)",
                e);
    if (st == NULL)
        return REFRACT_E_STORAGE;
    const struct store_upload_info *in = &row->info;
    char sum[17];
    snprintf(sum, sizeof sum, "%016" PRIx64, in->checksum);
    char *info = info_json(in);
    sqlite3_bind_text(st, 1, row->scene, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, row->kind, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 3, row->name, -1, SQLITE_STATIC);
    for (int a = 0; a < 3; a++)
        sqlite3_bind_int(st, 4 + a, in->dims[a]);
    sqlite3_bind_text(st, 7, in->type, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 8, in->components);
    sqlite3_bind_double(st, 9, in->min_all);
    sqlite3_bind_double(st, 10, in->max_all);
    sqlite3_bind_text(st, 11, sum, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 12, in->sha256, -1, SQLITE_STATIC);
    sqlite3_bind_int64(st, 13, (sqlite3_int64)in->bytes);
    sqlite3_bind_text(st, 14, info ? info : "{}", -1, SQLITE_STATIC);
    sqlite3_bind_int64(st, 15, in->created_unix);
    enum refract_code rc = step_done(s, st, "saving an upload", e);
    cJSON_free(info);
    if (strcmp(old_blob, in->sha256) == 0)
        old_blob[0] = '\0'; /* the same content again: nothing was replaced */
    return rc;
}

bool store_db_blob_referenced_locked(struct store *s, const char *hash)
{
    struct err e;
    sqlite3_stmt *q = prepare(s,
                              "SELECT 1 FROM uploads WHERE blob = ?1"
                              " UNION ALL SELECT 1 FROM job_frames WHERE blob = ?1 LIMIT 1",
                              &e);
    if (q == NULL)
        return true; /* when in doubt, keep the file */
    sqlite3_bind_text(q, 1, hash, -1, SQLITE_STATIC);
    int rc = sqlite3_step(q);
    sqlite3_finalize(q);
    return rc != SQLITE_DONE;
}

enum refract_code store_db_each_scene(struct store *s, store_db_scene_fn fn, void *ctx,
                                      struct err *e)
{
    sqlite3_stmt *q =
        prepare(s, "SELECT id, document, created, generation FROM scenes ORDER BY id", e);
    if (q == NULL)
        return REFRACT_E_STORAGE;
    while (sqlite3_step(q) == SQLITE_ROW)
        fn(s, (const char *)sqlite3_column_text(q, 0), (const char *)sqlite3_column_text(q, 1),
           (size_t)sqlite3_column_bytes(q, 1), sqlite3_column_int64(q, 2),
           (uint64_t)sqlite3_column_int64(q, 3), ctx);
    sqlite3_finalize(q);
    return REFRACT_E_OK;
}

enum refract_code store_db_each_upload(struct store *s, const char *scene, store_db_upload_fn fn,
                                       void *ctx, struct err *e)
{
    sqlite3_stmt *q = prepare(s,
                              "SELECT scene, kind, name, dims_x, dims_y, dims_z, type, components,"
                              " min, max, checksum, blob, bytes, info, created FROM uploads"
                              " WHERE scene = ?1 ORDER BY kind, name",
                              e);
    if (q == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(q, 1, scene, -1, SQLITE_STATIC);
    while (sqlite3_step(q) == SQLITE_ROW) {
        struct store_upload_row row = {0};
        snprintf(row.scene, sizeof row.scene, "%s", (const char *)sqlite3_column_text(q, 0));
        snprintf(row.kind, sizeof row.kind, "%s", (const char *)sqlite3_column_text(q, 1));
        snprintf(row.name, sizeof row.name, "%s", (const char *)sqlite3_column_text(q, 2));
        struct store_upload_info *in = &row.info;
        for (int a = 0; a < 3; a++)
            in->dims[a] = sqlite3_column_int(q, 3 + a);
        snprintf(in->type, sizeof in->type, "%s", (const char *)sqlite3_column_text(q, 6));
        in->components = sqlite3_column_int(q, 7);
        in->min_all = sqlite3_column_double(q, 8);
        in->max_all = sqlite3_column_double(q, 9);
        in->checksum = strtoull((const char *)sqlite3_column_text(q, 10), NULL, 16);
        snprintf(in->sha256, sizeof in->sha256, "%s", (const char *)sqlite3_column_text(q, 11));
        in->bytes = (size_t)sqlite3_column_int64(q, 12);
        info_from_json((const char *)sqlite3_column_text(q, 13), in);
        in->created_unix = sqlite3_column_int64(q, 14);
        fn(s, &row, ctx);
    }
    sqlite3_finalize(q);
    return REFRACT_E_OK;
}

bool store_db_meta_get_locked(struct store *s, const char *key, char *out, size_t size)
{
    struct err e;
    sqlite3_stmt *q = prepare(s, "SELECT value FROM meta WHERE key = ?1", &e);
    if (q == NULL)
        return false;
    sqlite3_bind_text(q, 1, key, -1, SQLITE_STATIC);
    bool found = sqlite3_step(q) == SQLITE_ROW;
    if (found)
        snprintf(out, size, "%s", (const char *)sqlite3_column_text(q, 0));
    sqlite3_finalize(q);
    return found;
}

enum refract_code store_db_meta_set_locked(struct store *s, const char *key, const char *value,
                                           struct err *e)
{
    sqlite3_stmt *st = prepare(s, "INSERT OR REPLACE INTO meta(key, value) VALUES (?1, ?2)", e);
    if (st == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, value, -1, SQLITE_STATIC);
    return step_done(s, st, "saving meta", e);
}

long long store_db_upload_count_locked(struct store *s)
{
    struct err e;
    sqlite3_stmt *q = prepare(s, "SELECT COUNT(*) FROM uploads", &e);
    if (q == NULL)
        return -1;
    long long n = sqlite3_step(q) == SQLITE_ROW ? sqlite3_column_int64(q, 0) : -1;
    sqlite3_finalize(q);
    return n;
}

size_t store_db_replace_credit_locked(struct store *s, const char *scene, const char *kind,
                                      const char *name)
{
    struct err e;
    sqlite3_stmt *q = prepare(s,
                              "SELECT u.bytes, (SELECT COUNT(*) FROM uploads WHERE blob = u.blob)"
                              " + (SELECT COUNT(*) FROM job_frames WHERE blob = u.blob)"
                              " FROM uploads u WHERE u.scene = ?1 AND u.kind = ?2 AND u.name = ?3",
                              &e);
    if (q == NULL)
        return 0;
    sqlite3_bind_text(q, 1, scene, -1, SQLITE_STATIC);
    sqlite3_bind_text(q, 2, kind, -1, SQLITE_STATIC);
    sqlite3_bind_text(q, 3, name, -1, SQLITE_STATIC);
    size_t credit = 0;
    if (sqlite3_step(q) == SQLITE_ROW && sqlite3_column_int64(q, 1) == 1)
        credit = (size_t)sqlite3_column_int64(q, 0);
    sqlite3_finalize(q);
    return credit;
}

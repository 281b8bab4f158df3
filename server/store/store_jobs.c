/*
 * store_jobs.c - batch jobs in the data directory (store.h, "batch jobs"): the jobs and
 * job_frames tables, and each finished frame as a content-addressed blob.
 *
 * Crash safety: a frame's blob is written and fsynced (store_blob_write_locked) before the
 * transaction that inserts its job_frames row and advances frames_done commits. A kill -9
 * before the commit leaves at most an orphan blob (collected at start-up) and frames_done
 * unchanged, so the job resumes at that frame; after it, the frame is counted and stored.
 * The UPDATE only advances frames_done from exactly `frame`, and (job, frame) is the
 * primary key, so a frame can never be recorded twice.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "store_internal.h"

static enum refract_code fail(struct store *s, struct err *e, const char *what)
{
    return err_set(e, REFRACT_E_STORAGE, "data directory database (%s/refract.db): %s: %s",
                   s->data_dir, what, sqlite3_errmsg(s->db));
}

static sqlite3_stmt *prep(struct store *s, const char *sql, struct err *e)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(s->db, sql, -1, &st, NULL) != SQLITE_OK) {
        fail(s, e, "prepare");
        return NULL;
    }
    return st;
}

enum refract_code store_job_insert(struct store *s, const struct store_job_row *row, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = REFRACT_E_OK;
    sqlite3_stmt *q =
        prep(s,
             "INSERT INTO jobs(id, scene, spec, state, frames_total, frames_done,"
             " created, updated, message) VALUES (?1, ?2, ?3, ?4, ?5, 0, ?6, ?6, NULL)",
             e);
    if (q == NULL) {
        rc = REFRACT_E_STORAGE;
    } else {
        sqlite3_bind_text(q, 1, row->id, -1, SQLITE_STATIC);
        if (row->scene[0])
            sqlite3_bind_text(q, 2, row->scene, -1, SQLITE_STATIC);
        else
            sqlite3_bind_null(q, 2); /* an inline scene (the spec holds it) */
        sqlite3_bind_text(q, 3, row->spec, -1, SQLITE_STATIC);
        sqlite3_bind_text(q, 4, row->state, -1, SQLITE_STATIC);
        sqlite3_bind_int(q, 5, row->frames_total);
        sqlite3_bind_int64(q, 6, row->created_unix);
        if (sqlite3_step(q) != SQLITE_DONE)
            rc = fail(s, e, "inserting a job");
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&s->lock);
    return rc;
}

static enum refract_code frame_rows_locked(struct store *s, const char *id, int frame,
                                           const char *hash, size_t len, struct err *e)
{
    sqlite3_stmt *ins =
        prep(s, "INSERT INTO job_frames(job, frame, blob, bytes) VALUES (?1, ?2, ?3, ?4)", e);
    if (ins == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(ins, 1, id, -1, SQLITE_STATIC);
    sqlite3_bind_int(ins, 2, frame);
    sqlite3_bind_text(ins, 3, hash, -1, SQLITE_STATIC);
    sqlite3_bind_int64(ins, 4, (sqlite3_int64)len);
    int rc = sqlite3_step(ins);
    sqlite3_finalize(ins);
    if (rc == SQLITE_CONSTRAINT)
        return err_set(e, REFRACT_E_CONFLICT, "frame %d of job %s is already stored", frame, id);
    if (rc != SQLITE_DONE)
        return fail(s, e, "inserting a job frame");
    sqlite3_stmt *up =
        prep(s,
             "UPDATE jobs SET frames_done = ?2 + 1, updated = ?3, started = COALESCE(started, ?3),"
             " state = CASE WHEN state = 'queued' THEN 'running' ELSE state END"
             " WHERE id = ?1 AND frames_done = ?2",
             e);
    if (up == NULL)
        return REFRACT_E_STORAGE;
    sqlite3_bind_text(up, 1, id, -1, SQLITE_STATIC);
    sqlite3_bind_int(up, 2, frame);
    sqlite3_bind_int64(up, 3, (sqlite3_int64)time(NULL));
    rc = sqlite3_step(up);
    sqlite3_finalize(up);
    if (rc != SQLITE_DONE)
        return fail(s, e, "advancing frames_done");
    if (sqlite3_changes(s->db) != 1)
        return err_set(e, REFRACT_E_CONFLICT,
                       "job %s is gone or is not at frame %d (frames are stored in order)", id,
                       frame);
    return REFRACT_E_OK;
}

enum refract_code store_job_frame_commit(struct store *s, const char *id, int frame,
                                         const void *bytes, size_t len, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    char hash[SHA256_HEX_SIZE];
    enum refract_code rc = store_storage_check_locked(s, len, 0, e);
    if (rc == REFRACT_E_OK)
        rc = store_blob_write_locked(s, bytes, len, hash, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_begin_locked(s, e);
    if (rc == REFRACT_E_OK) {
        rc = frame_rows_locked(s, id, frame, hash, len, e);
        if (rc == REFRACT_E_OK)
            rc = store_db_commit_locked(s, e);
        if (rc != REFRACT_E_OK) {
            store_db_rollback_locked(s);
            store_blob_release_locked(s, hash);
        }
    }
    pthread_mutex_unlock(&s->lock);
    return rc;
}

enum refract_code store_job_state_set(struct store *s, const char *id, const char *state,
                                      const char *message, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = REFRACT_E_OK;
    sqlite3_stmt *q = prep(s,
                           "UPDATE jobs SET state = ?2, message = ?3, updated = ?4,"
                           " started = COALESCE(started, CASE WHEN ?2 = 'running' THEN ?4 END),"
                           " finished = CASE WHEN ?2 IN ('done', 'failed', 'cancelled') THEN ?4"
                           " ELSE finished END WHERE id = ?1",
                           e);
    if (q == NULL) {
        rc = REFRACT_E_STORAGE;
    } else {
        sqlite3_bind_text(q, 1, id, -1, SQLITE_STATIC);
        sqlite3_bind_text(q, 2, state, -1, SQLITE_STATIC);
        if (message)
            sqlite3_bind_text(q, 3, message, -1, SQLITE_STATIC);
        else
            sqlite3_bind_null(q, 3);
        sqlite3_bind_int64(q, 4, (sqlite3_int64)time(NULL));
        if (sqlite3_step(q) != SQLITE_DONE)
            rc = fail(s, e, "updating a job");
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&s->lock);
    return rc;
}

static void copy_text(char *out, size_t size, const unsigned char *text)
{
    snprintf(out, size, "%s", text ? (const char *)text : "");
}

enum refract_code store_job_each(struct store *s, store_job_fn fn, void *ctx, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    sqlite3_stmt *q =
        prep(s,
             "SELECT id, scene, spec, state, frames_total, frames_done, created,"
             " updated, message, COALESCE(started, 0), COALESCE(finished, 0) FROM jobs"
             " ORDER BY created, id",
             e);
    if (q == NULL) {
        pthread_mutex_unlock(&s->lock);
        return REFRACT_E_STORAGE;
    }
    int rc;
    while ((rc = sqlite3_step(q)) == SQLITE_ROW) {
        struct store_job_row row = {0};
        copy_text(row.id, sizeof row.id, sqlite3_column_text(q, 0));
        copy_text(row.scene, sizeof row.scene, sqlite3_column_text(q, 1));
        row.spec = (const char *)sqlite3_column_text(q, 2);
        copy_text(row.state, sizeof row.state, sqlite3_column_text(q, 3));
        row.frames_total = sqlite3_column_int(q, 4);
        row.frames_done = sqlite3_column_int(q, 5);
        row.created_unix = sqlite3_column_int64(q, 6);
        row.updated_unix = sqlite3_column_int64(q, 7);
        copy_text(row.message, sizeof row.message, sqlite3_column_text(q, 8));
        row.started_unix = sqlite3_column_int64(q, 9);
        row.finished_unix = sqlite3_column_int64(q, 10);
        fn(&row, ctx);
    }
    sqlite3_finalize(q);
    enum refract_code out = rc == SQLITE_DONE ? REFRACT_E_OK : fail(s, e, "listing jobs");
    pthread_mutex_unlock(&s->lock);
    return out;
}

enum refract_code store_job_frame_read(struct store *s, const char *id, int frame, void **bytes,
                                       size_t *len, struct err *e)
{
    *bytes = NULL;
    *len = 0;
    char hash[SHA256_HEX_SIZE] = "";
    size_t size = 0;
    pthread_mutex_lock(&s->lock);
    sqlite3_stmt *q =
        prep(s, "SELECT blob, bytes FROM job_frames WHERE job = ?1 AND frame = ?2", e);
    int rc = SQLITE_ERROR;
    if (q != NULL) {
        sqlite3_bind_text(q, 1, id, -1, SQLITE_STATIC);
        sqlite3_bind_int(q, 2, frame);
        rc = sqlite3_step(q);
        if (rc == SQLITE_ROW) {
            copy_text(hash, sizeof hash, sqlite3_column_text(q, 0));
            size = (size_t)sqlite3_column_int64(q, 1);
        }
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&s->lock);
    if (q == NULL)
        return REFRACT_E_STORAGE;
    if (rc != SQLITE_ROW)
        return err_set(e, REFRACT_E_NOT_FOUND, "frame %d of job %s is not finished", frame, id);
    void *map = NULL;
    enum refract_code code = store_blob_map(s, hash, size, &map, e);
    if (code != REFRACT_E_OK)
        return code;
    *bytes = malloc(size ? size : 1);
    if (*bytes == NULL) {
        if (map)
            munmap(map, size);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory reading a frame");
    }
    if (size)
        memcpy(*bytes, map, size);
    if (map)
        munmap(map, size);
    *len = size;
    return REFRACT_E_OK;
}

enum refract_code store_job_frame_refs(struct store *s, const char *id, int count,
                                       struct store_job_frame_ref **out, struct err *e)
{
    *out = calloc(count > 0 ? (size_t)count : 1, sizeof **out);
    if (*out == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory listing %d frames", count);
    pthread_mutex_lock(&s->lock);
    sqlite3_stmt *q = prep(s,
                           "SELECT frame, blob, bytes FROM job_frames WHERE job = ?1 AND frame < ?2"
                           " ORDER BY frame",
                           e);
    int found = 0, rc = SQLITE_ERROR;
    if (q != NULL) {
        sqlite3_bind_text(q, 1, id, -1, SQLITE_STATIC);
        sqlite3_bind_int(q, 2, count);
        while ((rc = sqlite3_step(q)) == SQLITE_ROW && sqlite3_column_int(q, 0) == found) {
            copy_text((*out)[found].sha256, SHA256_HEX_SIZE, sqlite3_column_text(q, 1));
            (*out)[found++].bytes = (size_t)sqlite3_column_int64(q, 2);
        }
        if (rc != SQLITE_ROW && rc != SQLITE_DONE)
            fail(s, e, "listing a job's frames");
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&s->lock);
    enum refract_code code = REFRACT_E_OK;
    if (q == NULL || (rc != SQLITE_ROW && rc != SQLITE_DONE))
        code = REFRACT_E_STORAGE;
    else if (found != count)
        code = err_set(e, REFRACT_E_NOT_FOUND, "frame %d of job %s is not stored", found, id);
    if (code != REFRACT_E_OK) {
        free(*out);
        *out = NULL;
    }
    return code;
}

int store_job_frame_open(struct store *s, const struct store_job_frame_ref *ref, struct err *e)
{
    return store_blob_open(s, ref->sha256, ref->bytes, "frame blob", " (was the job deleted?)", e);
}

enum refract_code store_job_delete(struct store *s, const char *id, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    char(*blobs)[SHA256_HEX_SIZE] = NULL;
    size_t count = 0, cap = 0;
    enum refract_code rc = REFRACT_E_OK;
    sqlite3_stmt *q = prep(s, "SELECT blob FROM job_frames WHERE job = ?1", e);
    if (q == NULL)
        rc = REFRACT_E_STORAGE;
    while (q != NULL && sqlite3_step(q) == SQLITE_ROW) {
        if (count == cap) {
            cap = cap ? cap * 2 : 16;
            void *grown = realloc(blobs, cap * sizeof *blobs);
            if (grown == NULL)
                break; /* the sweep at start-up collects what is not released now */
            blobs = grown;
        }
        copy_text(blobs[count++], SHA256_HEX_SIZE, sqlite3_column_text(q, 0));
    }
    sqlite3_finalize(q);
    if (rc == REFRACT_E_OK)
        rc = store_db_begin_locked(s, e);
    if (rc == REFRACT_E_OK) {
        const char *sql[] = {"DELETE FROM job_frames WHERE job = ?1",
                             "DELETE FROM jobs WHERE id = ?1"};
        for (int i = 0; i < 2 && rc == REFRACT_E_OK; i++) {
            sqlite3_stmt *d = prep(s, sql[i], e);
            if (d == NULL) {
                rc = REFRACT_E_STORAGE;
                break;
            }
            sqlite3_bind_text(d, 1, id, -1, SQLITE_STATIC);
            if (sqlite3_step(d) != SQLITE_DONE)
                rc = fail(s, e, "deleting a job");
            sqlite3_finalize(d);
        }
        if (rc == REFRACT_E_OK)
            rc = store_db_commit_locked(s, e);
        else
            store_db_rollback_locked(s);
    }
    for (size_t i = 0; rc == REFRACT_E_OK && i < count; i++)
        store_blob_release_locked(s, blobs[i]);
    free(blobs);
    pthread_mutex_unlock(&s->lock);
    return rc;
}

enum refract_code store_scene_private(struct store *s, const char *id, const char *json, size_t len,
                                      struct store_scene **out, struct err *e)
{
    *out = NULL;
    struct scene *parsed = NULL;
    enum refract_code rc = scene_parse(json, len, &s->desc.limits, &parsed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct store_scene *v = store_version_new(s, id, NULL);
    char *copy = malloc(len + 1);
    if (v == NULL || copy == NULL) {
        free(copy);
        store_scene_release(v);
        scene_destroy(parsed);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for an inline scene");
    }
    memcpy(copy, json, len);
    copy[len] = '\0';
    v->json = copy;
    v->json_len = len;
    v->scene = parsed;
    *out = v;
    return REFRACT_E_OK;
}

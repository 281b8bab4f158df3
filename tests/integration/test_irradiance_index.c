/*
 * test_irradiance_index.c - the irradiance cache's index in the data directory's database
 * (server/cache/irradiance_index.h, store_irradiance.c):
 *   - a computed volume gets one row in refract.db's irradiance table, whose key is the
 *     files' name and whose bytes are their sizes; GET /v1/storage reports the same;
 *   - a pair of files without a row (a crash between the rename and the commit, made here
 *     by deleting the row while refractd is stopped) is adopted at start-up, and the
 *     volume is used without a recompute;
 *   - a row without files is dropped at start-up;
 *   - under --irradiance-disk-budget of one volume, a second pose removes the first one's
 *     files and row (evicted_disk), and asking for the first pose again computes it anew.
 */
#include <dirent.h>
#include <inttypes.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "irradiance_util.h"

static const char sun_down[] =
    "[{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [-0.02, -1, 0]}]";

/* Keys and byte total of the complete <key>.exr + <key>.json pairs in DATA/irradiance. */
static int files_on_disk(const char *data_dir, char keys[][17], int max, long long *bytes)
{
    char dir[400];
    snprintf(dir, sizeof dir, "%s/irradiance", data_dir);
    DIR *d = opendir(dir);
    int n = 0;
    *bytes = 0;
    struct dirent *ent;
    while (d && (ent = readdir(d)) != NULL) {
        if (strlen(ent->d_name) != 21 || strcmp(ent->d_name + 16, ".json") != 0)
            continue;
        char path[700];
        struct stat a, b;
        snprintf(path, sizeof path, "%s/%.16s.exr", dir, ent->d_name);
        if (stat(path, &a) != 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
        if (stat(path, &b) != 0)
            continue;
        if (n < max)
            snprintf(keys[n], 17, "%.16s", ent->d_name);
        n++;
        *bytes += (long long)a.st_size + (long long)b.st_size;
    }
    if (d)
        closedir(d);
    return n;
}

static sqlite3 *open_db(const char *data_dir)
{
    char path[400];
    snprintf(path, sizeof path, "%s/refract.db", data_dir);
    sqlite3 *db = NULL;
    if (sqlite3_open_v2(path, &db, SQLITE_OPEN_READWRITE, NULL) != SQLITE_OK) {
        CHECK_MSG(false, "cannot open %s: %s", path, db ? sqlite3_errmsg(db) : "?");
        sqlite3_close(db);
        return NULL;
    }
    sqlite3_busy_timeout(db, 5000);
    return db;
}

/* Rows of the irradiance table: count, and the first row's key and bytes. */
static int db_rows(const char *data_dir, char first_key[17], long long *first_bytes)
{
    sqlite3 *db = open_db(data_dir);
    if (db == NULL)
        return -1;
    sqlite3_stmt *q = NULL;
    int n = 0;
    first_key[0] = '\0';
    *first_bytes = -1;
    if (sqlite3_prepare_v2(db, "SELECT key, bytes FROM irradiance ORDER BY key", -1, &q, NULL) ==
        SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW) {
            if (n++ == 0) {
                snprintf(first_key, 17, "%s", (const char *)sqlite3_column_text(q, 0));
                *first_bytes = sqlite3_column_int64(q, 1);
            }
        }
    } else {
        CHECK_MSG(false, "no irradiance table: %s", sqlite3_errmsg(db));
        n = -1;
    }
    sqlite3_finalize(q);
    sqlite3_close(db);
    return n;
}

static void db_exec(const char *data_dir, const char *sql)
{
    sqlite3 *db = open_db(data_dir);
    char *msg = NULL;
    if (db && sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK)
        CHECK_MSG(false, "%s: %s", sql, msg ? msg : "?");
    sqlite3_free(msg);
    sqlite3_close(db);
}

static cJSON *storage(const struct test_daemon *d)
{
    struct irr_answer a = irr_http(d, "GET", "/v1/storage", NULL);
    CHECK_INT(a.status, 200);
    cJSON *o = cJSON_Parse(a.body ? a.body : "");
    free(a.body);
    CHECK(o != NULL);
    return o;
}

static double storage_irr(const struct test_daemon *d, const char *field)
{
    cJSON *o = storage(d);
    double v = irr_num(cJSON_GetObjectItemCaseSensitive(o, "irradiance"), field);
    cJSON_Delete(o);
    return v;
}

/* Polls GET /v1/storage until irradiance.volumes is `want` (files are written after the
 * volume is ready, by the cache's worker). */
static bool wait_volumes(const struct test_daemon *d, int want, double timeout_s)
{
    for (int i = 0; i < (int)(timeout_s * 20); i++) {
        if ((int)storage_irr(d, "volumes") == want)
            return true;
        usleep(50000);
    }
    return false;
}

static bool restart(struct test_daemon *d, const char *data_dir, const char *const *args)
{
    CHECK_INT(test_daemon_stop(d), 0);
    if (!test_daemon_start_in(d, data_dir, args)) {
        fprintf(stderr, "restart failed: %s\n", d->why);
        return false;
    }
    return true;
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_irradiance_index", d.why);
    char data_dir[sizeof d.data_dir];
    snprintf(data_dir, sizeof data_dir, "%s", d.data_dir);
    char *scene = beam_scene(sun_down);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, scene, id));
    free(scene);
    cJSON_Delete(irr_wait_ready(&d, id, 30));
    CHECK(wait_volumes(&d, 1, 10));

    /* One row naming the files. */
    char keys[4][17];
    long long file_bytes = 0, row_bytes = 0;
    char row_key[17];
    CHECK_INT(files_on_disk(data_dir, keys, 4, &file_bytes), 1);
    CHECK_INT(db_rows(data_dir, row_key, &row_bytes), 1);
    CHECK_STR(row_key, keys[0]);
    CHECK_INT(row_bytes, file_bytes);
    CHECK_NEAR(storage_irr(&d, "bytes"), (double)file_bytes, 0);
    CHECK_NEAR(storage_irr(&d, "disk_budget_bytes"), 8.0 * 1073741824.0, 0);

    /* Files without a row: adopted, and used without a recompute. */
    CHECK_INT(test_daemon_stop(&d), 0);
    db_exec(data_dir, "DELETE FROM irradiance");
    CHECK_INT(db_rows(data_dir, row_key, &row_bytes), 0);
    if (!test_daemon_start_in(&d, data_dir, NULL))
        test_setup_failed("test_irradiance_index (adopt)", d.why);
    CHECK_INT(db_rows(data_dir, row_key, &row_bytes), 1);
    CHECK_STR(row_key, keys[0]);
    CHECK_INT(row_bytes, file_bytes);
    cJSON *st = irr_wait_loaded(&d, id, "sun", 30);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(irr_light(st, "sun"), "loaded_from_disk")));
    CHECK_NEAR(irr_counter(st, "computed"), 0, 0);
    cJSON_Delete(st);

    /* A row without files: dropped. */
    CHECK_INT(test_daemon_stop(&d), 0);
    db_exec(data_dir, "INSERT INTO irradiance(key, transport, bytes, created, last_used)"
                      " VALUES ('00000000000000ab', '0', 1234, 0, 0)");
    CHECK_INT(db_rows(data_dir, row_key, &row_bytes), 2);
    if (!test_daemon_start_in(&d, data_dir, NULL))
        test_setup_failed("test_irradiance_index (drop)", d.why);
    CHECK_INT(db_rows(data_dir, row_key, &row_bytes), 1);
    CHECK_STR(row_key, keys[0]);
    CHECK_NEAR(storage_irr(&d, "volumes"), 1, 0);

    /* A disk budget of one volume: the second pose pushes the first off the disk. */
    char budget[32];
    snprintf(budget, sizeof budget, "%lld", file_bytes + file_bytes / 2);
    const char *tight[] = {"--irradiance-disk-budget", budget, NULL};
    if (!restart(&d, data_dir, tight))
        test_setup_failed("test_irradiance_index (budget)", d.why);
    CHECK_NEAR(storage_irr(&d, "disk_budget_bytes"), (double)(file_bytes + file_bytes / 2), 0);
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights", id);
    /* Both poses tilted slightly, mirror images of each other: with a receiver the light
     * grid covers the objects' footprint as the light sees it (docs/lightsim.md "Domain"),
     * and a beam straight down gives a uniform volume that compresses to a third of a
     * tilted one's bytes, so the budget of one volume must come from a like pose. */
    struct irr_answer a = irr_http(&d, "PUT", path,
                                   "{\"lights\": [{\"name\": \"sun\", \"type\": "
                                   "\"directional\", \"direction\": [0.02, -1, 0]}]}");
    CHECK_INT(a.status, 202);
    free(a.body);
    cJSON_Delete(irr_wait_ready(&d, id, 30));
    bool evicted = false;
    for (int i = 0; i < 200 && !evicted; i++) {
        st = irr_status(&d, id);
        evicted = irr_counter(st, "evicted_disk") >= 1;
        cJSON_Delete(st);
        if (!evicted)
            usleep(50000);
    }
    CHECK(evicted);
    CHECK(wait_volumes(&d, 1, 10)); /* the row goes right after the files */
    char after[4][17];
    long long after_bytes = 0;
    CHECK_INT(files_on_disk(data_dir, after, 4, &after_bytes), 1);
    CHECK(strcmp(after[0], keys[0]) != 0); /* the first pose's files went */
    CHECK_INT(db_rows(data_dir, row_key, &row_bytes), 1);
    CHECK_STR(row_key, after[0]);
    CHECK_NEAR(storage_irr(&d, "volumes"), 1, 0);
    CHECK(storage_irr(&d, "bytes") <= (double)(file_bytes + file_bytes / 2));

    /* The first pose again: computed anew, since its files are gone. */
    a = irr_http(&d, "PUT", path,
                 "{\"lights\": [{\"name\": \"sun\", \"type\": \"directional\", "
                 "\"direction\": [-0.02, -1, 0]}]}");
    CHECK_INT(a.status, 202);
    free(a.body);
    st = irr_wait_ready(&d, id, 30);
    CHECK(
        !cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(irr_light(st, "sun"), "loaded_from_disk")));
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    cJSON_Delete(st);
    printf("one volume: %lld bytes on disk; adopted, dropped a stale row, evicted under a "
           "budget of %s bytes\n",
           file_bytes, budget);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_irradiance_index");
}

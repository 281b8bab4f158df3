/*
 * cache_index.c - the cache's volumes on disk: the index row of each (irradiance_index.h,
 * kept in the data directory's database), when each was last used, and the disk budget
 * (`--irradiance-disk-budget`): past it, the least recently used volumes lose their files.
 *
 * Start-up reconciles the index with the directory: a row whose files are gone is
 * dropped; a complete pair without a row (a crash between its rename and the row's
 * commit, or a data directory from before the index) is adopted with the files' time as
 * its last use. Without an index (tests of the cache alone) the directory is the index.
 *
 * Uses are recorded lazily: a volume's last use reaches the database at most once a
 * minute (IRR_TOUCH_INTERVAL_MS), in one transaction per batch, from the worker thread;
 * renders never wait for an fsync.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "../core/log.h"
#include "cache_internal.h"

#define IRR_TOUCH_INTERVAL_MS 60000

int64_t irr_unix_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* Size of <key>.exr (or .pmap) + <key>.json and the sidecar's mtime; false unless both
 * exist. */
static bool pair_on_disk(const struct irradiance_cache *c, uint64_t key, uint64_t *bytes,
                         int64_t *mtime_ms)
{
    char path[700];
    struct stat a, b;
    irr_volume_path(c, key, irr_data_ext(c, key), path, sizeof path);
    if (stat(path, &a) != 0 || !S_ISREG(a.st_mode))
        return false;
    irr_volume_path(c, key, "json", path, sizeof path);
    if (stat(path, &b) != 0 || !S_ISREG(b.st_mode))
        return false;
    *bytes = (uint64_t)a.st_size + (uint64_t)b.st_size;
    *mtime_ms = (int64_t)b.st_mtim.tv_sec * 1000 + b.st_mtim.tv_nsec / 1000000;
    return true;
}

/* The sidecar goes first: the start-up scan trusts only pairs. */
static void remove_pair(const struct irradiance_cache *c, uint64_t key)
{
    char path[700];
    irr_volume_path(c, key, "json", path, sizeof path);
    remove(path);
    irr_volume_path(c, key, "exr", path, sizeof path);
    remove(path);
    irr_volume_path(c, key, "pmap", path, sizeof path);
    remove(path);
}

static struct irr_entry *add_disk_entry(struct irradiance_cache *c, uint64_t key,
                                        uint64_t transport, uint64_t bytes, int64_t used_ms)
{
    struct irr_entry *en = irr_entry_add_locked(c);
    if (en == NULL)
        return NULL;
    en->key = key;
    en->transport = transport;
    en->kind = strcmp(irr_data_ext(c, key), "pmap") == 0 ? IRR_KIND_PHOTONS : IRR_KIND_VOLUME;
    en->phase = IRR_READY;
    en->on_disk = true;
    en->disk_bytes = bytes;
    en->used_ms = used_ms;
    en->touched_ms = used_ms;
    en->last_use = ++c->tick; /* rows come least recently used first */
    return en;
}

static bool entry_known(struct irradiance_cache *c, uint64_t key)
{
    for (size_t i = 0; i < c->entry_count; i++)
        if (c->entries[i]->key == key)
            return true;
    return false;
}

void irr_index_startup(struct irradiance_cache *c)
{
    int indexed = 0, dropped = 0, adopted = 0;
    if (c->has_index) {
        struct irradiance_index_row *rows = NULL;
        size_t count = 0;
        struct err e = {0};
        if (c->index.list(c->index.ctx, &rows, &count, &e) != REFRACT_E_OK)
            log_warn("irradiance", "index: %s; using the files alone", e.msg);
        for (size_t i = 0; i < count; i++) {
            uint64_t bytes;
            int64_t mtime;
            if (entry_known(c, rows[i].key))
                continue;
            if (!pair_on_disk(c, rows[i].key, &bytes, &mtime)) {
                struct err re = {0};
                if (c->index.remove(c->index.ctx, rows[i].key, &re) != REFRACT_E_OK)
                    log_warn("irradiance", "index: %s", re.msg);
                dropped++;
                continue;
            }
            if (add_disk_entry(c, rows[i].key, rows[i].transport, bytes, rows[i].last_used_ms))
                indexed++;
        }
        free(rows);
    }
    /* Complete pairs the index does not name. */
    uint64_t *keys = NULL;
    size_t nkeys = irr_disk_list_pairs(c, &keys);
    for (size_t i = 0; i < nkeys; i++) {
        uint64_t bytes;
        int64_t mtime;
        if (entry_known(c, keys[i]) || !pair_on_disk(c, keys[i], &bytes, &mtime))
            continue;
        struct irr_entry *en = add_disk_entry(c, keys[i], 0, bytes, mtime);
        if (en == NULL)
            break;
        adopted++;
        if (c->has_index) {
            struct irradiance_index_row row = {.key = keys[i],
                                               .bytes = bytes,
                                               .created_unix = mtime / 1000,
                                               .last_used_ms = mtime};
            struct err e = {0};
            if (c->index.put(c->index.ctx, &row, &e) != REFRACT_E_OK)
                log_warn("irradiance", "index: %s", e.msg);
        }
    }
    free(keys);
    log_info("irradiance",
             "%s: %d volumes from the index, %d rows without files dropped, %d "
             "files without rows adopted",
             c->dir, indexed, dropped, adopted);
    irr_evict_disk(c);
}

void irr_index_recorded(struct irradiance_cache *c, struct irr_entry *en)
{
    uint64_t bytes = 0;
    int64_t mtime = 0;
    int64_t now = irr_unix_ms();
    bool ok = pair_on_disk(c, en->key, &bytes, &mtime);
    pthread_mutex_lock(&c->lock);
    en->disk_bytes = bytes;
    en->used_ms = now;
    en->touched_ms = now;
    uint64_t key = en->key, transport = en->transport;
    pthread_mutex_unlock(&c->lock);
    if (ok && c->has_index) {
        struct irradiance_index_row row = {.key = key,
                                           .transport = transport,
                                           .bytes = bytes,
                                           .created_unix = now / 1000,
                                           .last_used_ms = now};
        struct err e = {0};
        if (c->index.put(c->index.ctx, &row, &e) != REFRACT_E_OK)
            log_warn("irradiance", "volume %016" PRIx64 " on disk but not indexed: %s", key, e.msg);
    }
    irr_evict_disk(c);
}

void irr_note_use_locked(struct irradiance_cache *c, struct irr_entry *en)
{
    int64_t now = irr_unix_ms();
    en->used_ms = now;
    if (!c->has_index || !en->on_disk || now - en->touched_ms < IRR_TOUCH_INTERVAL_MS ||
        c->touch_count == IRR_TOUCH_MAX)
        return;
    en->touched_ms = now;
    c->touch_keys[c->touch_count] = en->key;
    c->touch_ms[c->touch_count++] = now;
    pthread_cond_signal(&c->wake);
}

void irr_index_flush_touches(struct irradiance_cache *c)
{
    uint64_t keys[IRR_TOUCH_MAX];
    int64_t ms[IRR_TOUCH_MAX];
    pthread_mutex_lock(&c->lock);
    size_t n = c->touch_count;
    memcpy(keys, c->touch_keys, n * sizeof keys[0]);
    memcpy(ms, c->touch_ms, n * sizeof ms[0]);
    c->touch_count = 0;
    pthread_mutex_unlock(&c->lock);
    struct err e = {0};
    if (n > 0 && c->index.touch(c->index.ctx, keys, ms, n, &e) != REFRACT_E_OK)
        log_warn("irradiance", "index: %s", e.msg);
}

uint64_t irr_disk_bytes_locked(const struct irradiance_cache *c)
{
    uint64_t n = 0;
    for (size_t i = 0; i < c->entry_count; i++)
        if (c->entries[i]->on_disk)
            n += c->entries[i]->disk_bytes;
    return n;
}

/* The least recently used volume whose files may go now: nothing reads or writes them and
 * it has no GPU copy (the GPU thread owns those). The newest volume on disk always stays,
 * so a budget below one volume still keeps the one just made. */
static struct irr_entry *disk_victim_locked(struct irradiance_cache *c)
{
    struct irr_entry *lru = NULL, *newest = NULL;
    for (size_t i = 0; i < c->entry_count; i++) {
        struct irr_entry *en = c->entries[i];
        if (en->on_disk && (newest == NULL || en->used_ms > newest->used_ms))
            newest = en;
    }
    for (size_t i = 0; i < c->entry_count; i++) {
        struct irr_entry *en = c->entries[i];
        if (!en->on_disk || en == newest || en->persisting || en->busy || en->loading > 0 ||
            en->uploading || en->has_gpu)
            continue;
        if (lru == NULL || en->used_ms < lru->used_ms)
            lru = en;
    }
    return lru;
}

void irr_evict_disk(struct irradiance_cache *c)
{
    for (;;) {
        pthread_mutex_lock(&c->lock);
        struct irr_entry *victim = NULL;
        if (irr_disk_bytes_locked(c) > c->desc.disk_budget_bytes)
            victim = disk_victim_locked(c);
        uint64_t key = 0;
        if (victim) {
            /* From here no reader starts on its files (they check on_disk), and the
             * cancelled entry is swept; a later request computes the pose again. The
             * files go under the lock, so that a new volume of the same key (persisted
             * by this thread only, later) can never lose its files to this removal. */
            key = victim->key;
            remove_pair(c, key);
            victim->on_disk = false;
            victim->cancelled = true;
            if (victim->has_host) {
                irr_host_free(&victim->host);
                victim->has_host = false;
            }
            c->counters.evicted_disk++;
            irr_sweep_locked(c);
        }
        pthread_mutex_unlock(&c->lock);
        if (victim == NULL)
            return;
        /* A crash before this leaves a row without files, which start-up drops. This
         * thread is the only one that records rows, so no newer row of the key exists. */
        struct err e = {0};
        if (c->has_index && c->index.remove(c->index.ctx, key, &e) != REFRACT_E_OK)
            log_warn("irradiance", "index: %s", e.msg);
        log_info("irradiance", "volume %016" PRIx64 " left the disk (--irradiance-disk-budget)",
                 key);
    }
}

/*
 * store_blob.c - content-addressed blob files: <data>/blobs/<aa>/<sha256>, immutable once
 * renamed there, and the temporary files they are made from (<data>/tmp).
 *
 * CRASH SAFETY: a blob is complete before its name exists (write to tmp, fsync the file,
 * rename, fsync the directory), and a row names it only after that (store.c commits the
 * row after store_blob_commit_locked returns). So at any kill -9 the directory holds:
 * complete blobs with rows, complete blobs without rows (an upload that died between
 * rename and commit: collected by the start-up sweep), and temporaries (removed at
 * start-up). A blob is never written in place and never partially visible.
 *
 * The collector runs under the store's lock, as do commits, so it cannot remove a blob
 * that a commit in progress is about to name.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_files.h"
#include "store_internal.h"

void store_blob_path(const struct store *s, const char *hash, char *out, size_t size)
{
    snprintf(out, size, "%s/blobs/%.2s/%s", s->data_dir, hash, hash);
}

static void fsync_dir(const char *path)
{
    int fd = open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
}

int store_tmp_create(struct store *s, const char *stem, char *path_out, size_t size, struct err *e)
{
    snprintf(path_out, size, "%s/tmp/%s-XXXXXX", s->data_dir, stem);
    int fd = mkstemp(path_out);
    if (fd >= 0)
        fcntl(fd, F_SETFD, FD_CLOEXEC);
    if (fd < 0)
        err_set(e, REFRACT_E_STORAGE, "cannot create a temporary file in %s/tmp: %s", s->data_dir,
                strerror(errno));
    return fd;
}

int store_upload_tmp_create(struct store *s, char *path_out, size_t size, struct err *e)
{
    return store_tmp_create(s, "upload", path_out, size, e);
}

enum refract_code store_storage_check_locked(struct store *s, size_t bytes, size_t credit,
                                             struct err *e)
{
    unsigned long long max = s->desc.max_storage_bytes;
    unsigned long long after =
        s->blob_bytes + bytes - (credit < s->blob_bytes ? credit : s->blob_bytes);
    if (max == 0 || after <= max)
        return REFRACT_E_OK;
    return err_set(e, REFRACT_E_STORAGE,
                   "storing %zu more bytes would exceed the data directory's limit: %llu of "
                   "%llu bytes are in use (refractd --max-storage-bytes); delete scenes or "
                   "uploads (DELETE /v1/scenes/{id}) or raise the limit",
                   bytes, s->blob_bytes, max);
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

enum refract_code store_blob_commit_locked(struct store *s, const char *tmp_path, const char *hash,
                                           size_t bytes, size_t credit, struct err *e)
{
    char path[STORE_PATH_MAX], dir[STORE_PATH_MAX];
    store_blob_path(s, hash, path, sizeof path);
    if (file_exists(path)) {
        unlink(tmp_path); /* the same content is stored already */
        return REFRACT_E_OK;
    }
    enum refract_code rc = store_storage_check_locked(s, bytes, credit, e);
    if (rc != REFRACT_E_OK) {
        unlink(tmp_path);
        return rc;
    }
    int fd = open(tmp_path, O_RDONLY | O_CLOEXEC);
    if (fd < 0 || fsync(fd) != 0) {
        rc =
            err_set(e, REFRACT_E_STORAGE, "cannot flush %s to disk: %s", tmp_path, strerror(errno));
        if (fd >= 0)
            close(fd);
        unlink(tmp_path);
        return rc;
    }
    close(fd);
    snprintf(dir, sizeof dir, "%s/blobs/%.2s", s->data_dir, hash);
    bool new_dir = !file_exists(dir);
    rc = io_mkdirs(dir, e);
    if (rc == REFRACT_E_OK && rename(tmp_path, path) != 0)
        rc = err_set(e, REFRACT_E_STORAGE, "cannot move %s to %s: %s", tmp_path, path,
                     strerror(errno));
    if (rc != REFRACT_E_OK) {
        unlink(tmp_path);
        return rc;
    }
    fsync_dir(dir);
    if (new_dir) {
        char blobs[STORE_PATH_MAX];
        snprintf(blobs, sizeof blobs, "%s/blobs", s->data_dir);
        fsync_dir(blobs);
    }
    s->blob_bytes += bytes;
    s->blob_count++;
    return REFRACT_E_OK;
}

enum refract_code store_blob_write_locked(struct store *s, const void *data, size_t len,
                                          char hash_out[SHA256_HEX_SIZE], struct err *e)
{
    struct sha256 h;
    sha256_init(&h);
    sha256_update(&h, data, len);
    sha256_final_hex(&h, hash_out);
    char path[STORE_PATH_MAX];
    store_blob_path(s, hash_out, path, sizeof path);
    if (file_exists(path))
        return REFRACT_E_OK;
    char tmp[STORE_PATH_MAX];
    int fd = store_tmp_create(s, "blob", tmp, sizeof tmp, e);
    if (fd < 0)
        return REFRACT_E_STORAGE;
    const char *p = data;
    size_t left = len;
    while (left > 0) {
        ssize_t n = write(fd, p, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            int saved = n < 0 ? errno : ENOSPC;
            close(fd);
            unlink(tmp);
            return err_set(e, REFRACT_E_STORAGE, "writing %s failed: %s", tmp, strerror(saved));
        }
        p += n;
        left -= (size_t)n;
    }
    close(fd);
    return store_blob_commit_locked(s, tmp, hash_out, len, 0, e);
}

void store_blob_release_locked(struct store *s, const char *hash)
{
    if (hash[0] == '\0' || store_db_blob_referenced_locked(s, hash))
        return;
    char path[STORE_PATH_MAX];
    store_blob_path(s, hash, path, sizeof path);
    struct stat st;
    if (stat(path, &st) != 0)
        return;
    if (unlink(path) == 0) {
        s->blob_bytes -= (unsigned long long)st.st_size <= s->blob_bytes
                             ? (unsigned long long)st.st_size
                             : s->blob_bytes;
        s->blob_count -= s->blob_count > 0;
    }
}

static bool is_hash(const char *name)
{
    if (strlen(name) != SHA256_HEX_SIZE - 1)
        return false;
    for (const char *c = name; *c; c++)
        if (!((*c >= '0' && *c <= '9') || (*c >= 'a' && *c <= 'f')))
            return false;
    return true;
}

/* Removes the regular files in dir whose names contain `needle` (NULL: all). */
static int remove_files(const char *dir, const char *needle)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return 0;
    int removed = 0;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (ent->d_name[0] == '.' || (needle && strstr(ent->d_name, needle) == NULL))
            continue;
        char path[STORE_PATH_MAX + 256];
        snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
        if (unlink(path) == 0)
            removed++;
    }
    closedir(d);
    return removed;
}

static void sweep_fanout_dir(struct store *s, const char *dir, int *orphans)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (ent->d_name[0] == '.')
            continue;
        char path[STORE_PATH_MAX + 256];
        snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
        struct stat st;
        if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (!is_hash(ent->d_name) || !store_db_blob_referenced_locked(s, ent->d_name)) {
            if (unlink(path) == 0)
                (*orphans)++;
            continue;
        }
        s->blob_bytes += (unsigned long long)st.st_size;
        s->blob_count++;
    }
    closedir(d);
}

void store_blob_sweep_locked(struct store *s)
{
    char dir[STORE_PATH_MAX];
    snprintf(dir, sizeof dir, "%s/tmp", s->data_dir);
    int temporaries = remove_files(dir, NULL);
    /* io_write_atomic's temporaries ("<name>.tmp.<pid>") of the irradiance cache. */
    snprintf(dir, sizeof dir, "%s/irradiance", s->data_dir);
    temporaries += remove_files(dir, ".tmp.");
    s->blob_bytes = 0;
    s->blob_count = 0;
    int orphans = 0;
    snprintf(dir, sizeof dir, "%s/blobs", s->data_dir);
    DIR *d = opendir(dir);
    if (d != NULL) {
        struct dirent *ent;
        while ((ent = readdir(d)) != NULL) {
            if (ent->d_name[0] == '.')
                continue;
            char sub[STORE_PATH_MAX];
            if (snprintf(sub, sizeof sub, "%s/%s", dir, ent->d_name) >= (int)sizeof sub)
                continue;
            sweep_fanout_dir(s, sub, &orphans);
        }
        closedir(d);
    }
    if (temporaries || orphans)
        log_info("store", "start-up sweep: removed %d temporary file(s) and %d orphan blob(s)",
                 temporaries, orphans);
}

int store_blob_open(const struct store *s, const char *hash, size_t bytes, const char *what,
                    const char *hint, struct err *e)
{
    char path[STORE_PATH_MAX];
    store_blob_path(s, hash, path, sizeof path);
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        int saved = errno;
        if (fd >= 0)
            close(fd);
        err_set(e, REFRACT_E_STORAGE, "%s %s: %s%s", what, path, strerror(saved), hint);
        return -1;
    }
    if ((size_t)st.st_size != bytes) {
        close(fd);
        err_set(e, REFRACT_E_STORAGE, "%s %s has %lld bytes, its row says %zu", what, path,
                (long long)st.st_size, bytes);
        return -1;
    }
    return fd;
}

enum refract_code store_blob_map(const struct store *s, const char *hash, size_t bytes, void **map,
                                 struct err *e)
{
    *map = NULL;
    char path[STORE_PATH_MAX];
    store_blob_path(s, hash, path, sizeof path);
    int fd = store_blob_open(s, hash, bytes, "blob", "", e);
    if (fd < 0)
        return e->code;
    if (bytes > 0) {
        void *p = mmap(NULL, bytes, PROT_READ, MAP_SHARED, fd, 0);
        if (p == MAP_FAILED) {
            int saved = errno;
            close(fd);
            return err_set(e, REFRACT_E_STORAGE, "cannot map blob %s: %s", path, strerror(saved));
        }
        *map = p;
    }
    close(fd);
    return REFRACT_E_OK;
}

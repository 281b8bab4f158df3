/*
 * io_files.c - atomic file writes and friends for the data directory (scene store and
 * irradiance cache); see io_files.h.
 */
#include "io_files.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

enum refract_code io_mkdirs(const char *path, struct err *e)
{
    char buf[1024];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return err_set(e, REFRACT_E_STORAGE, "path too long: %s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0750) != 0 && errno != EEXIST)
            return err_set(e, REFRACT_E_STORAGE, "cannot create directory %s: %s", buf,
                           strerror(errno));
        *p = '/';
    }
    if (mkdir(buf, 0750) != 0 && errno != EEXIST)
        return err_set(e, REFRACT_E_STORAGE, "cannot create directory %s: %s", buf,
                       strerror(errno));
    return REFRACT_E_OK;
}

static void fsync_parent(const char *path)
{
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash == NULL)
        return;
    *slash = '\0';
    int fd = open(dir, O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
}

enum refract_code io_write_atomic(const char *path, const void *data, size_t len, struct err *e)
{
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0640);
    if (fd < 0)
        return err_set(e, REFRACT_E_STORAGE, "cannot write %s: %s", tmp, strerror(errno));
    const char *p = data;
    size_t left = len;
    while (left > 0) {
        ssize_t n = write(fd, p, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            int saved = errno;
            close(fd);
            unlink(tmp);
            return err_set(e, REFRACT_E_STORAGE, "writing %s failed: %s (is the disk full?)", tmp,
                           strerror(saved));
        }
        p += n;
        left -= (size_t)n;
    }
    if (fsync(fd) != 0 || close(fd) != 0) {
        int saved = errno;
        unlink(tmp);
        return err_set(e, REFRACT_E_STORAGE, "flushing %s failed: %s", tmp, strerror(saved));
    }
    if (rename(tmp, path) != 0) {
        int saved = errno;
        unlink(tmp);
        return err_set(e, REFRACT_E_STORAGE, "renaming %s to %s failed: %s", tmp, path,
                       strerror(saved));
    }
    fsync_parent(path);
    return REFRACT_E_OK;
}

enum refract_code io_read_file(const char *path, size_t max_len, char **out, size_t *len,
                               struct err *e)
{
    *out = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return err_set(e, REFRACT_E_STORAGE, "cannot read %s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || st.st_size < 0 || (size_t)st.st_size > max_len) {
        fclose(f);
        return err_set(e, REFRACT_E_STORAGE, "%s is larger than %zu bytes", path, max_len);
    }
    size_t n = (size_t)st.st_size;
    char *buf = malloc(n + 1);
    if (buf == NULL) {
        fclose(f);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory reading %s", path);
    }
    size_t got = fread(buf, 1, n, f);
    fclose(f);
    if (got != n) {
        free(buf);
        return err_set(e, REFRACT_E_STORAGE, "short read of %s", path);
    }
    buf[n] = '\0';
    *out = buf;
    *len = n;
    return REFRACT_E_OK;
}

enum refract_code io_remove_tree(const char *path, struct err *e)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return REFRACT_E_OK;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        if (d == NULL)
            return err_set(e, REFRACT_E_STORAGE, "cannot open %s: %s", path, strerror(errno));
        struct dirent *ent;
        while ((ent = readdir(d)) != NULL) {
            if (strcmp(ent->d_name, ".") == 0 || strcmp(ent->d_name, "..") == 0)
                continue;
            char child[1024];
            snprintf(child, sizeof child, "%s/%s", path, ent->d_name);
            enum refract_code rc = io_remove_tree(child, e);
            if (rc != REFRACT_E_OK) {
                closedir(d);
                return rc;
            }
        }
        closedir(d);
        if (rmdir(path) != 0)
            return err_set(e, REFRACT_E_STORAGE, "cannot remove %s: %s", path, strerror(errno));
        return REFRACT_E_OK;
    }
    if (unlink(path) != 0)
        return err_set(e, REFRACT_E_STORAGE, "cannot remove %s: %s", path, strerror(errno));
    return REFRACT_E_OK;
}

enum refract_code io_map_file(const char *path, const void **map, size_t *len, struct err *e)
{
    *map = NULL;
    *len = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        int saved = errno;
        if (fd >= 0)
            close(fd);
        return err_set(e, REFRACT_E_STORAGE, "cannot read %s: %s", path, strerror(saved));
    }
    *len = (size_t)st.st_size;
    if (*len > 0) {
        void *p = mmap(NULL, *len, PROT_READ, MAP_PRIVATE, fd, 0);
        if (p == MAP_FAILED) {
            int saved = errno;
            close(fd);
            *len = 0;
            return err_set(e, REFRACT_E_STORAGE, "cannot map %s: %s", path, strerror(saved));
        }
        madvise(p, *len, MADV_SEQUENTIAL);
        *map = p;
    }
    close(fd);
    return REFRACT_E_OK;
}

void io_unmap_file(const void *map, size_t len)
{
    if (map != NULL)
        munmap((void *)map, len);
}

/*
 * job_batch_dir.c - the output directory that the array tasks of one batch job share
 * (docs/slurm.md): frames, their temporary files, and the progress files.
 *
 * INVARIANT. A file named frame_NNNNN.<ext> is complete: it only ever appears by rename(2)
 * of a temporary file that was written whole and fsynced, so a task killed at any point
 * leaves either the complete frame or a temporary file, never a partial frame. Two runs of
 * the same frame (a requeued task racing a late one) write identical bytes; the later
 * rename replaces the file with the same content, so each frame exists exactly once.
 * Temporary names carry the host and process (.frame_NNNNN.<ext>.<host>.<pid>.tmp) so that
 * two writers never share one, and they start with a dot so that `ls` and archive globs
 * (frame_*) skip them.
 *
 * Progress. Each task owns progress.d/frames_A-B.json; progress.json is rebuilt by any
 * task from the frames present and all task records. Both are replaced by rename, so a
 * reader never sees half a file. What it is not: a lock or a scheduler. Slurm (or
 * Kubernetes) decides which task runs where; this directory only records what is done.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "jobs.h"

#define PATH_SIZE 1024

void job_batch_frame_path(const char *dir, int n, enum job_format f, char *out, size_t size)
{
    snprintf(out, size, "%s/frame_%05d.%s", dir, n, job_format_extension(f));
}

bool job_batch_frame_exists(const char *dir, int n, enum job_format f)
{
    char path[PATH_SIZE];
    job_batch_frame_path(dir, n, f, path, sizeof path);
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0;
}

/* The name's host part: gethostname, with anything but [A-Za-z0-9-] replaced. */
static void host_name(char *out, size_t size)
{
    if (gethostname(out, size) != 0 || out[0] == '\0')
        snprintf(out, size, "host");
    out[size - 1] = '\0';
    for (char *p = out; *p; p++) {
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
              *p == '-'))
            *p = '_';
    }
}

/* fsyncs a directory so that a rename in it survives a crash of the machine. */
static void sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
}

/* Writes bytes to tmp, fsyncs it and renames it to path. */
static enum refract_code write_replace(const char *tmp, const char *path, const void *bytes,
                                       size_t len, struct err *e)
{
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return err_set(e, REFRACT_E_IO, "%s: cannot create it: %s", tmp, strerror(errno));
    const char *p = bytes;
    size_t left = len;
    while (left > 0) {
        ssize_t got = write(fd, p, left);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0) {
            int saved = errno;
            close(fd);
            unlink(tmp);
            return err_set(e, REFRACT_E_IO, "%s: write failed: %s", tmp, strerror(saved));
        }
        p += got;
        left -= (size_t)got;
    }
    if (fsync(fd) != 0 || close(fd) != 0) {
        int saved = errno;
        unlink(tmp);
        return err_set(e, REFRACT_E_IO, "%s: fsync failed: %s", tmp, strerror(saved));
    }
    if (rename(tmp, path) != 0) {
        int saved = errno;
        unlink(tmp);
        return err_set(e, REFRACT_E_IO, "%s: rename failed: %s", path, strerror(saved));
    }
    return REFRACT_E_OK;
}

enum refract_code job_batch_frame_write(const char *dir, int n, enum job_format f,
                                        const void *bytes, size_t len, struct err *e)
{
    char path[PATH_SIZE], tmp[PATH_SIZE + 128], host[64];
    job_batch_frame_path(dir, n, f, path, sizeof path);
    host_name(host, sizeof host);
    snprintf(tmp, sizeof tmp, "%s/.frame_%05d.%s.%s.%ld.tmp", dir, n, job_format_extension(f), host,
             (long)getpid());
    enum refract_code rc = write_replace(tmp, path, bytes, len, e);
    if (rc == REFRACT_E_OK)
        sync_dir(dir);
    return rc;
}

/* Removes the entries of dir whose names start with prefix and end in ".tmp". */
static int remove_temps(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return 0;
    int removed = 0;
    size_t plen = strlen(prefix);
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        const char *name = ent->d_name;
        size_t len = strlen(name);
        if (len < plen + 4 || strncmp(name, prefix, plen) != 0 || strcmp(name + len - 4, ".tmp"))
            continue;
        char path[PATH_SIZE + 300];
        snprintf(path, sizeof path, "%s/%s", dir, name);
        if (unlink(path) == 0)
            removed++;
    }
    closedir(d);
    return removed;
}

int job_batch_clean_temps(const char *dir, int first, int last)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return 0;
    int removed = 0;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        const char *name = ent->d_name;
        size_t len = strlen(name);
        int n = -1, used = 0;
        if (strncmp(name, ".frame_", 7) != 0 || len < 12 || strcmp(name + len - 4, ".tmp") != 0)
            continue;
        if (sscanf(name + 7, "%d%n", &n, &used) != 1 || name[7 + used] != '.' || n < first ||
            n > last)
            continue;
        char path[PATH_SIZE];
        snprintf(path, sizeof path, "%s/%s", dir, name);
        if (unlink(path) == 0)
            removed++;
    }
    closedir(d);
    /* The progress files this range's killed run was replacing (their temporary names
     * carry the range, see progress_tag). */
    char prefix[64], sub[PATH_SIZE + 16];
    snprintf(prefix, sizeof prefix, "progress.json.frames_%05d-%05d.", first, last);
    removed += remove_temps(dir, prefix);
    snprintf(prefix, sizeof prefix, "frames_%05d-%05d.json.", first, last);
    snprintf(sub, sizeof sub, "%s/progress.d", dir);
    removed += remove_temps(sub, prefix);
    return removed;
}

/* mkdir -p: each missing component with mode 0755. */
static enum refract_code make_dirs(const char *dir, struct err *e)
{
    char path[PATH_SIZE];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
        return err_set(e, REFRACT_E_USAGE, "--out %.80s...: the path is too long", dir);
    for (char *p = path + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(path, 0755) != 0 && errno != EEXIST)
            return err_set(e, REFRACT_E_IO, "--out: cannot create %s: %s", path, strerror(errno));
        *p = '/';
    }
    if (mkdir(path, 0755) != 0 && errno != EEXIST)
        return err_set(e, REFRACT_E_IO, "--out: cannot create %s: %s", path, strerror(errno));
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return err_set(e, REFRACT_E_IO, "--out %s: not a directory", path);
    return REFRACT_E_OK;
}

enum refract_code job_batch_dir_prepare(const char *dir, struct err *e)
{
    enum refract_code rc = make_dirs(dir, e);
    if (rc != REFRACT_E_OK)
        return rc;
    char sub[PATH_SIZE + 16];
    snprintf(sub, sizeof sub, "%s/progress.d", dir);
    return make_dirs(sub, e);
}

/* Writes text to dir/name through a temporary file of this process whose name carries
 * tag (the writer's range, "frames_AAAAA-BBBBB"), so that the range's next run can tell
 * its own leftovers from another task's file in flight (job_batch_clean_temps). */
static enum refract_code replace_text(const char *dir, const char *name, const char *tag,
                                      const char *text, struct err *e)
{
    char path[PATH_SIZE + 64], tmp[PATH_SIZE + 192], host[64];
    host_name(host, sizeof host);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(tmp, sizeof tmp, "%s.%s.%s.%ld.tmp", path, tag, host, (long)getpid());
    return write_replace(tmp, path, text, strlen(text), e);
}

/* The whole of a small file (a task record), NUL-terminated; NULL when unreadable. */
static char *read_small(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    char *buf = malloc(65536);
    size_t n = buf ? fread(buf, 1, 65535, f) : 0;
    fclose(f);
    if (buf)
        buf[n] = '\0';
    return buf;
}

/* Every task record of dir/progress.d (frames_*.json), in name order = frame order. */
static cJSON *task_records(const char *dir)
{
    char sub[PATH_SIZE + 16];
    snprintf(sub, sizeof sub, "%s/progress.d", dir);
    cJSON *arr = cJSON_CreateArray();
    struct dirent **names = NULL;
    int n = scandir(sub, &names, NULL, alphasort);
    for (int i = 0; i < n; i++) {
        const char *name = names[i]->d_name;
        size_t len = strlen(name);
        if (strncmp(name, "frames_", 7) == 0 && len > 5 && !strcmp(name + len - 5, ".json")) {
            char path[PATH_SIZE + 300];
            snprintf(path, sizeof path, "%s/%s", sub, name);
            char *text = read_small(path);
            cJSON *rec = text ? cJSON_Parse(text) : NULL;
            free(text);
            if (rec)
                cJSON_AddItemToArray(arr, rec);
        }
        free(names[i]);
    }
    free(names);
    return arr;
}

/* progress.json's text as the directory is now, without the time (compared between two
 * builds); *done gets the frames present. New string (caller frees). */
static char *progress_text(const char *dir, const struct job_frame *frames, int total, int *done)
{
    *done = 0;
    for (int n = 0; n < total; n++)
        *done += job_batch_frame_exists(dir, n, frames[n].format);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "frames_total", total);
    cJSON_AddNumberToObject(o, "frames_done", *done);
    cJSON_AddStringToObject(o, "state", *done == total ? "done" : "running");
    cJSON_AddItemToObject(o, "tasks", task_records(dir));
    char *text = cJSON_Print(o);
    cJSON_Delete(o);
    return text;
}

static char *task_text(const struct job_batch_task *t)
{
    cJSON *o = cJSON_CreateObject();
    cJSON *range = cJSON_AddArrayToObject(o, "frames");
    cJSON_AddItemToArray(range, cJSON_CreateNumber(t->first));
    cJSON_AddItemToArray(range, cJSON_CreateNumber(t->last));
    cJSON_AddNumberToObject(o, "frames_done", t->done);
    cJSON_AddStringToObject(o, "state", t->state);
    if (t->message && t->message[0])
        cJSON_AddStringToObject(o, "message", t->message);
    char host[64];
    host_name(host, sizeof host);
    cJSON_AddStringToObject(o, "host", host);
    cJSON_AddNumberToObject(o, "pid", (double)getpid());
    /* Which scheduler task this is, so `scontrol show job` / `kubectl` can be asked. */
    const char *array_job = getenv("SLURM_ARRAY_JOB_ID");
    const char *array_task = getenv("SLURM_ARRAY_TASK_ID");
    const char *index = getenv("JOB_COMPLETION_INDEX");
    if (array_job && array_task) {
        char id[96];
        snprintf(id, sizeof id, "%.40s_%.40s", array_job, array_task);
        cJSON_AddStringToObject(o, "slurm_job", id);
        const char *restarts = getenv("SLURM_RESTART_COUNT");
        cJSON_AddNumberToObject(o, "slurm_restarts", restarts ? atoi(restarts) : 0);
    } else if (index) {
        cJSON_AddStringToObject(o, "k8s_completion_index", index);
    }
    cJSON_AddNumberToObject(o, "updated_unix", (double)time(NULL));
    char *text = cJSON_Print(o);
    cJSON_Delete(o);
    return text;
}

/* Adds "updated_unix" to a progress text (it is left out of the comparison). */
static char *with_time(const char *text)
{
    cJSON *o = cJSON_Parse(text);
    if (o == NULL)
        return NULL;
    cJSON_AddNumberToObject(o, "updated_unix", (double)time(NULL));
    char *out = cJSON_Print(o);
    cJSON_Delete(o);
    return out;
}

enum refract_code job_batch_progress_write(const char *dir, const struct job_batch_task *t,
                                           const struct job_frame *frames, int total, struct err *e)
{
    char name[64], tag[32];
    snprintf(tag, sizeof tag, "frames_%05d-%05d", t->first, t->last);
    snprintf(name, sizeof name, "progress.d/%s.json", tag);
    char *rec = task_text(t);
    if (rec == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory writing progress");
    enum refract_code rc = replace_text(dir, name, tag, rec, e);
    free(rec);
    /* Rebuild until the directory says what we wrote: when two tasks finish together, the
     * one whose rename lands last saw the other's frames (see the file comment). Bounded:
     * a busy directory is caught up by the next frame's write. */
    char *written = NULL;
    for (int attempt = 0; rc == REFRACT_E_OK && attempt < 4; attempt++) {
        int done = 0;
        char *text = progress_text(dir, frames, total, &done);
        if (text == NULL) {
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory writing progress");
            break;
        }
        if (written && strcmp(text, written) == 0) {
            free(text);
            break;
        }
        char *stamped = with_time(text);
        rc = stamped ? replace_text(dir, "progress.json", tag, stamped, e)
                     : err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory writing progress");
        free(stamped);
        free(written);
        written = text;
    }
    free(written);
    return rc;
}

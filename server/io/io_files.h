/*
 * io_files.h - the data directory's file operations (store/ and cache/): atomic
 * writes, whole-file reads, recursive removal. Every write goes to "<path>.tmp.<pid>",
 * is fsync'ed, then renamed over <path>, and the directory is fsync'ed, so a crash
 * leaves either the old file or the new one, never a torn one.
 */
#ifndef REFRACT_IO_FILES_H
#define REFRACT_IO_FILES_H

#include <stddef.h>

#include "../core/err.h"

/* mkdir -p with mode 0750. */
enum refract_code io_mkdirs(const char *path, struct err *e);
/* Writes len bytes atomically to path. */
enum refract_code io_write_atomic(const char *path, const void *data, size_t len, struct err *e);
/* Reads a whole file: *out is a new buffer (NUL-terminated, caller frees), *len its size. */
enum refract_code io_read_file(const char *path, size_t max_len, char **out, size_t *len,
                               struct err *e);
/* Maps a whole file read-only: *map (NULL for an empty file) until io_unmap_file. */
enum refract_code io_map_file(const char *path, const void **map, size_t *len, struct err *e);
void io_unmap_file(const void *map, size_t len);
/* rm -r; missing paths are fine. */
enum refract_code io_remove_tree(const char *path, struct err *e);

#endif

/*
 * json_read.h - reading validated values out of cJSON trees, with errors that name
 * the JSON path, the rule and the allowed values.
 *
 * Used by scene parsing and by the HTTP layer for render/trace requests, so every
 * message reads the same way:
 *   "objects[0].resolution: expected 3 integers in 2..512, got 2 values"
 *   "camera: unknown field \"fov\"; allowed: eye, look_at, up, fov_y_deg, width, height"
 *   "render.step: expected a finite number in 0.01..8, got 12"
 *   "objects[1].ior: missing required field \"radius\""
 * `path` is the JSON path of the object that holds `key` ("" at the document root);
 * the helpers join them as "path.key". Non-finite numbers cannot come from JSON text,
 * but ranges reject anything cJSON parsed as huge (1e999 -> inf).
 *
 * Thread: any. Nothing here allocates except jr_string_dup.
 */
#ifndef REFRACT_JSON_READ_H
#define REFRACT_JSON_READ_H

#include <stdbool.h>
#include <stddef.h>

#include <cjson/cJSON.h>

#include "../core/err.h"
#include "../core/vec3.h"

/* Joins a path and a key or index: jr_path(buf, n, "objects[0]", "ior") ->
 * "objects[0].ior"; jr_path_index(buf, n, "objects", 2) -> "objects[2]". */
const char *jr_path(char *buf, size_t size, const char *path, const char *key);
const char *jr_path_index(char *buf, size_t size, const char *path, int index);

/* Parses a whole document; trailing non-space text is an error. On success *out is a new
 * tree the caller frees with cJSON_Delete. Error code REFRACT_E_INVALID_JSON with the
 * byte offset, line and column of the problem. */
enum refract_code jr_parse(const char *text, size_t len, cJSON **out, struct err *e);

/* Checks obj is a JSON object whose keys all appear in allowed (NULL-terminated);
 * otherwise INVALID_FIELD (not an object) or UNKNOWN_FIELD naming the key and listing
 * the allowed keys. Duplicate keys are INVALID_FIELD. */
enum refract_code jr_check_object(const cJSON *obj, const char *path, const char *const *allowed,
                                  struct err *e);

/* Each getter: when key is absent, required -> MISSING_FIELD, else *out = def and OK.
 * Wrong type or out of [min, max] -> INVALID_FIELD with the path, the rule and what
 * was given. */
enum refract_code jr_number(const cJSON *obj, const char *path, const char *key, bool required,
                            double def, double min, double max, double *out, struct err *e);
enum refract_code jr_int(const cJSON *obj, const char *path, const char *key, bool required,
                         int def, int min, int max, int *out, struct err *e);
enum refract_code jr_bool(const cJSON *obj, const char *path, const char *key, bool required,
                          bool def, bool *out, struct err *e);
/* Copies a string of 1..max_len bytes (max_len < size) into out. */
enum refract_code jr_string(const cJSON *obj, const char *path, const char *key, bool required,
                            const char *def, size_t max_len, char *out, size_t size, struct err *e);
/* One of names (NULL-terminated) -> its index in *out. The message lists the names. */
/* A key that was renamed: *use = key, or old_key when only the old name is present, so
 * documents written before the rename keep working; both present is an error naming them. */
enum refract_code jr_renamed(const cJSON *obj, const char *path, const char *key,
                             const char *old_key, const char **use, struct err *e);

enum refract_code jr_enum(const cJSON *obj, const char *path, const char *key, bool required,
                          int def, const char *const *names, int *out, struct err *e);
/* An array of exactly 3 finite numbers, each in [min, max]. */
enum refract_code jr_vec3(const cJSON *obj, const char *path, const char *key, bool required,
                          vec3 def, double min, double max, vec3 *out, struct err *e);
/* A unit-izable direction: 3 finite numbers with length > 1e-12; returned normalised. */
enum refract_code jr_direction(const cJSON *obj, const char *path, const char *key, bool required,
                               vec3 def, vec3 *out, struct err *e);

/* As jr_number, for a half-open range: min_exclusive < value <= max
 * ("objects[0].ior.radius: expected a finite number > 0 and <= 1000000, got 0"). */
enum refract_code jr_number_gt(const cJSON *obj, const char *path, const char *key, bool required,
                               double def, double min_exclusive, double max, double *out,
                               struct err *e);

/* Checks an item already in hand (an array element, say) whose full JSON path is
 * `path`: a finite number in [min, max], or in (min, max] when min_exclusive. */
enum refract_code jr_check_number(const cJSON *item, const char *path, double min,
                                  bool min_exclusive, double max, double *out, struct err *e);

/* Writes a short description of a JSON value for messages: 12, "abc" (quoted, escaped,
 * shortened), true, null, "an array of 2 values", "an object"; "nothing" for NULL.
 * Returns buf. */
const char *jr_describe(const cJSON *item, char *buf, size_t size);

#endif

/*
 * cli_json.h - the JSON editing that `refract render` and `refract trace` share: load a
 * request file as an object, and set keys so that command-line flags override the
 * file's values.
 */
#ifndef CLI_JSON_H
#define CLI_JSON_H

#include <cjson/cJSON.h>
#include <stdbool.h>

/* Reads path ("-" = stdin) and parses it as a JSON object. On success *out is a new tree
 * the caller deletes with cJSON_Delete(). On failure prints why (naming option, the flag
 * that gave the path) and returns REFRACT_E_IO, REFRACT_E_INVALID_JSON (not JSON) or
 * REFRACT_E_INVALID_FIELD (JSON, but not an object). */
int cli_json_load_object(const char *path, const char *option, cJSON **out);

/* Sets obj[key] = item, replacing an existing member of that name. Consumes item: on
 * failure (out of memory) it is deleted and false is returned. */
bool cli_json_set(cJSON *obj, const char *key, cJSON *item);

/* obj[key] as an object, created when absent. NULL when the member exists but is not
 * an object, or when out of memory. Borrowed from obj. */
cJSON *cli_json_object_member(cJSON *obj, const char *key);

#endif

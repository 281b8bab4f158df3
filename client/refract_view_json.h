/*
 * refract_view_json.h - view sessions at the JSON edge: the create body that a struct
 * refract_view_options describes, and a view status document read into struct
 * refract_view (docs/views.md).
 *
 * Pure JSON work with cJSON and no libcurl, so tests/unit/test_cli_args.c can compile it
 * directly. Internal to the client; refract.h declares the public wrappers.
 */
#ifndef REFRACT_VIEW_JSON_H
#define REFRACT_VIEW_JSON_H

#include <stdbool.h>
#include <stddef.h>

#include "refract.h"

/* Reads json[0..len) into out (overwritten; out->json is left NULL for the caller to
 * set). Only "id" is required (a string of at most REFRACT_ID_SIZE - 1 characters); other
 * members are read when present and of the right type, else -1 or "". "frame": null (or
 * absent) leaves has_frame 0. Returns false with why filled when json is not a view
 * status. */
bool refract_view_from_json(const char *json, size_t len, struct refract_view *out, char *why,
                            size_t why_size);

#endif

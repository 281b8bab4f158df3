/*
 * refract_status.h - reading an irradiance status document (GET /v1/scenes/{id}/irradiance,
 * and the replies of light changes) into struct refract_irradiance.
 *
 * Pure JSON work with cJSON and no libcurl, so tests/unit/test_cli_args.c compiles it
 * directly. Internal to the client; refract.h declares the public wrappers.
 */
#ifndef REFRACT_STATUS_H
#define REFRACT_STATUS_H

#include <stdbool.h>
#include <stddef.h>

#include "refract.h"

/* Reads json[0..len) into out (overwritten; out->json and out->http_status are left 0 for
 * the caller to set). Returns false with why filled ("lights[1].state: expected a
 * string") when json is not an irradiance status; out then owns nothing. Members the
 * document lacks read as -1 or "" (refract.h), so a newer or older refractd still reads. */
bool refract_status_from_json(const char *json, size_t len, struct refract_irradiance *out,
                              char *why, size_t why_size);

/* True for the states after which no volume is still to come for a light: "ready",
 * "failed" and "not_needed". Every other state, one this client does not know included,
 * is still on its way. */
bool refract_state_is_settled(const char *state);

#endif

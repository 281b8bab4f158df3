/*
 * cli_light.h - what `refract light set` makes of its flags: their syntax, whether they
 * fit the light's type, and the light object sent to refractd, merged into the light of
 * that name when the scene has one already.
 *
 * No I/O and no librefract, so tests/unit/test_cli_args.c compiles this file directly;
 * cJSON builds the object. Messages are written into why, as in cli_args.h.
 */
#ifndef CLI_LIGHT_H
#define CLI_LIGHT_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h>

/* The option values as given (NULL = not given); borrowed from argv. */
struct cli_light_flags {
    const char *type;      /* --type */
    const char *direction; /* --direction x,y,z */
    const char *position;  /* --position x,y,z */
    const char *angle;     /* --angle DEG: the spot cone's half angle */
    const char *color;     /* --color r,g,b */
    const char *intensity; /* --intensity I */
};

/* The flags, parsed. A field counts only when its has_ flag is set. */
struct cli_light_spec {
    const char *type; /* "directional", "point" or "spot" (static), NULL when not given */
    bool has_direction, has_position, has_angle, has_color, has_intensity;
    double direction[3];
    double position[3];
    double angle_deg;
    double color[3];
    double intensity;
};

/* Parses the flags' syntax: --type is directional, point or spot (any letter case);
 * vectors have three finite numbers; --direction is not 0,0,0; numbers are finite.
 * Ranges (an angle of 1..89 degrees, say) are refractd's to check. Returns false with
 * why ("--type: expected directional, point or spot, got 'sun'") on a mistake. */
bool cli_light_spec_parse(const struct cli_light_flags *flags, struct cli_light_spec *spec,
                          char *why, size_t why_size);

/* Checks that the given flags apply to a light of type (directional, point or spot):
 * a directional light has no position, a point light no direction, and only a spot has
 * an angle. A NULL type (a new light whose type refractd will default) checks nothing. */
bool cli_light_spec_fits(const struct cli_light_spec *spec, const char *type, char *why,
                         size_t why_size);

/* The light object to send for `light set NAME`: existing (the scene's light of that
 * name, or NULL for a new light) with the spec's fields set over it. When the spec
 * changes the type, the existing members that do not apply to the new type (a point
 * light's position when it becomes directional) are dropped; members this client does
 * not know are kept. Returns a new object (cJSON_Delete() it), or NULL with why filled
 * when the flags do not fit the light's type (a usage error), or NULL with why empty when
 * out of memory. */
cJSON *cli_light_build(const cJSON *existing, const char *name, const struct cli_light_spec *spec,
                       char *why, size_t why_size);

/* The light called name in a {"lights": [...]} document (a light without a "name" is
 * called "light<index>", refractd's default), or NULL. Borrowed from doc. */
const cJSON *cli_light_find(const cJSON *doc, const char *name);

#endif

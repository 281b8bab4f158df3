/*
 * ray_status.h - how a traced ray ended: one row per status gives the enum constant,
 * the number the GPU writes (shaders/bindings.h RAY_STATUS_*) and the JSON string of
 * /v1/scenes/{id}/trace, so the three cannot drift apart.
 */
#ifndef REFRACT_RAY_STATUS_H
#define REFRACT_RAY_STATUS_H

#include "bindings.h"

#define RAY_STATUS_TABLE(X)                                                                    \
    X(EXITED, RAY_STATUS_EXITED, "exited")                                                     \
    X(ABSORBED, RAY_STATUS_ABSORBED, "absorbed")                                               \
    X(MAX_STEPS, RAY_STATUS_MAX_STEPS, "max_steps")                                            \
    X(MISSED, RAY_STATUS_MISSED, "missed")

enum ray_status {
#define RAY_STATUS_X_ENUM(name, num, json) RAY_##name = num,
    RAY_STATUS_TABLE(RAY_STATUS_X_ENUM)
#undef RAY_STATUS_X_ENUM
};

/* "exited", ...; "unknown" for other values. */
const char *ray_status_json(int status);

#endif

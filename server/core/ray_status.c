/*
 * ray_status.c - names of ray statuses; the table is in ray_status.h.
 */
#include "ray_status.h"

const char *ray_status_json(int status)
{
#define RAY_STATUS_X_NAME(name, num, json)                                                    \
    if (status == num)                                                                         \
        return json;
    RAY_STATUS_TABLE(RAY_STATUS_X_NAME)
#undef RAY_STATUS_X_NAME
    return "unknown";
}

/*
 * cli_view.c - `refract view`'s pure helpers (cli_view.h): the --orbit rotation and the
 * frame file names.
 */
#include "cli_view.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

bool cli_orbit_eye(const double eye[3], const double look_at[3], const double up[3], double deg,
                   double out[3])
{
    double len = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    double k[3];
    double v[3];
    double kxv[3];
    double kv;
    double c = cos(deg * M_PI / 180.0);
    double s = sin(deg * M_PI / 180.0);

    if (!(len > 0) || !isfinite(len))
        return false;
    for (int i = 0; i < 3; i++) {
        k[i] = up[i] / len;
        v[i] = eye[i] - look_at[i];
    }
    kxv[0] = k[1] * v[2] - k[2] * v[1];
    kxv[1] = k[2] * v[0] - k[0] * v[2];
    kxv[2] = k[0] * v[1] - k[1] * v[0];
    kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    /* v' = v cos + (k x v) sin + k (k . v)(1 - cos) */
    for (int i = 0; i < 3; i++)
        out[i] = look_at[i] + v[i] * c + kxv[i] * s + k[i] * kv * (1.0 - c);
    return true;
}

bool cli_frame_path(char *buf, size_t size, const char *dir, long n)
{
    size_t dir_len = strlen(dir);
    const char *sep = dir_len == 0 || dir[dir_len - 1] == '/' ? "" : "/";
    int written = snprintf(buf, size, "%s%sframe_%04ld.jpg", dir, sep, n);

    return written > 0 && (size_t)written < size;
}

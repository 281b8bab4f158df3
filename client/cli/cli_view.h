/*
 * cli_view.h - the pure helpers of `refract view`: turning the eye around the point it
 * looks at (--orbit) and the names of the frame files.
 *
 * No libcurl, no cJSON and no I/O, so tests/unit/test_cli_args.c compiles this file
 * directly.
 */
#ifndef CLI_VIEW_H
#define CLI_VIEW_H

#include <stdbool.h>
#include <stddef.h>

/* Turns eye around the axis through look_at along up by deg degrees (right-handed:
 * positive deg turns counter-clockwise seen from the tip of up), keeping its distance to
 * look_at and its height along up (Rodrigues' rotation formula). Writes the new eye into
 * out (which may be eye). Returns false, leaving out alone, when up is the zero vector. */
bool cli_orbit_eye(const double eye[3], const double look_at[3], const double up[3], double deg,
                   double out[3]);

/* Writes "DIR/frame_NNNN.jpg" (n from 1, at least four digits) into buf; false when it
 * does not fit. dir "" means the current directory ("frame_0001.jpg"). */
bool cli_frame_path(char *buf, size_t size, const char *dir, long n);

#endif

/*
 * cli_io.c - local files for the refract CLI: read a whole input file (or stdin) and
 * write an output file (or stdout).
 *
 * Failures here are the user's local files, so they exit with REFRACT_E_IO and a message
 * that names the file and the system's reason. Inputs are read whole: scene documents,
 * volumes and images are sent as one request body anyway.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char *display_name(const char *path)
{
    return strcmp(path, "-") == 0 ? "<stdin>" : path;
}

/* Reads f to its end into a growing buffer; see cli_read_file() for ownership. */
static int read_all(FILE *f, const char *path, char **data, size_t *len)
{
    size_t cap = 65536;
    size_t n = 0;
    char *buf = malloc(cap);

    if (buf == NULL)
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "out of memory reading '%s'", path);
    for (;;) {
        size_t got;

        if (cap - n < 2) {
            char *grown = cap <= SIZE_MAX / 2 ? realloc(buf, cap * 2) : NULL;

            if (grown == NULL) {
                free(buf);
                return cli_fail(REFRACT_E_OUT_OF_MEMORY,
                                "out of memory reading '%s' (%zu "
                                "bytes so far)",
                                path, n);
            }
            buf = grown;
            cap *= 2;
        }
        got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0)
            break;
    }
    if (ferror(f)) {
        int err = errno;

        free(buf);
        return cli_fail(REFRACT_E_IO, "cannot read '%s': %s", path, strerror(err));
    }
    buf[n] = '\0';
    *data = buf;
    *len = n;
    return REFRACT_E_OK;
}

int cli_read_file(const char *path, char **data, size_t *len)
{
    FILE *f;
    int code;

    *data = NULL;
    *len = 0;
    if (strcmp(path, "-") == 0)
        return read_all(stdin, display_name(path), data, len);
    f = fopen(path, "rb");
    if (f == NULL)
        return cli_fail(REFRACT_E_IO, "cannot open '%s': %s", path, strerror(errno));
    code = read_all(f, path, data, len);
    fclose(f);
    return code;
}

int cli_write_file(const char *path, const void *data, size_t len)
{
    FILE *f;
    bool ok;

    if (strcmp(path, "-") == 0) {
        ok = fwrite(data, 1, len, stdout) == len && fflush(stdout) == 0;
        return ok ? REFRACT_E_OK : cli_fail(REFRACT_E_IO, "cannot write to stdout");
    }
    f = fopen(path, "wb");
    if (f == NULL)
        return cli_fail(REFRACT_E_IO, "cannot create '%s': %s", path, strerror(errno));
    ok = fwrite(data, 1, len, f) == len;
    /* fclose flushes, so its result counts: a full disk shows up here. */
    if (fclose(f) != 0)
        ok = false;
    if (!ok) {
        int err = errno;

        remove(path);
        return cli_fail(REFRACT_E_IO, "cannot write '%s': %s", path, strerror(err));
    }
    return REFRACT_E_OK;
}

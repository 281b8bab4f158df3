/*
 * cli_upload.h - `refract upload` and the older `volume upload` and `env upload`, which
 * share one way to send a file: what can be checked here is checked before a byte is
 * sent (the file is there, a raw file's size matches --dims and --type, an NRRD header
 * has its data attached), the file is streamed by librefract (never read whole), the
 * progress is drawn on stderr (cli_progress.h), and refractd's answer goes to stdout.
 *
 * The cli_upload_* helpers above cli_upload_run() are pure (strings and buffers), so
 * tests/unit/test_cli_args.c compiles cli_upload_plan.c directly.
 */
#ifndef CLI_UPLOAD_H
#define CLI_UPLOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "../refract.h"

struct cli;
struct cli_command;

/* The kind of upload a file's extension (any case) implies: .nrrd, .nhdr and .raw a
 * volume; .obj and .ply a mesh; .hdr, .png, .jpg and .jpeg the environment. 0 for .exr
 * (a volume or an environment map: the command line must say) and for anything else.
 * *format gets the format to name in the query ("nrrd", "raw", "exr", "obj", "ply"),
 * or NULL when refractd needs none (environment images) or the extension is unknown. */
int cli_upload_kind_from_path(const char *path, const char **format);

/* The name a file gives its upload when the command line gives none: its base name
 * without the extension ("scans/ior_64.nrrd" -> "ior_64"), when that is a valid
 * refractd name (1..63 of A-Z a-z 0-9 _ -). False otherwise. */
bool cli_upload_default_name(const char *path, char *out, size_t size);

/* Bytes per sample of a raw volume type: float32 4, float16 2, uint8 1, uint16 2;
 * 0 for anything else. */
int cli_upload_sample_bytes(const char *type);

/* True when an NRRD header (the first len bytes of the file, which need not hold all of
 * it) has a "data file:" field: the data is in another file, which refractd cannot
 * read (it takes attached data only). */
bool cli_upload_nrrd_detached(const char *head, size_t len);

/* What one upload sends and how it reports. */
struct cli_upload {
    const struct cli_command *cmd; /* for usage errors and message prefixes */
    const char *scene;
    const char *file; /* a path, or "-" for stdin */
    struct refract_upload_desc desc;
    bool quiet; /* no progress on stderr */
};

/* Checks what can be checked here, then sends the file and prints refractd's answer on
 * stdout; the progress goes to stderr (a bar on a terminal, a line per 10 % otherwise).
 * Returns the exit code: REFRACT_E_OK, REFRACT_E_USAGE, REFRACT_E_IO (the file),
 * REFRACT_E_INVALID_VOLUME (a raw file of the wrong size, a detached NRRD header: both
 * before anything is sent), or refractd's code with its message. */
int cli_upload_run(struct cli *cli, struct cli_upload *up);

#endif

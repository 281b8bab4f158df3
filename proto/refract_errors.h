/*
 * refract_errors.h - the one table of Refract error codes.
 *
 * This X-macro list is the single definition shared by refractd (HTTP status and
 * the JSON "error.code" string), librefract (refract_strerror) and the refract CLI
 * (its exit status is the code's number). It is documented in proto/openapi.yaml
 * (components/schemas/ErrorCode) and a unit test checks that both agree.
 *
 * RULE: codes are only ever appended. Never renumber, never remove, never reuse a
 * number: scripts depend on the CLI's exit codes. (curl's CURLcode rule.)
 *
 * Columns: X(NAME, number, http_status, "json_code", "what it means")
 * http_status 0 marks codes that only the client produces (nothing on the wire).
 *
 * Valid C; not included by GLSL.
 */
#ifndef REFRACT_ERRORS_H
#define REFRACT_ERRORS_H

#define REFRACT_ERROR_TABLE(X)                                                                     \
    X(OK, 0, 200, "ok", "success")                                                                 \
    X(INVALID_JSON, 1, 400, "invalid_json", "the request body is not valid JSON")                  \
    X(INVALID_FIELD, 2, 400, "invalid_field",                                                      \
      "a field has the wrong type, or an out-of-range or non-finite value")                        \
    X(UNKNOWN_FIELD, 3, 400, "unknown_field", "a field is not part of the schema")                 \
    X(MISSING_FIELD, 4, 400, "missing_field", "a required field is absent")                        \
    X(NOT_FOUND, 5, 404, "not_found", "no such route or resource")                                 \
    X(SCENE_NOT_FOUND, 6, 404, "scene_not_found", "no scene with this id")                         \
    X(METHOD_NOT_ALLOWED, 7, 405, "method_not_allowed",                                            \
      "the route exists but not for this method")                                                  \
    X(BODY_TOO_LARGE, 8, 413, "body_too_large", "the request body exceeds the configured limit")   \
    X(LIMIT_EXCEEDED, 9, 422, "limit_exceeded",                                                    \
      "a size, resolution or count exceeds a configured limit")                                    \
    X(UNSUPPORTED_MEDIA_TYPE, 10, 415, "unsupported_media_type",                                   \
      "the body's format or Content-Type is not accepted here")                                    \
    X(CONFLICT, 11, 409, "conflict",                                                               \
      "the request conflicts with the resource's state (e.g. a volume it needs is missing)")       \
    X(GPU_OUT_OF_MEMORY, 12, 507, "gpu_out_of_memory", "the GPU could not allocate the memory")    \
    X(GPU_ERROR, 13, 500, "gpu_error", "the GPU or its driver reported an error")                  \
    X(TIMEOUT, 14, 503, "timeout", "the work did not start before its deadline")                   \
    X(BUSY, 15, 503, "busy", "the work queue is full; retry later")                                \
    X(INTERNAL, 16, 500, "internal", "a bug in refractd; please report it")                        \
    X(INVALID_VOLUME, 17, 400, "invalid_volume",                                                   \
      "uploaded volume data is malformed (size, dimensions or values)")                            \
    X(INVALID_IMAGE, 18, 400, "invalid_image", "an uploaded image could not be decoded")           \
    X(SHUTTING_DOWN, 19, 503, "shutting_down", "the daemon is stopping")                           \
    X(OUT_OF_MEMORY, 20, 507, "out_of_memory", "host memory allocation failed")                    \
    X(CONNECT_FAILED, 21, 0, "connect_failed", "could not connect to refractd")                    \
    X(PROTOCOL, 22, 0, "protocol_error", "refractd's reply could not be understood")               \
    X(IO, 23, 0, "io_error", "a local file could not be read or written")                          \
    X(USAGE, 24, 0, "usage", "the command line is wrong")                                          \
    X(STORAGE, 25, 507, "storage_error",                                                           \
      "refractd could not read or write its data directory (disk full? permissions?)")          \
    X(INVALID_MESH, 26, 400, "invalid_mesh",                                                       \
      "an uploaded mesh file is malformed (syntax, indices, values or header counts)")           \
    X(UNAUTHORIZED, 27, 401, "unauthorized",                                                       \
      "refractd requires a bearer token (--token-file) and the request lacks it or has another")   \
    X(HOST_NOT_ALLOWED, 28, 421, "host_not_allowed",                                               \
      "the Host header names a host refractd does not serve (--allow-host)")                     \
    X(TOO_MANY_REQUESTS, 29, 429, "too_many_requests",                                             \
      "the client holds as many connections or queued renders as refractd allows one client")

enum refract_code {
#define REFRACT_X_ENUM(name, num, http, json, text) REFRACT_E_##name = num,
    REFRACT_ERROR_TABLE(REFRACT_X_ENUM)
#undef REFRACT_X_ENUM
        REFRACT_E_COUNT_
};

#endif

/*
 * refract_views.c - the calls of view sessions (docs/views.md): create (from a JSON body
 * or a struct refract_view_options), patch, status, delete, list. Their streams are read
 * by refract_view_stream.c.
 *
 * Built like refract_lights.c: argument checks, a path with the id percent-encoded as one
 * segment, refract_call_reply(), and the reply read into a struct (refract_view_json.c).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refract_internal.h"
#include "refract_url.h"
#include "refract_view_json.h"

void refract_view_free(struct refract_view *v)
{
    if (v == NULL)
        return;
    free(v->json);
    memset(v, 0, sizeof(*v));
}

static bool read_view(const char *json, size_t len, void *out, char *why, size_t why_size)
{
    return refract_view_from_json(json, len, out, why, why_size);
}

/* Reads the reply body (owned; taken) of method path into *out, or frees it when out is
 * NULL. */
static int take_view(refract_client *c, const char *method, const char *path, char *body,
                     struct refract_view *out)
{
    return refract_take_reply(c, method, path, body, "a view status", read_view, out,
                              out != NULL ? &out->json : NULL);
}

/* The exchange of method path with body (NULL: none), its reply read into out. */
static int call_view(refract_client *c, const char *method, const char *path, const char *body,
                     struct refract_view *out)
{
    return refract_call_reply(c, method, path, body, "a view status", read_view, out,
                              out != NULL ? &out->json : NULL, NULL);
}

int refract_view_parse(refract_client *c, const char *json, struct refract_view *out)
{
    char *copy;

    if (out != NULL)
        memset(out, 0, sizeof(*out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json == NULL || out == NULL)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_view_parse: json and out must not be "
                            "NULL");
    copy = malloc(strlen(json) + 1);
    if (copy == NULL)
        return refract_out_of_memory(c, "copying the view status");
    strcpy(copy, json);
    return take_view(c, "parse", "view status", copy, out);
}

/* "/v1/views/<escaped id><suffix>", or NULL when out of memory. */
static char *view_path(const char *view_id, const char *suffix)
{
    char *id = refract_url_escape_dup(view_id);
    char *path = id != NULL ? refract_path_printf("/v1/views/%s%s", id, suffix) : NULL;

    free(id);
    return path;
}

/* A call on one session: checks the id, builds the path, exchanges and reads the reply
 * into out (NULL: the reply is dropped). */
static int view_call(refract_client *c, const char *call, const char *method, const char *view_id,
                     const char *body, struct refract_view *out)
{
    char *path;
    int code = refract_check_segment(c, call, "view id", view_id);

    if (code != REFRACT_E_OK)
        return code;
    path = view_path(view_id, "");
    if (path == NULL)
        return refract_out_of_memory(c, "building the request path");
    code = call_view(c, method, path, body, out);
    free(path);
    return code;
}

int refract_view_create(refract_client *c, const char *scene_id, const char *request_json,
                        struct refract_view *out)
{
    const char *body = request_json != NULL ? request_json : "{}";
    char *path;
    int code;

    if (out != NULL)
        memset(out, 0, sizeof(*out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (out == NULL)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_view_create: out is NULL (the new "
                            "session's id is returned there)");
    code = refract_scene_route(c, "refract_view_create", scene_id, "/views", &path);
    if (code != REFRACT_E_OK)
        return code;
    code = call_view(c, "POST", path, body, out);
    free(path);
    return code;
}

int refract_view_create_opts(refract_client *c, const char *scene_id,
                             const struct refract_view_options *opts, struct refract_view *out)
{
    char *body = refract_view_options_json(opts);
    int code;

    if (body == NULL) {
        if (out != NULL)
            memset(out, 0, sizeof(*out));
        if (refract_begin(c, NULL) != REFRACT_E_OK)
            return REFRACT_E_USAGE;
        return refract_out_of_memory(c, "building the view's create body");
    }
    code = refract_view_create(c, scene_id, body, out);
    free(body);
    return code;
}

int refract_view_patch(refract_client *c, const char *view_id, const char *patch_json,
                       struct refract_view *out)
{
    if (out != NULL)
        memset(out, 0, sizeof(*out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (patch_json == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_view_patch: patch_json is NULL");
    return view_call(c, "refract_view_patch", "PATCH", view_id, patch_json, out);
}

int refract_view_status(refract_client *c, const char *view_id, struct refract_view *out)
{
    if (out != NULL)
        memset(out, 0, sizeof(*out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_view_status: out is NULL");
    return view_call(c, "refract_view_status", "GET", view_id, NULL, out);
}

int refract_view_delete(refract_client *c, const char *view_id)
{
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    return view_call(c, "refract_view_delete", "DELETE", view_id, NULL, NULL);
}

int refract_view_list(refract_client *c, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_view_list: json_out is NULL");
    return refract_call_json(c, "GET", "/v1/views", NULL, 0, NULL, json_out);
}

/*
 * h_storage.c - GET /v1/storage: what the data directory holds and its limits
 * (docs/api.md, "Storage"): blob bytes and count against --max-storage-bytes, scenes,
 * upload rows, and the per-upload limit --max-upload-bytes.
 */
#include "http_internal.h"

enum MHD_Result http_handle_storage(struct http_request *req)
{
    struct store_usage u;
    store_usage_get(req->app->store, &u);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "used_bytes", (double)u.blob_bytes);
    cJSON_AddNumberToObject(root, "blobs", (double)u.blob_count);
    if (u.max_storage_bytes)
        cJSON_AddNumberToObject(root, "max_storage_bytes", (double)u.max_storage_bytes);
    else
        cJSON_AddNullToObject(root, "max_storage_bytes");
    cJSON_AddNumberToObject(root, "max_upload_bytes", (double)req->cfg->max_upload_bytes);
    cJSON_AddNumberToObject(root, "scenes", (double)u.scenes);
    cJSON_AddNumberToObject(root, "uploads", (double)u.uploads);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

/*
 * h_storage.c - GET /v1/storage: what the data directory holds and its limits
 * (docs/api.md, "Storage"): blob bytes and count against --max-storage-bytes, scenes,
 * upload rows, the per-upload limit --max-upload-bytes, and the irradiance cache's files
 * (its index rows in refract.db) against --irradiance-disk-budget.
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
    /* The irradiance cache's files, from its index rows (they do not count against
     * --max-storage-bytes: they are recomputable and have their own budget). */
    long long volumes = 0;
    unsigned long long bytes = 0;
    store_irradiance_usage(req->app->store, &volumes, &bytes);
    cJSON *irr = cJSON_AddObjectToObject(root, "irradiance");
    cJSON_AddNumberToObject(irr, "volumes", (double)volumes);
    cJSON_AddNumberToObject(irr, "bytes", (double)bytes);
    cJSON_AddNumberToObject(
        irr, "disk_budget_bytes",
        (double)irradiance_cache_settings(req->app->irradiance)->disk_budget_bytes);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

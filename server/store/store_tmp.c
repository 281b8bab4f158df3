/*
 * store_tmp.c - the bytes of uploads being received, counted against --max-storage-bytes
 * (store.h): an upload streams to <data>/tmp for as long as its client sends it, and
 * before this a client that never finished its uploads could fill the disk outside the
 * limit. The check adds every upload in progress to the stored blobs; committing a blob
 * (store_blob.c) checks the blobs alone, since the upload it commits is among them.
 */
#include "store_internal.h"

enum refract_code store_upload_tmp_reserve(struct store *s, size_t bytes, struct err *e)
{
    enum refract_code rc = REFRACT_E_OK;
    pthread_mutex_lock(&s->lock);
    unsigned long long max = s->desc.max_storage_bytes;
    unsigned long long used = s->blob_bytes + s->tmp_bytes;
    if (max != 0 && used + bytes > max)
        rc = err_set(e, REFRACT_E_STORAGE,
                     "the upload does not fit in the data directory's limit: %llu of %llu bytes "
                     "are in use, %llu of them by uploads still being received (refractd "
                     "--max-storage-bytes); delete scenes or uploads (DELETE /v1/scenes/{id}), "
                     "wait for the other uploads, or raise the limit",
                     used, max, s->tmp_bytes);
    else
        s->tmp_bytes += bytes;
    pthread_mutex_unlock(&s->lock);
    return rc;
}

void store_upload_tmp_release(struct store *s, size_t bytes)
{
    pthread_mutex_lock(&s->lock);
    s->tmp_bytes -= bytes < s->tmp_bytes ? bytes : s->tmp_bytes;
    pthread_mutex_unlock(&s->lock);
}

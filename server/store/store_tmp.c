/*
 * store_tmp.c - the bytes of uploads being received, counted against --max-storage-bytes
 * (store.h): an upload streams to <data>/tmp for as long as its client sends it, and
 * before this a client that never finished its uploads could fill the disk outside the
 * limit.
 *
 * CONCEPT: the blobs and every upload in progress together stay under the limit.
 * REALITY: an upload that arrives alone is never refused here, because what it will cost
 * is known only once it is in: a duplicate of a stored blob costs nothing, and one that
 * replaces an upload frees the old one's bytes (store_blob.c checks that, at commit).
 * So the uploads arriving together must fit in the room the blobs leave, except the
 * first, which may take up to --max-upload-bytes beyond it until its commit decides:
 * the disk holds at most the limit plus one upload, however many clients send and
 * never finish.
 */
#include "store_internal.h"

enum refract_code store_upload_tmp_reserve(struct store *s, size_t held, size_t bytes,
                                           struct err *e)
{
    enum refract_code rc = REFRACT_E_OK;
    pthread_mutex_lock(&s->lock);
    unsigned long long max = s->desc.max_storage_bytes;
    unsigned long long used = s->blob_bytes + s->tmp_bytes;
    bool others = s->tmp_bytes > held;
    if (max != 0 && others && used + bytes > max)
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

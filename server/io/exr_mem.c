/*
 * exr_mem.c - an in-memory OpenEXR read source. See exr_mem.h.
 */
#include "exr_mem.h"

#include <stdint.h>
#include <string.h>

static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (ctxt == NULL || exr_get_user_data(ctxt, &ud) != EXR_ERR_SUCCESS || ud == NULL)
        return;
    struct exr_mem_src *s = ud;
    if (s->have_error)
        return;
    s->have_error = true;
    err_set(s->e, code == EXR_ERR_OUT_OF_MEMORY ? REFRACT_E_OUT_OF_MEMORY : s->bad_input,
            "OpenEXR: %s (%s)", msg ? msg : "", exr_get_error_code_as_string(code));
}

static int64_t read_src(exr_const_context_t ctxt, void *userdata, void *buffer, uint64_t sz,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    const struct exr_mem_src *s = userdata;
    if (offset >= s->len)
        return 0;
    uint64_t n = s->len - offset < sz ? s->len - offset : sz;
    memcpy(buffer, s->bytes + offset, (size_t)n);
    return (int64_t)n;
}

static int64_t size_src(exr_const_context_t ctxt, void *userdata)
{
    (void)ctxt;
    return (int64_t)((const struct exr_mem_src *)userdata)->len;
}

void exr_mem_src_attach(exr_context_initializer_t *init, struct exr_mem_src *src)
{
    init->error_handler_fn = on_error;
    init->user_data = src;
    init->read_fn = read_src;
    init->size_fn = size_src;
}

/* exr_gen.c — see exr_gen.h. */
#include "exr_gen.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct gen_sink {
    uint8_t *buf;
    size_t size, cap;
    char *err;
    size_t err_cap;
} gen_sink;

static void gen_error_cb(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (exr_get_user_data(ctxt, &ud) != EXR_ERR_SUCCESS || !ud) return;
    gen_sink *s = ud;
    if (s->err && s->err_cap && !s->err[0]) snprintf(s->err, s->err_cap, "%s (%s)", msg, exr_get_error_code_as_string(code));
}

static int64_t gen_write(exr_const_context_t ctxt, void *ud, const void *buffer, uint64_t sz, uint64_t offset,
                         exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    gen_sink *s = ud;
    size_t end = (size_t)(offset + sz);
    if (end > s->cap) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap < end) cap *= 2;
        uint8_t *nb = realloc(s->buf, cap);
        if (!nb) return -1;
        memset(nb + s->cap, 0, cap - s->cap);
        s->buf = nb;
        s->cap = cap;
    }
    memcpy(s->buf + offset, buffer, (size_t)sz);
    if (end > s->size) s->size = end;
    return (int64_t)sz;
}

uint16_t exr_gen_float_to_half(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    uint16_t sign = (uint16_t)((u >> 16) & 0x8000);
    int e8 = (int)((u >> 23) & 0xff);
    uint32_t mant = u & 0x7fffff;
    if (e8 == 0xff) return (uint16_t)(sign | 0x7c00 | (mant ? 0x200 : 0));
    int exp = e8 - 127 + 15;
    if (exp >= 31) return (uint16_t)(sign | 0x7c00);
    if (exp <= 0) {
        if (exp < -10) return sign;
        mant |= 0x800000;
        return (uint16_t)(sign | (mant >> (14 - exp)));
    }
    return (uint16_t)(sign | (exp << 10) | (mant >> 13));
}

#define GEN_TRY(call)                                                                        \
    do {                                                                                     \
        exr_result_t rv_ = (call);                                                           \
        if (rv_ != EXR_ERR_SUCCESS) {                                                        \
            if (!err[0]) snprintf(err, err_cap, "%s: %s", #call, exr_get_error_code_as_string(rv_)); \
            goto fail;                                                                       \
        }                                                                                    \
    } while (0)

bool exr_gen_write(const exr_gen_opts *o, exr_gen_value_fn value, void *user, uint8_t **data, size_t *size,
                   char *err, size_t err_cap)
{
    err[0] = '\0';
    gen_sink sink = {.err = err, .err_cap = err_cap};
    exr_context_initializer_t ci = EXR_DEFAULT_CONTEXT_INITIALIZER;
    ci.error_handler_fn = gen_error_cb;
    ci.user_data = &sink;
    ci.write_fn = gen_write;
    exr_context_t ctx = NULL;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool enc_used = false;
    int nch = (int)strlen(o->channels);
    size_t bpe = o->type == EXR_PIXEL_HALF ? 2 : 4;
    size_t npix = (size_t)o->width * (size_t)o->height;
    uint8_t *planes = malloc(npix * bpe * (size_t)nch + 1);
    if (!planes) return false;
    for (int c = 0; c < nch; c++)
        for (int y = 0; y < o->height; y++)
            for (int x = 0; x < o->width; x++) {
                float v = value(x, y, o->channels[c], user);
                uint8_t *p = planes + ((size_t)c * npix + (size_t)y * (size_t)o->width + (size_t)x) * bpe;
                if (o->type == EXR_PIXEL_HALF) {
                    uint16_t h = exr_gen_float_to_half(v);
                    memcpy(p, &h, 2);
                } else if (o->type == EXR_PIXEL_UINT) {
                    uint32_t u = v <= 0.0f ? 0u : (uint32_t)v;
                    memcpy(p, &u, 4);
                } else {
                    memcpy(p, &v, 4);
                }
            }

    GEN_TRY(exr_start_write(&ctx, "gen.exr", EXR_WRITE_FILE_DIRECTLY, &ci));
    int part = 0;
    GEN_TRY(exr_add_part(ctx, NULL, o->tiled ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part));
    exr_attr_box2i_t dw = {.min = {.x = o->min_x, .y = o->min_y},
                           .max = {.x = o->min_x + o->width - 1, .y = o->min_y + o->height - 1}};
    exr_attr_v2f_t swc = {.x = 0, .y = 0};
    GEN_TRY(exr_initialize_required_attr(ctx, part, &dw, &dw, 1.0f, &swc, 1.0f, EXR_LINEORDER_INCREASING_Y,
                                         o->compression));
    for (int c = 0; c < nch; c++) {
        char name[2] = {o->channels[c], 0};
        GEN_TRY(exr_add_channel(ctx, part, name, o->type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1));
    }
    if (o->tiled) GEN_TRY(exr_set_tile_descriptor(ctx, part, (uint32_t)o->tile_w, (uint32_t)o->tile_h, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN));
    if (o->chroma) GEN_TRY(exr_attr_set_chromaticities(ctx, part, "chromaticities", o->chroma));
    GEN_TRY(exr_write_header(ctx));

    int nx = 1, ny, step = 1;
    if (o->tiled) {
        nx = (o->width + o->tile_w - 1) / o->tile_w;
        ny = (o->height + o->tile_h - 1) / o->tile_h;
    } else {
        int32_t lines = 1;
        GEN_TRY(exr_get_scanlines_per_chunk(ctx, part, &lines));
        step = lines;
        ny = (o->height + lines - 1) / lines;
    }
    for (int ty = 0; ty < ny; ty++)
        for (int tx = 0; tx < nx; tx++) {
            exr_chunk_info_t cinfo;
            int x0 = 0, y0;
            if (o->tiled) {
                GEN_TRY(exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &cinfo));
                x0 = tx * o->tile_w;
                y0 = ty * o->tile_h;
            } else {
                y0 = ty * step;
                GEN_TRY(exr_write_scanline_chunk_info(ctx, part, o->min_y + y0, &cinfo));
            }
            if (enc_used) GEN_TRY(exr_encoding_update(ctx, part, &cinfo, &enc));
            else {
                enc_used = true;
                GEN_TRY(exr_encoding_initialize(ctx, part, &cinfo, &enc));
            }
            for (int c = 0; c < enc.channel_count; c++) {
                int idx = (int)(strchr(o->channels, enc.channels[c].channel_name[0]) - o->channels);
                enc.channels[c].encode_from_ptr =
                    planes + ((size_t)idx * npix + (size_t)y0 * (size_t)o->width + (size_t)x0) * bpe;
                enc.channels[c].user_pixel_stride = (int32_t)bpe;
                enc.channels[c].user_line_stride = (int32_t)(bpe * (size_t)o->width);
                enc.channels[c].user_data_type = (uint16_t)o->type;
                enc.channels[c].user_bytes_per_element = (int16_t)bpe;
            }
            GEN_TRY(exr_encoding_choose_default_routines(ctx, part, &enc));
            GEN_TRY(exr_encoding_run(ctx, part, &enc));
        }
    if (enc_used) exr_encoding_destroy(ctx, &enc);
    enc_used = false;
    GEN_TRY(exr_finish(&ctx));
    free(planes);
    *data = sink.buf;
    *size = sink.size;
    return true;
fail:
    if (enc_used) exr_encoding_destroy(ctx, &enc);
    if (ctx) exr_finish(&ctx);
    free(planes);
    free(sink.buf);
    return false;
}

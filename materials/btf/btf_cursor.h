/* btf_cursor.h — reading a little-endian file from memory for the BTF readers (internal to
 * materials/btf): every read checks the bytes left first; failures are one line
 * "<name>: byte <offset> (<field>): <problem>". */
#ifndef PRW_BTF_CURSOR_H
#define PRW_BTF_CURSOR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "prw_core.h"

typedef struct btf_cur {
    const uint8_t *p;
    size_t n, at;
    const char *name;
    prw_error *e;
} btf_cur;

static inline uint32_t prw_btf_le32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/* Fails naming the current offset and the field; returns false. */
bool btf_cur_fail(btf_cur *c, const char *what, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* count elements of size bytes fit in what is left; else fails. */
bool btf_cur_need(btf_cur *c, uint64_t count, uint64_t size, const char *what);
bool btf_cur_take(btf_cur *c, void *dst, size_t bytes, const char *what);
bool btf_cur_u8(btf_cur *c, const char *what, uint8_t *v);
bool btf_cur_u32(btf_cur *c, const char *what, uint32_t *v);
bool btf_cur_f32(btf_cur *c, const char *what, float *v);

#endif

/* btf_cursor.c — see btf_cursor.h. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "btf_cursor.h"

bool btf_cur_fail(btf_cur *c, const char *what, const char *fmt, ...)
{
    char why[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    return prw_fail(c->e, "%s: byte %zu (%s): %s", c->name, c->at, what, why);
}

bool btf_cur_need(btf_cur *c, uint64_t count, uint64_t size, const char *what)
{
    uint64_t bytes = prw_mul_sat(count, size);
    if (bytes > (uint64_t)(c->n - c->at))
        return btf_cur_fail(c, what, "%llu x %llu bytes claimed, only %zu bytes left in the file",
                            (unsigned long long)count, (unsigned long long)size, c->n - c->at);
    return true;
}

bool btf_cur_take(btf_cur *c, void *dst, size_t bytes, const char *what)
{
    if (!btf_cur_need(c, bytes, 1, what)) return false;
    if (bytes) memcpy(dst, c->p + c->at, bytes);
    c->at += bytes;
    return true;
}

bool btf_cur_u8(btf_cur *c, const char *what, uint8_t *v) { return btf_cur_take(c, v, 1, what); }

bool btf_cur_u32(btf_cur *c, const char *what, uint32_t *v)
{
    uint8_t b[4];
    if (!btf_cur_take(c, b, 4, what)) return false;
    *v = prw_btf_le32(b);
    return true;
}

bool btf_cur_f32(btf_cur *c, const char *what, float *v)
{
    uint32_t u;
    if (!btf_cur_u32(c, what, &u)) return false;
    memcpy(v, &u, 4);
    return true;
}

/* json_doc.c — see prw_json_doc.h. */
#include "prw_json_doc.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

void prw_json_sanitize(char *dst, size_t cap, const char *src, size_t n)
{
    size_t o = 0;
    for (size_t i = 0; i < n && src[i] && o + 1 < cap; i++) {
        unsigned char ch = (unsigned char)src[i];
        dst[o++] = (ch >= 0x20 && ch < 0x7f) ? (char)ch : '?';
    }
    dst[o] = '\0';
}

static void line_col(const char *text, size_t size, size_t off, int *line, int *col)
{
    if (off > size) off = size;
    int l = 1;
    size_t start = 0;
    for (size_t i = 0; i < off; i++)
        if (text[i] == '\n') {
            l++;
            start = i + 1;
        }
    *line = l;
    *col = (int)(off - start) + 1;
}

cJSON *prw_json_doc_parse(const char *text, size_t size, const char *file, prw_error *e)
{
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, size, &end, false);
    int line, col;
    if (!root) {
        size_t off = end && end >= text ? (size_t)(end - text) : 0;
        line_col(text, size, off, &line, &col);
        if (off >= size) {
            prw_fail(e, "%s:%d:%d: JSON syntax error: unexpected end of input", file, line, col);
            return NULL;
        }
        char near[40];
        prw_json_sanitize(near, sizeof near, text + off, PRW_MIN(size - off, (size_t)24));
        prw_fail(e, "%s:%d:%d: JSON syntax error near '%s'", file, line, col, near);
        return NULL;
    }
    size_t off = (size_t)(end - text);
    while (off < size && (text[off] == ' ' || text[off] == '\t' || text[off] == '\n' || text[off] == '\r')) off++;
    if (off < size) {
        line_col(text, size, off, &line, &col);
        cJSON_Delete(root);
        prw_fail(e, "%s:%d:%d: unexpected text after the JSON document", file, line, col);
        return NULL;
    }
    return root;
}

bool prw_json_fail_at(const prw_json_ctx *c, const char *place, const char *fmt, ...)
{
    char reason[PRW_ERROR_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    if (place && place[0]) return prw_fail(c->e, "%s:%s: %s", c->file, place, reason);
    return prw_fail(c->e, "%s: %s", c->file, reason);
}

void prw_json_join(char *out, size_t cap, const char *place, const char *key)
{
    size_t o = 0;
    for (const char *s = place; *s && o + 1 < cap; s++) out[o++] = *s;
    if (place[0] && o + 1 < cap) out[o++] = '.';
    for (const char *s = key; *s && o + 1 < cap; s++) out[o++] = *s;
    out[o] = '\0';
}

bool prw_json_check_keys(const prw_json_ctx *c, const cJSON *obj, const char *place, const char *const *keys, int n)
{
    uint64_t seen = 0;
    for (const cJSON *it = obj->child; it; it = it->next) {
        int k = -1;
        for (int i = 0; i < n && i < 64 && k < 0; i++)
            if (it->string && strcmp(it->string, keys[i]) == 0) k = i;
        char name[80];
        prw_json_sanitize(name, sizeof name, it->string ? it->string : "", 64);
        if (k < 0) return prw_json_fail_at(c, place, "unknown key '%s'", name);
        if (seen & (1ull << k)) return prw_json_fail_at(c, place, "duplicate key '%s'", name);
        seen |= 1ull << k;
    }
    return true;
}

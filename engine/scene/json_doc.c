/* json_doc.c — see prw_json_doc.h. */
#include "prw_json_doc.h"

#include <stdio.h>

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

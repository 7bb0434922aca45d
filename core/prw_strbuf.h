/* prw_strbuf — a growing text buffer for writers that build a file in memory (JSON, glTF).
 * Zero-initialised it is empty (p NULL); after the first append p is NUL-terminated text of n bytes.
 * The caller owns p (free). */
#ifndef PRW_STRBUF_H
#define PRW_STRBUF_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_strbuf {
    char *p;
    size_t n, cap;
} prw_strbuf;

/* Appends printf-formatted text (grows by doubling; out of memory aborts as prw_realloc does). */
void prw_strbuf_printf(prw_strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#ifdef __cplusplus
}
#endif

#endif

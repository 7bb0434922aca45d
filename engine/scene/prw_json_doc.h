/* prw_json_doc — the one way prw's JSON readers (scene manifest, camera paths, display and HMD
 * profiles) open a document: cJSON parse with the error place as line:col, trailing text rejected.
 * Errors read "<file>:<line>:<col>: JSON syntax error near '<text>'" (or "...: unexpected end of
 * input", "...: unexpected text after the JSON document"). */
#ifndef PRW_JSON_DOC_H
#define PRW_JSON_DOC_H

#include <cJSON.h>

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The parsed document (free with cJSON_Delete), or NULL with e set. text need not be NUL-terminated. */
cJSON *prw_json_doc_parse(const char *text, size_t size, const char *file, prw_error *e);

/* Copies at most n bytes of src (stopping at NUL) into dst (cap >= 1), non-printable bytes as '?':
 * for quoting input text in error messages. */
void prw_json_sanitize(char *dst, size_t cap, const char *src, size_t n);

/* Errors at a place inside a document read "<file>:<place>: <reason>" ("<file>: <reason>" when place
 * is empty), e.g. "hmd.json:distortion_k[2]: must be a finite number". */
typedef struct prw_json_ctx {
    const char *file;
    prw_error *e;
} prw_json_ctx;
bool prw_json_fail_at(const prw_json_ctx *c, const char *place, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* out = "place.key", or "key" when place is empty; truncated to cap - 1 bytes. */
void prw_json_join(char *out, size_t cap, const char *place, const char *key);

/* Every member of obj has one of the n (<= 64) names in keys and none appears twice; otherwise the
 * error "unknown key '<k>'" or "duplicate key '<k>'" at place (the key quoted via prw_json_sanitize). */
bool prw_json_check_keys(const prw_json_ctx *c, const cJSON *obj, const char *place, const char *const *keys, int n);

#ifdef __cplusplus
}
#endif
#endif

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

#ifdef __cplusplus
}
#endif
#endif

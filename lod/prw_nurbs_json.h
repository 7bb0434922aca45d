/* prw_nurbs_json — the JSON form of a trimmed-NURBS model, for hand-made models and tests.
 * The format is documented in lod/nurbs_json.md.
 *
 * Promises: the whole document is validated (every knot vector, weight and trim curve); on
 * failure nothing is returned and the error reads "<name>:<json path>: <reason>".  Coordinates are
 * converted to metres with the document's "unit"/"scale". */
#ifndef PRW_NURBS_JSON_H
#define PRW_NURBS_JSON_H

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

bool prw_nurbs_json_parse(const char *text, size_t len, const char *name, prw_nurbs_model *out, prw_error *e);
bool prw_nurbs_json_load(const char *path, prw_nurbs_model *out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif

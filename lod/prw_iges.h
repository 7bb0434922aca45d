/* prw_iges — IGES 5.3 reader for trimmed NURBS models.
 *
 * Promises:
 *  - ASCII fixed-80-column files (S, G, D, P, T sections in that order; the Start section may be
 *    empty; lines end in LF or CRLF, or the file is a bare run of 80-column records).  Every
 *    record is checked: length 80 (trailing blanks beyond 80 tolerated), section letter in column
 *    73, sequence number 1, 2, … in columns 74–80, D records in pairs, P back-pointers, and the
 *    Terminate record's section counts.  Binary and compressed forms are rejected.  Tolerated,
 *    with a note in info->warning (OpenCASCADE reads such files): a Terminate record miscounting
 *    the Start or Global section; a directory entry whose parameter record count disagrees with
 *    the P records pointing back to it when those hold a whole record (they are taken).
 *  - Parameters use the delimiters from the Global section (Hollerith strings nH…; reals with E
 *    or D exponents).  Units: Global unit flag 1–11 (flag 3: the unit name; flag 0 with no unit
 *    name: the default, inches, noted in info->warning) → metres, divided by
 *    the model space scale (parameter 13: model/real-world ratio).  Transformation matrices (124,
 *    chained) are applied.  The output is in metres.
 *  - Converted: 100, 102, 110, 112 (Bezier pieces, its own parameter kept), 124, 126, 128, 142,
 *    144, 314; 108 and 190 (point 116 + normal 123; form 1's reference direction orients u) as a
 *    bilinear patch covering the bounding / trim curves (or the display size), 118
 *    (degree (p, 1) ruled NURBS on equal relative parameters), 120 (A8.1 revolution, rational
 *    quadratic circle of ≤ 4 arcs), 122 (C(u) + v·d) — exactly, see lod/nurbs_json.md §IGES for the
 *    constructions; bounded surfaces (143 with 141 boundaries) and B-rep solids and shells (186,
 *    514, 510, 508, 504, 502; a face's orientation flag reverses it in u) become trimmed surfaces.
 *  - Drawn: every 144, 143, 128, 108, 118, 120 and 122 whose Directory Entry subordinate switch is
 *    "independent" or "logically dependent" (physically dependent entities are parts of others),
 *    every face of a 186, of a 514 no solid uses, and every 510 no shell uses (also when flagged
 *    physically dependent, unless a 308 subfigure holds it: a free face); a surface
 *    referenced by a 144 / 143 / 510 is never drawn untrimmed.  A 142 without a parameter-space
 *    curve (or on a 108, which has no IGES parameterisation) is projected into (u, v) by point
 *    inversion.
 *  - Everything else (e.g. 140, annotation) is skipped, and a face that needs a skipped entity is
 *    left out: info->warning lists each skipped type with its count and the faces left out, in one
 *    line; nothing is printed.
 *  - Work is bounded: curve pieces plus projected points beyond prw_iges_default_work(size) fail
 *    the read ("too much geometry").
 *  - A malformed record fails the whole read with "<name>:<line>: <reason>", line = 1-based line
 *    of the offending record in the file.
 */
#ifndef PRW_IGES_H
#define PRW_IGES_H

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_iges_info {
    char warning[1024]; /* "" when nothing was skipped; else one line: "<name>: skipped N unsupported
                           entities: 212 x2, 406 x1; M faces left out, they need 140 x1" */
    int entities;       /* directory entries */
    int trimmed, untrimmed;
    int skipped;       /* directory entries of types this reader does not convert */
    int faces_skipped; /* faces left out because they need such an entity (e.g. a 140 surface) */
    double metres_per_unit; /* unit factor / model space scale, as applied */
    double max_projection_distance; /* largest distance of a projected 142 curve point (metres) */
} prw_iges_info;

bool prw_iges_parse(const char *data, size_t size, const char *name, prw_nurbs_model *out, prw_iges_info *info,
                    prw_error *e);
/* prw_iges_parse with its work limit given: `work` curve pieces and projected points in all (beyond
 * it the read fails, "too much geometry"); prw_iges_parse allows prw_iges_default_work(size) =
 * 4e6 + 64 x size.  For callers that must bound the time per file more tightly (the fuzz target). */
bool prw_iges_parse_limited(const char *data, size_t size, const char *name, long work, prw_nurbs_model *out,
                            prw_iges_info *info, prw_error *e);
long prw_iges_default_work(size_t size);
bool prw_iges_load(const char *path, prw_nurbs_model *out, prw_iges_info *info, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif

/* Internal to prw_lod_*.c: boundary spans, triangle error bounds and the centroid-fan checks. */
#ifndef PRW_LOD_INTERNAL_H
#define PRW_LOD_INTERNAL_H

#include "prw_lod.h"

typedef struct lod_ivec {
    int *v;
    int n, cap;
} lod_ivec;

void lod_ipush(lod_ivec *l, int x);
/* Removes one x (order not kept). */
void lod_iremove(lod_ivec *l, int x);

/* A binary min-heap of candidate collapses v -> w (cost first; sv, sw: the callers' staleness
 * stamps), shared by the patch hierarchy and the whole-model proxy. */
typedef struct lod_hent {
    double cost;
    int v, w;
    unsigned sv, sw;
} lod_hent;

typedef struct lod_heap {
    lod_hent *a;
    int n, cap;
} lod_heap;

void lod_heap_push(lod_heap *h, lod_hent x);
lod_hent lod_heap_pop(lod_heap *h); /* h->n > 0 */

/* Is vertex v present?  active != NULL: active[v]; else removed_at[v] > level. */
static inline bool lod_active(const prw_lod_patch *p, const unsigned char *active, int level, int v)
{
    return active ? active[v] != 0 : p->removed_at[v] > level;
}

/* If (a, b) is a boundary edge (consecutive present vertices of one ring), the ring positions
 * strictly between them, ordered from a to b, go to *span and true is returned. */
bool lod_span(const prw_lod_patch *p, int a, int b, const unsigned char *active, int level, lod_ivec *span);

/* The (u, v) centroid and 3-D position used for display fans (one formula everywhere). */
static inline void lod_centroid(const prw_lod_patch *p, int a, int b, int c, double *uv, prw_dvec3 *x)
{
    uv[0] = (p->uv[2 * a] + p->uv[2 * b] + p->uv[2 * c]) / 3;
    uv[1] = (p->uv[2 * a + 1] + p->uv[2 * b + 1] + p->uv[2 * c + 1]) / 3;
    *x = prw_v3_scale(prw_v3_add(prw_v3_add(p->pos[a], p->pos[b]), p->pos[c]), 1.0 / 3);
}

/* 3-D validity of a triangle: non-zero area, every height above 1e-8·diag, and a normal within 90°
 * of the surface normal at uvc (skipped where that vanishes).  Triangles joining two copies of one
 * node are exempt (dropped at output).  a may be -1 (a fan centroid). */
bool lod_tri3_ok(const prw_nurbs_surface *s, const prw_lod_patch *p, double diag, int a, int b, int c, const double *uvc,
                 prw_dvec3 xa, prw_dvec3 xb, prw_dvec3 xc);

/* Error bound of triangle (a, b, c) (CCW in uv) with its finest fan; also checks the fan.
 * Returns false when the triangle or its fan is invalid (orientation / zero area / normal). */
bool lod_triangle_eval(const prw_seam_graph *g, const prw_nurbs_surface *s, const prw_lod_patch *p, int a, int b, int c,
                       const unsigned char *active, double *err);
/* The same; *boundary_err (may be NULL) = the part of the bound due to the boundary chords alone
 * (what no interior refinement can lower). */
bool lod_triangle_eval_parts(const prw_seam_graph *g, const prw_nurbs_surface *s, const prw_lod_patch *p, int a, int b,
                             int c, const unsigned char *active, double *err, double *boundary_err);

#endif

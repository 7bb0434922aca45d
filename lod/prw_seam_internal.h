/* Internal to the seam-graph setup (prw_seam_curves.c, prw_seam_build.c): boundary curves in
 * model space, their dense flattening, the adjacency grid and the pieces they are split into. */
#ifndef PRW_SEAM_INTERNAL_H
#define PRW_SEAM_INTERNAL_H

#include <stdint.h>

#include "prw_seam.h"

typedef struct seam_curve {
    int patch, loop;
    const prw_nurbs_surface *surf;
    prw_nurbs_curve uv; /* owned copy */
    double t0, t1;
    int n;              /* dense points */
    double *t;
    prw_dvec3 *x;
    double length;
    prw_dvec3 lo, hi;
} seam_curve;

typedef struct seam_piece {
    int curve;
    double ta, tb;
    int label; /* partner curve, -1 none */
    bool degenerate;
    int node[2];
    int match; /* matched piece, -1 */
    int seg;
    bool reversed; /* partner piece runs against the segment */
    int side;
} seam_piece;

typedef struct seam_ctx {
    const prw_nurbs_model *m;
    double tol, chord, max_edge;
    seam_curve *curves;
    int ncurves;
    /* per patch: loops as ranges of curves */
    int *patch_loop_first; /* per patch: first entry in loop_curve_start */
    int *loop_curve_start; /* curves of global loop L are [loop_curve_start[L], loop_curve_start[L+1]) */
    int nloops_total;
    /* adjacency grid: sorted (cell hash, edge) pairs; edge = curve << 32 | index */
    uint64_t *cell_key;
    uint64_t *cell_edge;
    size_t ncell;
    double cell;
    prw_dvec3 origin;
    seam_piece *pieces;
    int npieces;
} seam_ctx;

prw_dvec3 seam_curve_eval(const seam_curve *c, double t);
double seam_curve_uv(const seam_curve *c, double t, double *uv);
/* Builds ctx->curves (dense) and the grid. */
bool seam_curves_build(seam_ctx *c, prw_seam_graph *g, prw_error *e);
/* Nearest other curve within tol (direction within 60°) at x; returns the curve or -1. */
int seam_nearest_curve(const seam_ctx *c, prw_dvec3 x, prw_dvec3 dir, int exclude, double radius, double *dist);
/* Splits every curve into labelled pieces (ctx->pieces, in curve order, t ascending). */
void seam_pieces_build(seam_ctx *c);
/* Distance from x to the curve's dense polyline restricted to [ta, tb]; *t gets the nearest t. */
double seam_curve_project(const seam_curve *c, prw_dvec3 x, double ta, double tb, double *t);
void seam_ctx_free(seam_ctx *c);

#endif

/* prw_seam — the seam graph of a trimmed-NURBS model (Meseth, ch. 6.1): Patch → Boundary (trim
 * loop) → Boundary Segment → Boundary Vertex (sewing points shared by adjacent patches).
 *
 * Setup (prw_seam_build):
 *  1. Every trim curve of every patch (a natural outer boundary becomes the four domain edges) is
 *     mapped to model space through its surface and flattened densely (3-D chord error ≤ chord/16,
 *     edges ≤ max_edge/4).
 *  2. Adjacency: each dense point of a curve is labelled with the nearest OTHER curve (any patch,
 *     the same patch included — a periodic seam) within `tol` whose direction there is within 60°
 *     of the curve's; runs of equal labels become pieces, split where the label changes at the
 *     parameter found by bisection on the exact curve.  Curves shorter than `tol` in 3-D (collapsed
 *     edges, sphere poles) become degenerate pieces.
 *  3. Piece ends are clustered within `tol` into nodes (union-find).  A labelled piece of patch A
 *     and a piece of its partner B labelled A with the same unordered node pair and midpoints within
 *     `tol` form one SHARED segment; pieces left over are OPEN segments (true borders, or gaps wider
 *     than the tolerance — each open segment's largest distance to the nearest other boundary is
 *     reported).  A segment is shared by at most two patches.
 *  4. Sewing points: sampled ONCE per segment on the owner piece (the first patch) to the chordal
 *     tolerance `chord` (3-D distance of the exact curve to the chord, checked at ¼, ½, ¾) and at
 *     most `max_edge` apart; the ends are the node positions.  Both patches use these positions
 *     bit-for-bit; the partner's (u, v) for each point is found by projection onto its own curve.
 *  5. Per segment, `dense` exact-curve samples between the sewing points (for error measurement),
 *     the largest distance of the sewing polyline to them (`chord_err`), and the minimum number of
 *     interior points every coarser level keeps (2 for a closed segment, 1 when another segment
 *     joins the same two nodes, else 0), so coarse boundary loops never degenerate.
 * Global vertex ids ("gid"): nodes are 0 .. nnodes-1; interior sewing point i (1 .. npts-2) of
 * segment s is seg[s].gid0 + i - 1.  prw_seam_gid_pos gives the shared position.
 * Nothing here prints.  A patch whose trim curves cannot be flattened is skipped (counted).
 */
#ifndef PRW_SEAM_H
#define PRW_SEAM_H

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_seam_options {
    double tol;      /* adjacency tolerance (metres); 0: 1e-6 x model diagonal */
    double chord;    /* sewing chordal tolerance (metres); 0: 1e-3 x model diagonal */
    double max_edge; /* longest sewing edge (metres); 0: diagonal / 40 */
} prw_seam_options;

#define PRW_SEAM_DENSE 6 /* exact-curve samples per sewing edge, besides its ends */

typedef struct prw_seam_segment {
    int node[2];     /* start / end node (equal: closed segment or degenerate) */
    int patch[2];    /* patch[0] owns the sampling; patch[1] = -1 when open */
    int loop[2];     /* the trim loop (index in the patch's seam loops) on each side */
    bool degenerate; /* shorter than tol in 3-D: no interior points; never drawn as an edge */
    int npts;        /* sewing points, ends included */
    prw_dvec3 *pts;  /* npts; pts[0] / pts[npts-1] are the node positions (same bits) */
    double *uv[2];   /* 2 * npts per side, in segment order */
    int gid0;        /* gid of interior point 1 */
    int min_interior;
    prw_dvec3 *dense; /* (npts - 1) * PRW_SEAM_DENSE exact-curve points, edge i at [i * DENSE ..] */
    double chord_err; /* max distance of dense points to the sewing polyline */
    double gap;       /* shared: max |S_partner(uv) - sewing point|; open: max distance to the nearest
                         other boundary, INFINITY when none within 100 tol */
    double length;
} prw_seam_segment;

typedef struct prw_seam_use {
    int seg;
    bool reversed; /* walk the segment from its end to its start */
    int side;      /* 0 or 1: which uv array of the segment is this patch's */
} prw_seam_use;

typedef struct prw_seam_loop {
    prw_seam_use *uses; /* in loop order; use k ends where use k+1 starts */
    int count;
} prw_seam_loop;

typedef struct prw_seam_patch {
    prw_seam_loop *loops;
    int nloops;
    bool skipped; /* could not be processed (message in the report) */
    prw_dvec3 lo, hi; /* bounding box of the sewing points and control hull */
} prw_seam_patch;

typedef struct prw_seam_graph {
    prw_dvec3 *nodes;
    int nnodes;
    prw_seam_segment *segs;
    int nsegs;
    prw_seam_patch *patches;
    int npatches;
    int ngids;
    double tol, chord, max_edge, diag;
    /* report */
    int shared, open, degenerate, unmatched, skipped_patches;
    double max_shared_gap;
    char first_problem[256];
} prw_seam_graph;

bool prw_seam_build(const prw_nurbs_model *m, const prw_seam_options *o, prw_seam_graph *g, prw_error *e);
void prw_seam_free(prw_seam_graph *g);
prw_dvec3 prw_seam_gid_pos(const prw_seam_graph *g, int gid);
/* gid of sewing point i (0 .. npts-1) of segment s. */
int prw_seam_point_gid(const prw_seam_graph *g, int s, int i);

#ifdef __cplusplus
}
#endif
#endif

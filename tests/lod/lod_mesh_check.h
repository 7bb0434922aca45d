/* Watertightness checks for extracted LOD meshes (tests only): weld bit-identical positions, count
 * edge uses, find T-junctions and zero-area triangles. */
#ifndef LOD_MESH_CHECK_H
#define LOD_MESH_CHECK_H

#include "prw_lod.h"

typedef struct lod_border_set lod_border_set;

typedef struct lod_check_result {
    size_t verts, tris, edges;
    int bad_edges;    /* used once off a true border, or more than twice */
    int border_edges; /* used once on an open segment */
    int tjunctions;   /* a vertex within eps of another edge's interior */
    int zero_area;    /* |cross| <= 1e-12 · longest edge² */
    double min_rel_area;
} lod_check_result;

/* The sewing points of the graph's open (true-border) segments. */
lod_border_set *lod_border_set_make(const prw_seam_graph *g);
void lod_border_set_free(lod_border_set *b);
/* eps_tj: T-junction distance (0 skips that check). */
void lod_check_mesh(const lod_border_set *b, const prw_lod_mesh *m, double eps_tj, lod_check_result *r);

#endif

/* prw_lod_select — per-frame CPU choice of each patch's level (Meseth §6.3).
 *
 * Promises:
 *  - d = distance from the NEARER eye to the patch's bounding box (control hull ∪ sewing points,
 *    which contains the exact patch): a conservative (small) distance, so the projected error
 *    err / (d · pixel_angle) over-estimates what any point of the patch shows.
 *  - Acceptable error ε = max(tol_px · pixel_angle · d, floor_frac · sewing error); the level is
 *    the coarsest whose stored bound is <= ε.  Where the floor raised ε above the pixel tolerance
 *    and the chosen level's error projects above tol_px, the patch counts in floor_binds; where
 *    even level 0 exceeds ε, level 0 is taken and the patch counts in finest_binds.
 *  - One choice serves both eyes.  Segments then follow prw_lod_segment_levels (the finer side).
 *  - Optional triangle budget: while the sum of the patches' level triangle counts exceeds it, the
 *    patch whose next coarser level projects the smallest error is coarsened (priority order);
 *    budget_binds / budget_steps report it and max_px is the worst projected error afterwards.
 *  - Not yet: frustum and normal-cone back-face culling (a later step; every patch is selected).
 */
#ifndef PRW_LOD_SELECT_H
#define PRW_LOD_SELECT_H

#include "prw_lod.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_lod_view {
    prw_dvec3 eye[2];
    int neyes;          /* 1 or 2 */
    double pixel_angle; /* radians per pixel */
    double tol_px;      /* 0: 0.5 */
    double floor_frac;  /* 0: 0.1 */
    size_t tri_budget;  /* 0: no budget */
} prw_lod_view;

typedef struct prw_lod_select_report {
    int floor_binds, finest_binds;
    bool budget_binds;
    int budget_steps;
    size_t triangles;
    double max_px;
} prw_lod_select_report;

double prw_lod_patch_distance(const prw_lod_model *lm, int patch, const prw_lod_view *v);
/* Projected size in pixels of an error `err` at patch `patch`. */
double prw_lod_project(const prw_lod_model *lm, int patch, const prw_lod_view *v, double err);
void prw_lod_select(const prw_lod_model *lm, const prw_lod_view *v, int *levels, prw_lod_select_report *r);

#ifdef __cplusplus
}
#endif
#endif

/* Dense two-sided distance between an extracted patch mesh and its exact trimmed surface (tests). */
#ifndef LOD_DISTANCE_H
#define LOD_DISTANCE_H

#include "prw_lod.h"

/* Surface -> mesh: an n x n (u, v) grid, points inside the trimmed region (prw_trim at 1e-6 of the
 * domain) to the nearest triangle.  Mesh -> surface: an order-`order` barycentric grid on every
 * triangle to the untrimmed surface by point inversion.  Returns the larger.  Exact for the max:
 * a sample is settled early only when an upper bound of its distance (some triangle's, or Newton
 * from the previous foot point) is already within the running max; otherwise the full search
 * (every triangle / grid-start inversion) decides. */
double lod_two_sided(const prw_trimmed_surface *t, const prw_lod_mesh *m, int n, int order);

/* The same for a whole model: surface -> mesh samples of every patch (n x n each, inside its trim)
 * to the nearest triangle; mesh -> surface: each barycentric sample to the union of the trimmed
 * patches, per patch an upper bound of the distance (the inversion's foot when it lies in the
 * trimmed region, else the nearest of 8 exact samples per trim-polygon edge), patches skipped by
 * their control-hull box.  The mesh -> surface half can only overestimate. */
double lod_two_sided_model(const prw_nurbs_model *mdl, const prw_lod_mesh *m, int n, int order);

#endif

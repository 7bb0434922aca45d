/* Dense two-sided distance between an extracted patch mesh and its exact trimmed surface (tests). */
#ifndef LOD_DISTANCE_H
#define LOD_DISTANCE_H

#include "prw_lod.h"

/* Surface -> mesh: an n x n (u, v) grid, points inside the trimmed region (prw_trim at 1e-6 of the
 * domain) to the nearest triangle.  Mesh -> surface: an order-`order` barycentric grid on every
 * triangle to the untrimmed surface by point inversion.  Returns the larger. */
double lod_two_sided(const prw_trimmed_surface *t, const prw_lod_mesh *m, int n, int order);

#endif

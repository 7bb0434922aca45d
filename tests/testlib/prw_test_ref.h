/* prw_test_ref — a reference image rendered only at the pixels a test reads.
 *
 * Tests that judge the rasterizer over a mask (a mirror, a floor, chart borders) read the path
 * tracer's image only there.  prw_reference.h promises that samples are scrambled per pixel and that
 * tiles merge bit-exactly, so those pixels come out bit-identical to a whole-image render at a
 * fraction of its cost. */
#ifndef PRW_TEST_REF_H
#define PRW_TEST_REF_H

#include <stdint.h>

#include "prw_image.h"
#include "prw_reference.h"

/* The mean image of view v for desc's sample range, seed, filter and threads (its tile is ignored)
 * at the pixels where need[y * width + x] != 0 (need NULL: every pixel), one tile per run of such
 * pixels in a row; the mean is formed as prw_ref_acc_images forms it.  The other pixels are NaN
 * (alpha 1), so a test that reads outside its mask shows NaN figures.  *out is allocated
 * (width x height of v); *pixels (may be NULL) gets the count rendered. */
bool prw_test_ref_pixels(prw_ref_renderer *ref, const prw_view *v, const prw_ref_desc *desc, const uint8_t *need,
                         prw_image *out, size_t *pixels, prw_error *e);

#endif

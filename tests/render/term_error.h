/* term_error — the error of a rasterised GI term against the reference's term over a pixel mask, as
 * test_mirror and test_glossy measure it (rendering-test helper; CHECK failures end the test). */
#ifndef TERM_ERROR_H
#define TERM_ERROR_H

#include "lightmaps.h"
#include "prw_image.h"

typedef struct term_err {
    double relmse, flip;
} term_err;

/* relMSE (eps PRW_RELMSE_EPSILON) and mean LDR-FLIP over the mask; both images zeroed outside it and
 * tone mapped at EV100 ev. */
void masked_error(const prw_image *test, const prw_image *ref, const unsigned char *mask, double ev, term_err *out);

/* The light maps of s from a reduced bake made here, no cache (radiosity_size and samples as given, seed 7;
 * 32 and 8 in light mode): the baked indirect diffuse the base pass and the mirror images draw, into
 * *out.  Prints its figures; CHECK failures end the test. */
void term_bake(const prw_scene *s, uint32_t radiosity_size, uint32_t samples, prw_app_lightmaps **out);

#endif

/* Small helpers shared by the metrics tests: a seeded generator and image fills. */
#ifndef PRW_METRICS_TESTUTIL_H
#define PRW_METRICS_TESTUTIL_H

#include <math.h>
#include <stdint.h>

#include "prw_image.h"

typedef struct trng {
    uint64_t s;
} trng;

/* xorshift64* (Vigna 2016) */
static inline uint64_t trng_u64(trng *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return r->s * 2685821657736338717ULL;
}
/* uniform in [0,1) with 53 bits */
static inline double trng_uniform(trng *r) { return (double)(trng_u64(r) >> 11) * (1.0 / 9007199254740992.0); }
/* standard normal, Box-Muller */
static inline double trng_normal(trng *r)
{
    double u1 = trng_uniform(r), u2 = trng_uniform(r);
    if (u1 < 1e-300) u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586476925 * u2);
}

static inline void fill_rgb(prw_image *img, float r, float g, float b)
{
    for (int i = 0; i < img->width * img->height; i++) {
        img->rgba[i * 4] = r;
        img->rgba[i * 4 + 1] = g;
        img->rgba[i * 4 + 2] = b;
        img->rgba[i * 4 + 3] = 1.0f;
    }
}

static inline float *px(prw_image *img, int x, int y) { return img->rgba + ((size_t)y * img->width + x) * 4; }

#endif

/* btf_ubo.c — the Bonn-format BTF in memory: freeing, value lookup, colour models, halves
 * (prw_btf_ubo.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "btf_ubo_internal.h"

void prw_btf_ubo_free(prw_btf_ubo *b)
{
    if (!b) return;
    free(b->xml);
    if (b->channel_names)
        for (uint32_t i = 0; i < b->channels; i++) free(b->channel_names[i]);
    free(b->channel_names);
    free(b->channel_len);
    free(b->view_dirs);
    free(b->light_dirs);
    free(b->rotations);
    if (b->factors) {
        uint32_t n = b->format == PRW_BTF_UBO_DFMF ? b->channels : 1;
        for (uint32_t i = 0; i < n; i++) {
            free(b->factors[i].s);
            free(b->factors[i].u);
            free(b->factors[i].sxv);
        }
    }
    free(b->factors);
    free(b->height_map);
    free(b->mask);
    free(b->bdi);
    free(b->bdi_slot);
    memset(b, 0, sizeof *b);
}

static double dot_row(const prw_btf_ubo_factors *f, uint64_t row, uint64_t col)
{
    const double *u = f->u + row * f->components, *s = f->sxv + col * f->components;
    double sum = 0;
    for (uint32_t k = 0; k < f->components; k++) sum += u[k] * s[k];
    return sum;
}

double prw_btf_ubo_raw(const prw_btf_ubo *b, uint32_t c, uint32_t v, uint32_t l, uint32_t x, uint32_t y)
{
    uint64_t lv = (uint64_t)v * b->lights + l, xy = (uint64_t)y * b->width + x;
    switch (b->format) {
    case PRW_BTF_UBO_DFMF: return dot_row(&b->factors[c], lv, xy);
    case PRW_BTF_UBO_FMF: return dot_row(&b->factors[0], lv * b->channels + c, xy);
    case PRW_BTF_UBO_BDI: {
        if (!b->mask[xy]) return 0;
        uint64_t k = 0; /* the stored index of texel xy: the stored texels before it */
        if (b->bdi_slot) k = b->bdi_slot[xy];
        else
            for (uint64_t i = 0; i < xy; i++) k += b->mask[i];
        uint64_t abrdf = (uint64_t)b->views * b->lights * b->channels;
        return prw_btf_half_to_float(b->bdi[k * abrdf + c + (uint64_t)b->channels * lv]);
    }
    }
    return 0;
}

#define DRR_EPS 1e-5

bool prw_btf_ubo_rgb(const prw_btf_ubo *b, uint32_t v, uint32_t l, uint32_t x, uint32_t y, double rgb[3], prw_error *e)
{
    if (b->channels != 3) return prw_fail(e, "btf: %u channels, not RGB", b->channels);
    double a[3];
    for (uint32_t c = 0; c < 3; c++) a[c] = prw_btf_ubo_raw(b, c, v, l, x, y);
    int model = b->format == PRW_BTF_UBO_DFMF ? b->color_model : 0;
    if (b->format == PRW_BTF_UBO_FMF && b->drr)
        for (int c = 0; c < 3; c++) a[c] = exp(a[c]) - DRR_EPS;
    static const double yuv[9] = {1, 0, 1.13983, 1, -0.39465, -0.5806, 1, 2.03211, 0};
    static const double ycocg[9] = {1, 1, -1, 1, 0, 1, 1, -1, -1};
    const double *m = NULL;
    switch (model) {
    case 0: break;
    case 1: m = yuv; break;
    case 3: { /* PCA: row vector times the transform, plus the mean */
        double t[3];
        for (int j = 0; j < 3; j++) {
            t[j] = b->color_mean[j];
            for (int i = 0; i < 3; i++) t[j] += a[i] * b->color_transform[3 * i + j];
        }
        memcpy(a, t, sizeof t);
        break;
    }
    case 4: m = ycocg; break;
    case 9: a[0] = exp(a[0]) - DRR_EPS, m = yuv; break;
    case 10:
        a[0] = exp(a[0]) - DRR_EPS;
        for (int c = 1; c < 3; c++) a[c] = (a[c] > 0 ? 1 : a[c] < 0 ? -1 : 0) * exp(fabs(a[c]) + log(DRR_EPS));
        m = yuv;
        break;
    case 11:
        a[0] = exp(a[0]) - DRR_EPS;
        a[1] *= a[0] + DRR_EPS, a[2] *= a[0] + DRR_EPS;
        m = yuv;
        break;
    case 12:
        for (int c = 0; c < 3; c++) a[c] = exp(a[c]) - DRR_EPS;
        break;
    default: return prw_fail(e, "btf: colour model %d is not supported", model);
    }
    for (int i = 0; i < 3; i++) rgb[i] = m ? m[3 * i] * a[0] + m[3 * i + 1] * a[1] + m[3 * i + 2] * a[2] : a[i];
    return true;
}

float prw_btf_half_to_float(uint16_t h)
{
    uint32_t s = (uint32_t)(h >> 15) << 31, ex = (h >> 10) & 31u, m = h & 1023u, u;
    if (ex == 31) u = s | 0x7f800000u | (m << 13);
    else if (ex) u = s | ((ex + 112u) << 23) | (m << 13);
    else if (!m) u = s;
    else {
        float f = ldexpf((float)m, -24); /* subnormal: exact */
        return s ? -f : f;
    }
    float f;
    memcpy(&f, &u, 4);
    return f;
}

uint16_t prw_btf_float_to_half(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    uint16_t s = (uint16_t)((u >> 16) & 0x8000u);
    uint32_t a = u & 0x7fffffffu;
    if (a >= 0x7f800000u) return (uint16_t)(s | 0x7c00u | (a > 0x7f800000u ? 0x200u : 0)); /* Inf, NaN */
    if (a >= 0x477ff000u) return (uint16_t)(s | 0x7c00u); /* rounds past 65504: Inf */
    if (a < 0x38800000u) { /* below the smallest normal half: subnormal or 0, rounded to nearest even */
        float x = fabsf(f) * 16777216.0f; /* in units of 2^-24, exact */
        float r = nearbyintf(x);          /* the current rounding mode: to nearest even */
        return (uint16_t)(s | (uint16_t)r);
    }
    uint32_t m = a & 0x7fffffu, ex = (a >> 23) - 112u;
    uint32_t h = (ex << 10) | (m >> 13), rest = m & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) h++; /* a carry into the exponent is right */
    return (uint16_t)(s | h);
}

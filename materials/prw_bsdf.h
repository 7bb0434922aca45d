/* prw_bsdf — the CPU side of the one material model (C only): evaluation through the shared scalar
 * header prw_brdf.h, importance sampling and pdfs, for the reference path tracer and the tests.
 *
 * Promises:
 *  - Local shading frame: the normal is +Z; wo points towards the viewer, wi towards the light; both unit.
 *  - prw_bsdf_eval() returns f(wo, wi) in 1/sr per RGB channel (no cosine), exactly prw_brdf_channel()
 *    of prw_brdf.h per channel (through its *_terms forms, the fitted albedos evaluated once), so the
 *    rasterizer and the reference evaluate the same model.
 *  - With clearcoat > 0 the coated model of prw_brdf.h (prw_brdf_coated_channel): a second GGX lobe
 *    around the coat normal coat_n (local frame; all zero = +Z) over the base; clearcoat 0 is the
 *    uncoated model exactly (same code path).
 *  - prw_bsdf_sample() draws wi from a mixture of a cosine-weighted diffuse lobe, GGX visible-normal
 *    sampling of the specular lobe and, with a coat, GGX visible-normal sampling of the coat lobe in
 *    the coat normal's frame (mixture weights from the lobes' estimated albedos); *pdf is the
 *    mixture's solid-angle density, equal to prw_bsdf_pdf(wo, wi).  Returns false (no sample) when the
 *    drawn direction is below the horizon or wo is.
 *  - Each sampler also stands alone (cosine, GGX VNDF) with its pdf, for the chi-square tests.
 *  - prw_bsdf_pdf() is 0 when wo or wi is below the horizon; over the upper hemisphere it integrates
 *    to the fraction of prw_bsdf_sample() draws that succeed.  The multiple-scattering lobe is
 *    sampled through the cosine lobe; lobe probabilities depend on wo only.
 *  - Deterministic: no internal state; u in [0,1)^3 comes from the caller.
 */
#ifndef PRW_BSDF_H
#define PRW_BSDF_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_bsdf {
    double base[3];   /* linear base colour */
    double metallic;  /* [0, 1] */
    double roughness; /* perceptual, alpha = roughness^2 (clamped as in prw_brdf.h) */
    double specular;  /* dielectric F0 scale (1 = F0 0.04) */
    double clearcoat;           /* coat weight in [0, 1] (KHR_materials_clearcoat); 0: no coat */
    double clearcoat_roughness; /* perceptual */
    double coat_n[3];           /* the coat's unit normal in the local frame; all zero: +Z (the shading normal) */
} prw_bsdf;

void prw_bsdf_eval(const prw_bsdf *b, const double wo[3], const double wi[3], double f[3]);
/* The diffuse lobe's part of prw_bsdf_eval (prw_brdf_coated_diffuse_channel), for light-path filters. */
void prw_bsdf_eval_diffuse(const prw_bsdf *b, const double wo[3], const double wi[3], double f[3]);
double prw_bsdf_pdf(const prw_bsdf *b, const double wo[3], const double wi[3]);
bool prw_bsdf_sample(const prw_bsdf *b, const double wo[3], const double u[3], double wi[3], double *pdf);

/* What the model needs at one (material, wo), computed once per shading point by prw_bsdf_lobes_at
 * and passed to the *_at forms, which return exactly (to the bit) what prw_bsdf_eval / _pdf /
 * _sample do with that b and wo: the mixture's lobe probabilities (they depend on wo only) and the
 * fitted albedos of prw_brdf.h that do not depend on wi (the roughness rows of the 2-D fits, the
 * averages and the values at wo), so an evaluation fits only at wi. */
typedef struct prw_bsdf_lobes {
    double ps; /* GGX lobe of the base (else the cosine lobe); 0 without a specular lobe */
    double pc; /* the coat lobe first (0 without a coat) */
    /* private to prw_bsdf.c */
    int fits;  /* 1: the fields below hold the fits (wo above the horizon) */
    int lambert; /* no specular lobe (metallic 0, specular 0, no coat): f = base / pi, fits all zero */
    float ec_row[16], ed_row[16], ec_avg, ed_avg, ec_o, ed_o;         /* base, roughness */
    float cc_row[16], cd_row[16], cc_avg, coat_t_o, cc_o, coat_mo; /* coat, clearcoat roughness */
    float coat_fms, coat_a_o; /* the coat's F_ms and its albedo at wo */
} prw_bsdf_lobes;
prw_bsdf_lobes prw_bsdf_lobes_at(const prw_bsdf *b, const double wo[3]);
void prw_bsdf_eval_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3], double f[3]);
void prw_bsdf_eval_diffuse_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3],
                              double f[3]);
double prw_bsdf_pdf_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3]);
bool prw_bsdf_sample_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double u[3],
                        double wi[3], double *pdf);

/* Lobes on their own. */
void prw_sample_cosine(const double u[2], double wi[3]);
double prw_pdf_cosine(const double wi[3]);
/* Visible-normal sampling of GGX (Heitz 2018): a microfacet normal wm seen from wo. */
void prw_sample_ggx_vndf(const double wo[3], double alpha, const double u[2], double wm[3]);
/* Density of wi = reflect(wo, wm) with wm drawn by prw_sample_ggx_vndf. */
double prw_pdf_ggx_reflect(const double wo[3], const double wi[3], double alpha);

/* A right-handed orthonormal basis (t, b, n) around unit n (Duff et al. 2017): orthonormal to
 * rounding for every n; continuous except across the plane n.z = 0, where the sign branch that
 * removes the singularity at n = (0, 0, -1) flips. */
void prw_frame_from_normal(const double n[3], double t[3], double b[3]);

#ifdef __cplusplus
}
#endif
#endif

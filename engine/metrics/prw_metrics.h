/* prw_metrics — image error metrics between a test image and a reference (DESIGN.md §5).
 *
 * Promises:
 *  - Images are prw_image (linear RGBA float, row 0 at top).  Only R, G, B take part; alpha is
 *    ignored everywhere.  "ref" is always the reference, "test" the image being judged.
 *  - RMSE, relMSE and PSNR are computed on linear RGB as stored (basic.c).
 *  - SSIM and LDR-FLIP are computed on the frozen *metric tone map* (tonemap_metric.c), never on
 *    the user's tone mapping: linear RGB * 1/(1.2 * 2^EV100), clamp to [0,1], sRGB OETF, kept in
 *    float (no 8-bit quantisation).  Its version is PRW_METRIC_TONEMAP_VERSION; any change to it
 *    must bump the version, so figures stay comparable across months.
 *  - HDR-FLIP is computed on linear RGB with its own exposure bracket from the reference.
 *  - Every stage of FLIP is a function that can be tested on its own (flip.c): colour pipeline,
 *    CSF filter, feature detection, distance/redistribution, error pooling.
 *  - Failures are one line in prw_error: "<file or stage>: <place>: <reason>"; nothing here prints.
 */
#ifndef PRW_METRICS_H
#define PRW_METRICS_H

#include "prw_core.h"
#include "prw_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- versions and constants ------------------------------------------------------------- */

/* The frozen metric tone map (see tonemap_metric.c).  Bump on ANY change to its definition. */
#define PRW_METRIC_TONEMAP_VERSION 1
/* Version of the metric implementations as a whole (FLIP/SSIM definitions, pooling, heat map). */
#define PRW_METRICS_VERSION 1

/* relMSE = mean over pixels and R,G,B of (test - ref)^2 / (ref^2 + eps): the relative MSE of the
 * denoising literature (e.g. Rousselle, Knaus, Zwicker 2011, "Adaptive sampling and reconstruction
 * using greedy error minimization"); the denominator uses the reference only; eps = 0.01 is the
 * project's fixed choice (prw issue), kept constant so figures stay comparable. */
#define PRW_RELMSE_EPSILON 0.01

/* FLIP default viewing condition: 0.7 m from a 0.7 m wide 3840-pixel monitor, which the FLIP
 * paper (Andersson et al. 2020, Sec. 4) rounds to 67 pixels per degree. */
#define PRW_FLIP_DEFAULT_PPD 67.0

/* ---- basic.c: RMSE, relMSE, PSNR on linear RGB --------------------------------------------- */

typedef struct prw_basic_metrics {
    double mse;    /* mean over pixels and R,G,B of (test - ref)^2 */
    double rmse;   /* sqrt(mse) */
    double relmse; /* see PRW_RELMSE_EPSILON */
    double peak;   /* the peak PSNR used */
    double psnr;   /* 10 log10(peak^2 / mse) dB; +INFINITY when mse == 0; NaN when peak <= 0 */
} prw_basic_metrics;

/* Largest R, G or B value of the image (alpha ignored); 0 for an all-black image. */
double prw_image_max_rgb(const prw_image *img);
/* Fails on a size mismatch.  peak <= 0 means "the reference's largest R/G/B value". */
bool prw_metrics_basic(const prw_image *test, const prw_image *ref, double peak, prw_basic_metrics *out,
                       prw_error *e);

/* ---- tonemap_metric.c: the frozen metric tone map ---------------------------------------- */

/* Luminance 1.2 * 2^EV100 cd/m^2 maps to 1.0; returns 1 / (1.2 * 2^EV100). */
double prw_metric_tonemap_scale(double ev100);
/* sRGB transfer functions (IEC 61966-2-1); the OETF clamps its input to [0,1] first. */
float prw_srgb_oetf(float linear);
float prw_srgb_eotf(float encoded);
/* out (allocated here, alpha = 1) = OETF(clamp(linear * scale, 0, 1)) per R,G,B. */
bool prw_metric_tonemap(const prw_image *linear, double ev100, prw_image *out, prw_error *e);

/* ---- ssim.c: SSIM (Wang et al. 2004) ------------------------------------------------------ */

#define PRW_SSIM_RADIUS 5 /* 11x11 Gaussian window, sigma 1.5 */
#define PRW_SSIM_SIGMA 1.5
#define PRW_SSIM_K1 0.01
#define PRW_SSIM_K2 0.03

/* Luma of encoded values: Y' = 0.2126 R' + 0.7152 G' + 0.0722 B' (Rec.709 coefficients applied to
 * the sRGB-encoded values).  out has width*height floats. */
void prw_luma709(const prw_image *encoded, float *out);
/* Mean SSIM of two single-channel images with data range 1, over the (w-10)x(h-10) windows that
 * lie inside the image (no padding).  map (optional) receives the (w-10)*(h-10) per-window
 * values, row-major.  Fails when w or h < 11. */
bool prw_ssim_gray(const float *test, const float *ref, int w, int h, double *mean, float *map, prw_error *e);
/* SSIM on the luma of two already metric-tone-mapped (encoded) images. */
bool prw_ssim_encoded(const prw_image *test_enc, const prw_image *ref_enc, double *mean, prw_error *e);

/* ---- flip.c: LDR-FLIP and HDR-FLIP (Andersson et al. 2020, 2021) ---------------------------- */

/* Colour pipeline, one pixel at a time.  rgb is display-linear Rec.709 RGB. */
void prw_flip_linrgb_to_xyz(const float rgb[3], float xyz[3]);
void prw_flip_xyz_to_linrgb(const float xyz[3], float rgb[3]);
void prw_flip_linrgb_to_ycxcz(const float rgb[3], float ycxcz[3]);
void prw_flip_ycxcz_to_linrgb(const float ycxcz[3], float rgb[3]);
void prw_flip_linrgb_to_lab(const float rgb[3], float lab[3]); /* CIELAB, D65 white = RGB(1,1,1) */
void prw_flip_hunt(float lab[3]);                              /* a *= 0.01 L, b *= 0.01 L */
double prw_flip_hyab(const float lab1[3], const float lab2[3]); /* |dL| + sqrt(da^2 + db^2) */
/* cmax = HyAB(Hunt(Lab(green)), Hunt(Lab(blue)))^0.7 */
double prw_flip_color_cmax(void);
/* Colour error of one pixel from two filtered, clamped linear-RGB colours: HyAB of the Hunt-
 * adjusted L*a*b*, raised to 0.7, then redistributed with pc = 0.4, pt = 0.95 to [0,1]. */
double prw_flip_color_error(const float rgb_test[3], const float rgb_ref[3]);
/* The redistribution alone: x = HyAB^0.7 in [0, cmax] -> [0,1]. */
double prw_flip_color_redistribute(double x, double cmax);

/* CSF filters. channel 0 = achromatic (Yy), 1 = red-green (Cx), 2 = blue-yellow (Cz). */
int prw_flip_csf_radius(double ppd);
/* Fills k ((2r+1)^2 values, row-major, normalised to sum 1) and returns r. k may be NULL. */
int prw_flip_csf_kernel(int channel, double ppd, double *k);
/* Filters a w*h*3 interleaved YCxCz image in place (clamp-to-edge borders). */
void prw_flip_csf_filter(float *ycxcz, int w, int h, double ppd);

/* Feature detection on an achromatic image in [0,1] (Y / Yn). */
int prw_flip_feature_radius(double ppd); /* ceil(3 sigma), sigma = 0.5 * 0.082 * ppd */
/* 1-D kernels, 2r+1 values each: gauss sums to 1; edge (first derivative) and point (second
 * derivative) have positive weights summing to 1 and negative ones to -1.  Returns r. */
int prw_flip_feature_kernels(double ppd, double *gauss, double *edge, double *point);
/* edge[i] = |(I*Ex, I*Ey)|, point[i] = |(I*Px, I*Py)| (w*h floats each, clamp-to-edge). */
void prw_flip_features(const float *achromatic, int w, int h, double ppd, float *edge, float *point);
/* ((1/sqrt 2) max(|edge_t - edge_r|, |point_t - point_r|))^0.5 */
double prw_flip_feature_error(double edge_test, double edge_ref, double point_test, double point_ref);
/* dE = dEc^(1 - dEf) */
double prw_flip_combine(double color_error, double feature_error);

/* LDR-FLIP of two display-linear RGB images (values clamped to [0,1] on entry).  map: w*h. */
bool prw_flip_ldr_linear(const prw_image *test, const prw_image *ref, double ppd, float *map, prw_error *e);
/* LDR-FLIP of two sRGB-encoded images (decoded with the sRGB EOTF first). */
bool prw_flip_ldr_encoded(const prw_image *test_enc, const prw_image *ref_enc, double ppd, float *map,
                          prw_error *e);

/* HDR-FLIP tone mapper: the ACES filmic fit of Narkowicz (2015) with its 0.6 input scale, as
 * used by the HDR-FLIP paper: t(x) = (a x^2 + b x) / (c x^2 + d x + f) with a = 0.36*2.51,
 * b = 0.6*0.03, c = 0.36*2.43, d = 0.6*0.59, f = 0.14; clamped to [0,1]. */
#define PRW_HDRFLIP_TONEMAPPER "ACES (Narkowicz 2015 fit, 0.6 input scale)"
double prw_hdrflip_tonemap(double x);
/* x such that t(x) = y (0 < y < t(inf)); the bracket uses y = 0.85. */
double prw_hdrflip_tonemap_inverse(double y);

typedef struct prw_flip_exposures {
    double start, stop; /* exposure compensations in stops: colour * 2^c before tone mapping */
    int count;          /* max(2, ceil(stop - start)) evenly spaced from start to stop */
    double y_max, y_median; /* the reference luminances they came from */
} prw_flip_exposures;

/* HDR-FLIP paper, Sec. 3: start = log2(x85 / Ymax), stop = log2(x85 / Ymedian), with x85 the
 * tone-mapper input mapping to 0.85 and Y = 0.2126 R + 0.7152 G + 0.0722 B of the reference.
 * Median: numpy-style (linear interpolation between order statistics).  Choices of prw (the
 * paper does not cover them): an all-black reference gives start = stop = 0; a median <= 0 is
 * replaced by the median of the positive luminances. */
void prw_hdrflip_exposures(const prw_image *ref, prw_flip_exposures *out);
/* Exposure i of the bracket. */
double prw_hdrflip_exposure(const prw_flip_exposures *x, int i);
/* HDR-FLIP: per-pixel max over the bracket of LDR-FLIP of the tone-mapped images. exposures
 * (optional) receives the bracket. */
bool prw_flip_hdr(const prw_image *test, const prw_image *ref, double ppd, float *map,
                  prw_flip_exposures *exposures, prw_error *e);

/* Pooling of an error map.  Weighted quantiles use a histogram of PRW_FLIP_HIST_BINS equal bins on
 * [0,1] in which each pixel adds its own error value as weight (so larger errors count more, as in
 * the FLIP tool's "weighted" statistics); the weighted q-quantile is where the cumulative weight
 * reaches q * total, interpolated linearly inside the bin.  All-zero maps give 0. */
#define PRW_FLIP_HIST_BINS 1000
typedef struct prw_flip_stats {
    double mean, weighted_median, weighted_q1, weighted_q3, min, max;
} prw_flip_stats;
void prw_flip_pool(const float *map, size_t n, prw_flip_stats *out);

/* ---- heatmap.c: magma heat map --------------------------------------------------------- */

/* Magma colour map (matplotlib's, the FLIP convention) at t in [0,1] (clamped), 8-bit sRGB. */
void prw_magma(double t, uint8_t rgb[3]);
/* Writes the error map (values in [0,1]) as an 8-bit RGB PNG, atomically. */
bool prw_heatmap_write_png(const char *path, const float *map, int w, int h, prw_error *e);

/* ---- compare.c: everything `prw compare` computes ---------------------------------------- */

typedef struct prw_compare_opts {
    double ppd;   /* <= 0: PRW_FLIP_DEFAULT_PPD */
    double ev100; /* exposure of the metric tone map (required) */
    double peak;  /* PSNR peak; <= 0: the reference's largest R/G/B value */
} prw_compare_opts;

typedef struct prw_compare_metrics {
    prw_basic_metrics basic;
    double ssim;
    prw_flip_stats ldr_flip, hdr_flip;
} prw_compare_metrics;

/* Reads an EXR for comparison: NaN/Inf pixels rejected. */
bool prw_compare_load(const char *path, prw_image *out, prw_error *e);

/* What a file holds, from its first bytes (not its name): OpenEXR (linear radiance) or PNG
 * (display values).  Anything else: "<path>: not an OpenEXR or PNG file". */
typedef enum prw_compare_kind {
    PRW_COMPARE_EXR = 1,
    PRW_COMPARE_PNG = 2,
} prw_compare_kind;
bool prw_compare_sniff(const char *path, prw_compare_kind *kind, prw_error *e);
/* Reads a PNG for comparison as its encoded display values: R, G, B = 8-bit code / 255 (16-bit
 * files are scaled to 8 bits), A = 1 (the file's alpha is ignored, as by the FLIP tool).  The
 * values are taken as sRGB-encoded (IEC 61966-2-1), whatever gAMA/iCCP chunks say. */
bool prw_compare_load_png(const char *path, prw_image *encoded, prw_error *e);
/* Every metric of two PNGs (encoded display values, as prw_compare_load_png gives them), as the
 * FLIP tool treats LDR images: LDR-FLIP on the display values decoded with the sRGB EOTF to linear
 * [0,1]; RMSE, relMSE and PSNR (peak: opts->peak, else 1) on those linear display values; SSIM on
 * the luma of the encoded values (as for EXRs, where it runs on the metric tone map's encoded
 * output).  HDR-FLIP is not defined for display values: out->hdr_flip is all NaN.  opts->ev100 is
 * not used.  ldr_map (optional, w*h floats) receives the LDR-FLIP map. */
bool prw_compare_images_ldr(const prw_image *test_enc, const prw_image *ref_enc, const prw_compare_opts *opts,
                            prw_compare_metrics *out, float *ldr_map, prw_error *e);

/* The metric exposure of a reference without a prw:ev100 attribute (another renderer's EXR): the
 * EV100 that maps the reference's log-average luminance to middle grey in the metric tone map,
 *   L_avg = exp(mean over pixels of ln(delta + Y)),  Y = 0.2126 R + 0.7152 G + 0.0722 B,
 *   L_avg / (1.2 * 2^EV100) = 0.18   ->   EV100 = log2(L_avg / (1.2 * 0.18)),
 * (key 0.18 and delta = 1e-6 cd/m^2 as in Reinhard et al. 2002, the scene key of the renderer's
 * tone mappers), rounded to 4 decimals — the printed value, so `--ev100 <printed>` reproduces the
 * figures exactly — and clamped to [-20, 40], the range --ev100 accepts.  *log_avg (optional)
 * receives L_avg.  Negative and non-finite luminances count as 0. */
#define PRW_COMPARE_EV_KEY 0.18
#define PRW_COMPARE_EV_DELTA 1e-6
double prw_compare_derive_ev100(const prw_image *ref, double *log_avg);
/* "prw:ev100" of an EXR.  Returns false with e->msg "" when absent, with a message on errors
 * (unreadable, not a number). */
bool prw_compare_read_ev100(const char *path, double *ev100, prw_error *e);
/* Same size, else "<test_name>: size: WxH differs from <ref_name> WxH". */
bool prw_compare_check_sizes(const prw_image *test, const prw_image *ref, const char *test_name,
                             const char *ref_name, prw_error *e);
/* All metrics of test against ref.  hdr_map (optional, w*h floats) receives the HDR-FLIP map;
 * exposures (optional) the HDR-FLIP bracket. */
bool prw_compare_images(const prw_image *test, const prw_image *ref, const prw_compare_opts *opts,
                        prw_compare_metrics *out, float *hdr_map, prw_flip_exposures *exposures, prw_error *e);

/* Verdicts against the reference noise (the same metric between two references of different
 * seeds): below when error < 2 * noise, with error taken as RMSE, relMSE, 1 - SSIM, FLIP mean.
 * PSNR follows RMSE (same peak): PSNR_err > PSNR_noise - 20 log10 2. */
typedef struct prw_compare_verdicts {
    bool rmse, relmse, psnr, ssim, ldr_flip, hdr_flip; /* true = below reference noise */
} prw_compare_verdicts;
void prw_compare_verdict(const prw_compare_metrics *err, const prw_compare_metrics *noise,
                         prw_compare_verdicts *out);

#ifdef __cplusplus
}
#endif
#endif

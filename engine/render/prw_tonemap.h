/* prw_tonemap — display-aware tone mapping: the plain-C reference of every operator (issue 6).
 * The GPU passes (pass_tonemap.c, shaders/tonemap_*.comp) compute the same functions in float;
 * tests compare them on the display-encoded signal before quantisation.
 *
 * Pipeline per pixel (all operators):
 *   1. input: linear Rec.709 radiance in cd/m^2 (the renderer's HDR image).  NaN and negative
 *      channels read as 0, values above PRW_TM_INPUT_MAX (and +Inf) as PRW_TM_INPUT_MAX.
 *   2. operator -> display-relative RGB r in working primaries, where r = 0 is the display's
 *      L_min = black + reflection and r = 1 its L_max = peak (prw_display.h), so a relative value r
 *      is shown at L_min + r (L_max - L_min) cd/m^2 in total.
 *   3. gamut mapping: r -> display primaries (matrix from chromaticities; grey stays grey), then, if a
 *      channel is outside [0, 1], desaturate towards the grey of the same luminance (r_Y, r_Y, r_Y)
 *      by the largest factor t in [0, 1] that brings every channel inside: luminance and hue (the
 *      line through the white point) are kept, nothing is negative or clipped per channel.
 *   4. encoding: each channel's target luminance through the inverse display model -> signal V.
 *
 * Operators (x = L * exposure is relative scene luminance; x = 1 is the scene's reference white,
 * the luminance 1.2 * 2^EV100 cd/m^2 the camera exposes to white):
 *  - exposure: r = clamp(g x) per channel (the baseline).  g anchors reference white (below).
 *  - reinhard: Reinhard, Stark, Shirley, Ferwerda 2002, "Photographic tone reproduction for digital
 *    images", eqs. 1-4: log-average Lw_bar = exp(mean ln(delta + Lw)) with delta = PRW_TM_LOG_DELTA
 *    cd/m^2 (the guard against log 0), L = a / Lw_bar * Lw (key a, default 0.18),
 *    Ld = L (1 + L / Lwhite^2) / (1 + L), Lwhite default = the image's largest L.  Colour by the
 *    ratio Ld / Lw.  An auto-exposure operator: it ignores the camera's exposure.
 *  - neutral: Khronos PBR Neutral tone mapper (Khronos Group, "PBR Neutral Tone Mapping", 2024:
 *    F90 = 0.04, start of compression 0.8 - 0.04, desaturation 0.15), applied to g * x * rgb.
 *  - adaptive: this project's display-adaptive curve (simpler than Mantiuk, Daly, Kerofsky 2008):
 *    L' = (W / L_ref) L, i.e. scene reference white L_ref = 1 / exposure shown at the display's
 *    reference white W.  Where the display can, L' is shown as is (absolute within the range
 *    [K, W]); below K = min(4 L_min, W / 2) a power toe L_min + (K - L_min) (L'/K)^p with
 *    p = K / (K - L_min) (C1 at K) lifts what would fall under black + reflection; above W, when the
 *    frame's largest L' exceeds L_max, a shoulder in log luminance u = ln(L'/W) in [0, U],
 *    v = a u / (1 + b u) + m u with m = lambda V / U, a = 1 - m, b chosen so v(U) = V = ln(L_max/W)
 *    (C1 at W: v'(0) = 1; monotonic; slope >= m everywhere so highlights never flatten to one
 *    value).  Colour keeps the scene's chromaticity: r_i = r_Y + (Y_t / dL) (rgb_i / L - 1).
 *  - absolute: the predictive mode: scene cd/m^2 shown at the same cd/m^2, clipped to
 *    [L_min, L_max] (chromaticity kept); pixels below L_min, above L_max and needing gamut
 *    mapping are counted (prw_tm_report) and can be painted (overlay: below blue, above red,
 *    out of gamut magenta).
 * Reference-white anchoring (exposure, neutral): g solves f(g) = (W - L_min) / (L_max - L_min)
 * for the operator's grey curve f, so the scene's reference white is shown at W cd/m^2 — 203 on
 * HDR10 (ITU-R BT.2408), the profile's fraction of peak on SDR displays.
 */
#ifndef PRW_TONEMAP_H
#define PRW_TONEMAP_H

#include "prw_core.h"
#include "prw_display.h"
#include "prw_image.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_TM_INPUT_MAX 1e12   /* cd/m^2 */
#define PRW_TM_LOG_DELTA 1e-6   /* cd/m^2, Reinhard's delta */
#define PRW_TM_SHOULDER_LAMBDA 0.5
#define PRW_TM_GAMUT_EPS 1e-6   /* channel excursions smaller than this are rounding, not gamut */

typedef enum prw_tm_op {
    PRW_TM_EXPOSURE = 0,
    PRW_TM_REINHARD = 1,
    PRW_TM_NEUTRAL = 2,
    PRW_TM_ADAPTIVE = 3,
    PRW_TM_ABSOLUTE = 4,
    PRW_TM_OP_COUNT
} prw_tm_op;

/* Per-pixel classification flags. */
enum { PRW_TM_BELOW = 1u, PRW_TM_ABOVE = 2u, PRW_TM_GAMUT = 4u };

typedef struct prw_tonemap_settings {
    prw_tm_op op;
    double key;    /* reinhard: key a; 0 -> 0.18 */
    double white;  /* reinhard: Lwhite in scaled luminance; 0 -> the frame's largest */
    bool overlay;  /* paint classified pixels (any operator; meant for absolute) */
    bool report;   /* count classified pixels every frame (always on for absolute and overlay) */
} prw_tonemap_settings;

/* Host-prepared constants (no image statistics). */
typedef struct prw_tm_params {
    prw_tm_op op;
    prw_eotf eotf;
    bool overlay;
    double exposure;            /* 1 / L_ref */
    double lmin, lmax, dl;      /* display range, dl = lmax - lmin */
    double black, peak, refl;
    double gamma, enc_scale;    /* enc_scale = dl / (peak - black) (srgb/gamma: relative -> V^gamma) */
    double bt_a, bt_b;          /* BT.1886 */
    double white_cd;            /* W, cd/m^2 */
    double gain;                /* exposure, neutral: g */
    double key, white;          /* reinhard */
    double knee, toe_p;         /* adaptive: K, p (K = 0: no toe) */
    double m[9];                /* Rec.709 -> display primaries */
} prw_tm_params;

/* Frame statistics (the stats pass): over all pixels of all views. */
typedef struct prw_tm_stats {
    double log_avg;  /* exp(mean ln(delta + Y)) */
    double max_lum;  /* largest Y */
    uint64_t count;
} prw_tm_stats;

/* Per-frame constants derived from the statistics. */
typedef struct prw_tm_frame {
    double rh_scale, rh_white2;      /* reinhard: a / Lw_bar, Lwhite^2 */
    double sh_on, sh_a, sh_b, sh_m;  /* adaptive shoulder (sh_on = 0: identity above W) */
    double sh_v;                     /* V = ln(L_max / W) */
} prw_tm_frame;

typedef struct prw_tm_report {
    uint64_t pixels, below_black, above_peak, out_of_gamut;
} prw_tm_report;

const char *prw_tm_op_name(prw_tm_op op);
bool prw_tm_op_parse(const char *name, prw_tm_op *out, prw_error *e);
/* "exposure, reinhard, neutral, adaptive, absolute" */
const char *prw_tm_op_list(void);

void prw_tm_prepare(const prw_tonemap_settings *s, const prw_display *d, double exposure, prw_tm_params *out);
/* Sanitised luminance of one input pixel (step 1). */
double prw_tm_input_lum(const float rgb[3]);
void prw_tm_stats_image(const prw_image *hdr, prw_tm_stats *out);
void prw_tm_derive(const prw_tm_params *p, const prw_tm_stats *st, prw_tm_frame *out);
/* One pixel: input cd/m^2 -> signal V (RGB); returns PRW_TM_* flags. */
unsigned prw_tm_pixel(const prw_tm_params *p, const prw_tm_frame *f, const float rgb[3], double v[3]);
/* Whole image: stats (from this image unless `stats` is given) -> derive -> pixels.  out gets V in
 * RGB, A = 1; rep (may be NULL) the counts. */
bool prw_tm_apply(const prw_tm_params *p, const prw_tm_stats *stats, const prw_image *hdr, prw_image *out,
                  prw_tm_report *rep, prw_error *e);

/* Pieces exposed for tests. */
void prw_tm_pbr_neutral(const double in[3], double out[3]);
/* Grey curve of an operator: relative scene luminance x -> relative display r (exposure, neutral,
 * adaptive with the given frame; reinhard: x is scaled luminance L). */
double prw_tm_grey(const prw_tm_params *p, const prw_tm_frame *f, double x);
/* Relative r (display primaries, in [0,1]) -> signal V through the inverse display model. */
double prw_tm_encode(const prw_tm_params *p, double r);

#ifdef __cplusplus
}
#endif
#endif

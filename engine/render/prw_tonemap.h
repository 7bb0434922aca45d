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
 *    Ld = L (1 + L / Lwhite^2) / (1 + L), Lwhite default = PRW_TM_WHITE_HEADROOM x the image's
 *    largest L (so the largest pixel lands just below peak, not on it).  Colour by the
 *    ratio Ld / Lw.  An auto-exposure operator: it ignores the camera's exposure.
 *  - neutral: Khronos PBR Neutral tone mapper (Khronos Group, "PBR Neutral Tone Mapping", 2024:
 *    F90 = 0.04, start of compression 0.8 - 0.04, desaturation 0.15), applied to g * x * rgb.
 *  - adaptive: this project's display-adaptive curve (simpler than Mantiuk, Daly, Kerofsky 2008):
 *    L' = (W / L_ref) L, i.e. scene reference white L_ref = 1 / exposure shown at the display's
 *    reference white W.  Where the display can, L' is shown as is (absolute within the range
 *    [K, W]); below K = min(4 L_min, W / 2) a power toe L_min + (K - L_min) (L'/K)^p with
 *    p = K / (K - L_min) (C1 at K) lifts what would fall under black + reflection; above W, when the
 *    frame's largest L' exceeds L_max, a shoulder in log luminance u = ln(L'/W) in [0, U],
 *    v = a u / (1 + b u) + m u with m = lambda V / U, a = 1 - m, b chosen so v(U) = V = ln(L_max/W),
 *    U = ln(PRW_TM_WHITE_HEADROOM x the largest L' / W) (the largest pixel just below peak)
 *    (C1 at W: v'(0) = 1; monotonic; slope >= m everywhere so highlights never flatten to one
 *    value).  Colour keeps the scene's chromaticity: r_i = r_Y + (Y_t / dL) (rgb_i / L - 1).
 *  - absolute: the predictive mode: scene cd/m^2 shown at the same cd/m^2, clipped to
 *    [L_min, L_max] (chromaticity kept); pixels below L_min, above L_max and needing gamut
 *    mapping are counted (prw_tm_report) and can be painted (overlay: below blue, above red,
 *    out of gamut magenta).
 *  - local: Reinhard, Stark, Shirley, Ferwerda 2002, section 3 ("automatic dodging-and-burning"),
 *    eqs. 5-9, on the scaled luminance L = a / Lw_bar * Lw of eq. 2 (same key and log-average as
 *    reinhard).  Centre-surround at scales s_i = 1.6^i pixels, i = 0..PRW_TM_LOCAL_SCALES-1:
 *    V_1(s_i) = L (x) R(alpha_1 s_i), V_2(s_i) = L (x) R(alpha_2 s_i) with the Gaussians of eq. 5,
 *    R(x, y, alpha s) ~ exp(-(x^2 + y^2) / (alpha s)^2), alpha_1 = 1 / (2 sqrt 2), alpha_2 = 1.6 alpha_1
 *    (so V_2(s_i) = V_1(s_{i+1}): 9 blur levels serve 8 scales).  Discretisation (ours): a separable
 *    kernel sampled at integer offsets |k| <= ceil(3 sigma), sigma = alpha s / sqrt 2, normalised to
 *    sum 1, clamp-to-edge.  Eq. 7: V(s) = (V_1 - V_2) / (2^phi a / s^2 + V_1), phi = 8; eq. 8: s_m is
 *    the largest scale reached from s_0 upwards while |V(s)| < eps = 0.05 (s_0 when already
 *    |V(s_0)| >= eps); eq. 9: Ld = L / (1 + V_1(s_m)), clamped to 1.  Colour by Ld / Lw.
 *  - selective: the selective framework of Michael's thesis (ch. 4.4; notes seed-002-michael.md §3).
 *    Tiles of T x T pixels (T = sel_tile, default 16) are marked important when the largest Sobel
 *    gradient magnitude of log10(delta + Y) inside them, |(Gx, Gy)| / 8 in log10 units per pixel
 *    (3 x 3 Sobel, clamp-to-edge, delta = PRW_TM_LOG_DELTA), exceeds sel_threshold (default 0.1).
 *    The local operator's Ld_loc is blended with the global curve Ld_glob = L / (1 + L) (Reinhard
 *    eq. 3, the limit of eq. 9 where the surround equals the centre) by a weight
 *    w = smoothstep(1 - d / T), d = the Euclidean distance from the pixel centre to the nearest
 *    marked tile: w = 1 on marked tiles, falling to 0 across the neighbouring tile, so there is no
 *    seam; the local operator only runs on marked tiles and their 8 neighbours (w > 0 only there).
 *    Ld = w Ld_loc + (1 - w) Ld_glob.  Colour by Ld / Lw.
 *    A single pixel (prw_tm_pixel) has no neighbourhood: for local and selective it gets Ld_glob.
 * Temporal adaptation (optional, settings.adapt): the adapted luminance La (cd/m^2) follows the
 * frame's log-average luminance T (the statistics over all views of the frame) exponentially,
 * La <- T + (La - T) exp(-dt / tau), tau = tau_bright when T > La, else tau_dark, dt the frame time
 * (so a step in T is followed by 1 - 1/e of it after tau, exactly, whatever the frame rate).
 * La then replaces the frame's log-average (reinhard, local, selective) and sets the exposure of the
 * others to key / La (auto exposure: exposure, neutral, adaptive); absolute ignores it.  In the
 * renderer the frame uses La updated with the previous frame's T (one frame of latency); the first
 * frame uses its own statistics.
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
/* reinhard's default Lwhite and adaptive's shoulder end sit this factor above the frame's largest
 * value: a flat brightest region (a window, a lamp) is shown just below peak, not piled on it
 * (issue 6 must-show 2a: < 0.5 % of pixels at peak).  Mirrored in shaders/tonemap_common.glsl. */
#define PRW_TM_WHITE_HEADROOM 1.05
#define PRW_TM_GAMUT_EPS 1e-6   /* channel excursions smaller than this are rounding, not gamut */
#define PRW_TM_LOCAL_SCALES 8   /* local: scales s_0..s_7 (9 blur levels) */
#define PRW_TM_LOCAL_PHI 8.0
#define PRW_TM_LOCAL_EPS 0.05
#define PRW_TM_SEL_THRESHOLD 0.1 /* selective: default Sobel threshold, log10 units per pixel */
#define PRW_TM_SEL_TILE 16       /* selective: default tile size, pixels (a multiple of 16, <= 256) */
#define PRW_TM_TAU_BRIGHT 0.4    /* s: adaptation to a brighter scene (fast) */
#define PRW_TM_TAU_DARK 4.0      /* s: adaptation to a darker scene (slow) */

typedef enum prw_tm_op {
    PRW_TM_EXPOSURE = 0,
    PRW_TM_REINHARD = 1,
    PRW_TM_NEUTRAL = 2,
    PRW_TM_ADAPTIVE = 3,
    PRW_TM_ABSOLUTE = 4,
    PRW_TM_LOCAL = 5,
    PRW_TM_SELECTIVE = 6,
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
    double sel_threshold; /* selective: Sobel threshold, log10 units per pixel; 0 -> PRW_TM_SEL_THRESHOLD */
    uint32_t sel_tile;    /* selective: tile size, a multiple of 16 up to 256; 0 -> PRW_TM_SEL_TILE */
    bool adapt;           /* temporal adaptation (renderer: one state for all views of a frame) */
    bool local_tiled;     /* GPU local: the tiled kernel of selective on every 16 x 16 block instead of
                           * the separable full-image passes (same result; a benchmark baseline) */
    double tau_bright, tau_dark; /* adaptation time constants, s; 0 -> PRW_TM_TAU_BRIGHT / _DARK */
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
    double sel_threshold;       /* selective */
    int sel_tile;
    double adapt_la;            /* adapted luminance, cd/m^2; 0: off (prw_tm_set_adaptation) */
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
    /* selective: tiles of the last view, marked ones, 16 x 16 blocks the local operator ran on */
    uint64_t tiles, tiles_marked, blocks, blocks_local;
} prw_tm_report;

const char *prw_tm_op_name(prw_tm_op op);
bool prw_tm_op_parse(const char *name, prw_tm_op *out, prw_error *e);
/* "exposure, reinhard, neutral, adaptive, absolute, local, selective" */
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

/* ---- local and selective operators (pieces, also used by prw_tm_apply) ---- */
/* Blur level j (0..PRW_TM_LOCAL_SCALES): sigma = alpha_1 1.6^j / sqrt 2 pixels, radius ceil(3 sigma). */
double prw_tm_local_sigma(int level);
int prw_tm_local_radius(int level);
/* Local operator on a w x h field of scaled luminance L: ld[i] = Ld (eq. 9, before clamping).
 * margin (may be NULL) gets per pixel the smallest ||V(s)| - eps| over the scale decisions taken
 * (tests skip pixels whose scale choice float rounding could flip). */
bool prw_tm_local_ld(const double *L, int w, int h, double key, double *ld, double *margin, prw_error *e);
/* Selective classification of an HDR image: marks[ty * tx_count + tx] = 1 for important tiles
 * (tx_count = ceil(w / tile)); grad (may be NULL) gets each tile's largest gradient.  Returns the
 * number of marked tiles. */
int prw_tm_classify(const prw_image *hdr, int tile, double threshold, uint8_t *marks, double *grad);
/* Blend weight of pixel (x, y) for the marks of a w x h image (see "selective" above). */
double prw_tm_sel_weight(const uint8_t *marks, int w, int h, int tile, int x, int y);
/* Seam measures over the pixel pairs (a, b) straddling a tile border (b.x % tile == 0 or
 * b.y % tile == 0), largest over pairs and RGB channels:
 *  - border gradient: |img(b) - img(a)|;
 *  - border jump: |img(b) - img(a)| - max(|img(a) - img(a')|, |img(b') - img(b)|), where a' and b'
 *    continue the line outwards: how much the step across the border exceeds its neighbouring steps
 *    (a seam is a step there that the neighbourhood does not have). */
double prw_tm_border_gradient(const prw_image *img, int tile);
double prw_tm_border_jump(const prw_image *img, int tile);
/* One pixel of a luminance-ratio operator: target display-relative luminance ld -> signal V
 * (gamut mapping and encoding as every operator); returns PRW_TM_* flags. */
unsigned prw_tm_pixel_ratio(const prw_tm_params *p, const float rgb[3], double ld, double v[3]);

/* Procedural HDR still (tests, prw tmbench): a w x h smooth coloured luminance field whose log10 Y
 * spans exactly `dr` decades around a geometric mean of 50 cd/m^2.  Returns the exposure a meter
 * would pick (key 0.18 / log-average); 0 (and an empty image) when out of memory. */
double prw_tm_field(prw_image *img, int w, int h, double dr, unsigned seed);

/* ---- temporal adaptation ---- */
/* One step of duration dt (s) towards target T; tau from the direction (see above). */
double prw_tm_adapt_step(double la, double target, double dt, double tau_bright, double tau_dark);
/* Uses la (> 0) as the adapted luminance in p (see above); la <= 0 turns adaptation off. */
void prw_tm_set_adaptation(prw_tm_params *p, double la);

/* ---- output files ---- */
/* Chromaticities of the display's primaries and D65: {rx, ry, gx, gy, bx, by, wx, wy}. */
void prw_tm_display_chroma(const prw_display *d, float chroma[8]);
/* Linear display-referred light: per channel the total displayed cd/m^2 (display model, in the
 * display's primaries) of a signal image; for EXR output with prw_tm_display_chroma. */
bool prw_tm_display_light(const prw_display *d, const prw_image *signal, prw_image *out, prw_error *e);
/* CTA-861.3 light levels of a PQ signal image: MaxCLL = largest max(R, G, B) in cd/m^2, MaxFALL =
 * the frame average of max(R, G, B). */
void prw_tm_light_levels(const prw_image *signal, double *max_cll, double *max_fall);
/* HDR10 file: 16-bit RGB PNG of the PQ signal (Rec.2020 primaries) with a cICP chunk (9, 16, 0, 1)
 * before IDAT, and the sidecar "<path>.json" with MaxCLL / MaxFALL.  Fails unless the display is
 * PQ Rec.2020.  Both files or none. */
bool prw_tm_write_hdr10_png(const char *path, const prw_display *d, const prw_image *signal, prw_error *e);

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

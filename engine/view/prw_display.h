/* prw_display — display profiles: what a display does with the signal it is sent (issue 6).
 *
 * The display model (Mantiuk, Daly and Kerofsky 2008, "Display adaptive tone mapping", eq. 1 and §3):
 *     L_d(V) = (L_peak - L_black) * V^gamma + L_black + (k / pi) * E_amb
 * with V the signal in [0, 1], L_peak the peak the panel emits (excluding the reflection term),
 * L_black its black level, k the screen reflectivity and E_amb the ambient illuminance in lux.  Here
 * V^gamma generalises to the profile's EOTF, normalised to [0, 1]:
 *  - gamma:  V^gamma;
 *  - srgb:   the IEC 61966-2-1 piecewise curve (linear segment below V = 0.04045);
 *  - bt1886: ITU-R BT.1886 Annex 1, L = a * max(V + b, 0)^gamma with a, b from L_peak and L_black
 *            (its black is built in, so L_d = L_bt1886(V) + reflection);
 *  - pq:     SMPTE ST 2084 (absolute: V encodes cd/m^2 up to 10000); the panel shows
 *            clamp(PQ(V), L_black, L_peak), so L_d = clamp(PQ(V), L_black, L_peak) + reflection.
 * The range every operator targets is [L_min, L_max] = [L_black + (k/pi) E_amb, L_peak] in total
 * displayed luminance: black plus reflected light at the bottom, the panel's peak at the top (the
 * reflection term is not added to the top, so no pixel is ever shown above L_peak).
 *
 * Colour: each channel follows the model in luminance-equivalent units (R = G = B = 1 is the
 * display's D65 white).  Primaries are Rec.709, Display P3 or Rec.2020 (D65); the matrices are
 * computed from the chromaticities (SMPTE RP 177 normalised primary matrix).
 *
 * Profiles are small JSON files (assets/displays/NAME.json, format below); the five in assets/ are also
 * built in by name, plus "srgb" (an ideal 80 cd/m^2 sRGB display with no black or reflection and
 * reference white at peak: with the exposure operator it reproduces the provisional tone map).
 *
 *   { "prw_display": 1, "name": "default-lcd", "description": "...",
 *     "eotf": "gamma" | "srgb" | "bt1886" | "pq", "gamma": 2.2,        (gamma: not for pq)
 *     "peak": 200, "black": 0.8, "reflectivity": 0.01, "ambient": 60,  (cd/m^2, cd/m^2, 1, lux)
 *     "primaries": "rec709" | "p3" | "rec2020",
 *     "reference_white_fraction": 0.8  |  "reference_white": 203,       (exactly one)
 *     "pixels_per_degree": 40, "bits": 8, "hmd": false }              (optional)
 * Errors are one line "<file>:<line>:<col>: <reason>" (syntax) or "<file>:<key>: <reason>".
 */
#ifndef PRW_DISPLAY_H
#define PRW_DISPLAY_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_eotf {
    PRW_EOTF_SRGB = 0,
    PRW_EOTF_GAMMA = 1,
    PRW_EOTF_BT1886 = 2,
    PRW_EOTF_PQ = 3,
} prw_eotf;

typedef enum prw_primaries {
    PRW_PRIMARIES_REC709 = 0,
    PRW_PRIMARIES_P3 = 1,
    PRW_PRIMARIES_REC2020 = 2,
} prw_primaries;

typedef struct prw_display {
    char name[64];
    prw_eotf eotf;
    prw_primaries primaries;
    double gamma;         /* gamma / bt1886 exponent; sRGB: 2.4 of the piecewise curve (informative) */
    double peak;          /* L_peak, cd/m^2, emitted (no reflection) */
    double black;         /* L_black, cd/m^2 */
    double reflectivity;  /* k */
    double ambient;       /* E_amb, lux */
    double ref_white;     /* cd/m^2 the scene's reference white is shown at (HDR: 203; SDR: fraction * peak) */
    double ppd;           /* pixels per degree (0 = unknown) */
    uint32_t bits;        /* signal bits per channel of the output file (8, 10, 12 or 16) */
    bool hmd;
} prw_display;

/* PQ (SMPTE ST 2084) constants, exactly as the standard gives them. */
#define PRW_PQ_M1 (2610.0 / 16384.0)
#define PRW_PQ_M2 (2523.0 / 32.0)
#define PRW_PQ_C1 (3424.0 / 4096.0)
#define PRW_PQ_C2 (2413.0 / 128.0)
#define PRW_PQ_C3 (2392.0 / 128.0)

/* PQ EOTF: signal E in [0, 1] -> cd/m^2 in [0, 10000]; inverse: cd/m^2 -> E (both clamp). */
double prw_pq_eotf(double e);
double prw_pq_inverse(double cd_m2);
/* sRGB piecewise (IEC 61966-2-1): decode V -> linear, encode linear -> V, on [0, 1]. */
double prw_srgb_decode(double v);
double prw_srgb_encode(double x);

/* Reflected ambient light (k / pi) * E_amb in cd/m^2. */
double prw_display_reflection(const prw_display *d);
/* The target range [L_min, L_max] in total displayed cd/m^2 (see above). */
double prw_display_min(const prw_display *d);
double prw_display_max(const prw_display *d);
/* Total displayed luminance (cd/m^2) of one channel for signal V (the display model). */
double prw_display_luminance(const prw_display *d, double v);
/* The inverse: the signal V giving total displayed luminance L, clamped into [L_min, L_max]
 * (so V is always in the display's valid signal range). */
double prw_display_signal(const prw_display *d, double cd_m2);
/* BT.1886 a and b for this display (eq. in Annex 1); other EOTFs: a = b = 0. */
void prw_display_bt1886(const prw_display *d, double *a, double *b);

/* 3x3 row-major matrices (double). */
void prw_primaries_to_xyz(prw_primaries p, double m[9]);
/* Linear Rec.709 (working primaries) -> linear display primaries; identity for Rec.709. */
void prw_display_matrix(const prw_display *d, double m[9]);

const char *prw_eotf_name(prw_eotf e);
const char *prw_primaries_name(prw_primaries p);

/* Checks the tuple (finite, positive peak > black >= 0, gamma in [1, 4], ...). */
bool prw_display_validate(const prw_display *d, const char *who, prw_error *e);

/* Built-in profiles: "srgb", "office-lcd", "default-lcd", "bright-lcd", "hdr10-1000", "hmd-lcd". */
bool prw_display_builtin(const char *name, prw_display *out);
/* Names of the built-in profiles (NULL-terminated). */
const char *const *prw_display_builtin_names(void);

/* Parses a profile from JSON text; `file` names it in errors. */
bool prw_display_parse(const char *text, size_t size, const char *file, prw_display *out, prw_error *e);
bool prw_display_load(const char *path, prw_display *out, prw_error *e);
/* A built-in name, else a path to a .json profile. */
bool prw_display_resolve(const char *name_or_path, prw_display *out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif

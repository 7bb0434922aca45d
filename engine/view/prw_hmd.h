/* prw_hmd — HMD profiles, the lens model and the side-by-side panel composition (C reference).
 *
 * Geometry.  The panel (both eyes side by side) is screen_width x screen_height metres with
 * panel_width x panel_height pixels; eye 0 (left) owns the left half.  Lens centres sit
 * lens_separation apart, symmetric about the panel centre, at mid-height.  Lens-centred normalised
 * coordinates p are panel metres from the eye's lens centre divided by R = screen_width / 4 (half of
 * one eye's half-panel width: the Oculus SDK 0.2 "ScaleIn" convention), y up.
 *
 * Lens model (radial polynomial, Oculus SDK 0.2 convention):
 *     D(r) = 1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8,    q = p D(|p|)
 * q is the undistorted position in the same units; the eye sees panel point p along the view
 * tangent t = q R / eye_to_screen (eye_to_screen: metres of panel per unit tangent at the lens
 * centre, the SDK's "MetersPerTanAngleAtCenter").  Chromatic aberration: channel c is seen at
 * q_c = q s_c(r) with s_red = ca0 + ca1 r^2, s_green = 1, s_blue = ca2 + ca3 r^2 (r of the panel point).
 * prw_lens_forward is p -> q_c; prw_lens_inverse its numerical inverse (Newton on the radius,
 * double).  Profiles are accepted only when every channel's r D(r) s_c(r) increases strictly up
 * to 1.1 x the panel-corner radius, so the inverse is unique there.
 *
 * Pre-distortion: panel pixel centre p of eye k shows, in channel c, the eye image at tangent
 * q_c R / eye_to_screen (bilinear, pixel centres at i + 0.5, black outside the eye image).  Viewed
 * through the lens this reproduces the eye image (barrel pre-distortion + per-channel
 * chromatic-aberration pre-correction).  The eye FOV (XrFovf style) reaches the panel-half's edge
 * midpoints in every channel; eye-buffer size: eye_buffer_scale eye pixels per panel pixel at the
 * lens centre (1 = matched there, the SDK's convention).
 *
 * Side-by-side debug view: each half shows its eye image scaled to the half, no distortion.
 *
 * Profile JSON (assets/hmd/NAME.json; "dk2" is also built in):
 *   { "prw_hmd": 1, "name": "dk2", "description": "...",
 *     "panel": [1920, 1080], "screen_size_m": [0.12576, 0.07074], "eye_to_screen_m": 0.036,
 *     "lens_separation_m": 0.0635, "ipd_m": 0.064, "distortion_k": [k1, k2, k3, k4],
 *     "chromatic": [ca0, ca1, ca2, ca3], "eye_buffer_scale": 1.0, "peak_luminance": 100 }
 * Errors are one line "<file>:<line>:<col>: <reason>" (syntax) or "<file>:<key>: <reason>".
 */
#ifndef PRW_HMD_H
#define PRW_HMD_H

#include "prw_core.h"
#include "prw_stereo.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_hmd {
    char name[64];
    uint32_t panel_width, panel_height; /* pixels, both eyes */
    double screen_width, screen_height; /* metres, whole panel */
    double eye_to_screen;               /* metres of panel per unit tangent at the lens centre */
    double lens_separation;             /* metres between the lens centres */
    double ipd;                         /* metres, eye separation used for rendering */
    double k[4];                        /* k1..k4 */
    double ca[4];                       /* red: ca0 + ca1 r^2; blue: ca2 + ca3 r^2 */
    double eye_buffer_scale;            /* eye pixels per panel pixel at the lens centre */
    double peak_luminance;              /* cd/m^2, for the tone mapper */
} prw_hmd;

bool prw_hmd_parse(const char *text, size_t size, const char *file, prw_hmd *out, prw_error *e);
bool prw_hmd_load(const char *path, prw_hmd *out, prw_error *e);
/* A built-in name ("dk2") or a .json path. */
bool prw_hmd_resolve(const char *name_or_path, prw_hmd *out, prw_error *e);
bool prw_hmd_builtin(const char *name, prw_hmd *out);
/* Range and monotonicity checks (also run by parse); file names the profile in messages. */
bool prw_hmd_validate(const prw_hmd *h, const char *file, prw_error *e);

/* ---- lens model ---- */
double prw_lens_radius_scale(const prw_hmd *h, int channel, double r2); /* D(r) s_c(r), r2 = r^2 */
void prw_lens_forward(const prw_hmd *h, int channel, double px, double py, double *qx, double *qy);
/* Inverse of prw_lens_forward; false when q is beyond the checked range (1.1 x corner radius). */
bool prw_lens_inverse(const prw_hmd *h, int channel, double qx, double qy, double *px, double *py);
double prw_hmd_lens_unit(const prw_hmd *h);        /* R in metres */
double prw_hmd_corner_radius(const prw_hmd *h);    /* largest normalised panel radius of an eye half */
double prw_hmd_lens_circle(const prw_hmd *h);      /* normalised radius of the largest circle about the lens
                                                      centre inside the eye's panel half */
double prw_hmd_lens_centre_x(const prw_hmd *h, int eye); /* metres from the panel centre, right positive */

/* Eye FOV and eye-buffer size for a panel of panel_w x panel_h pixels (0: the profile's). */
void prw_hmd_eye_fov(const prw_hmd *h, int eye, prw_fov *out);
void prw_hmd_eye_size(const prw_hmd *h, uint32_t panel_w, uint32_t panel_h, uint32_t *w, uint32_t *h_out);

/* ---- composition (C reference of the GPU pass) ---- */
typedef enum prw_compose_mode {
    PRW_COMPOSE_SIDE_BY_SIDE = 0, /* debug view: each eye scaled to its half, no distortion */
    PRW_COMPOSE_HMD = 1,          /* barrel pre-distortion + chromatic pre-correction */
} prw_compose_mode;

typedef struct prw_compose_params {
    prw_compose_mode mode;
    uint32_t out_w, out_h, eye_w, eye_h;
    double screen_w, screen_h, lens_unit, eye_to_screen;
    double lens_x[2];     /* lens centres, metres from the panel centre */
    double k[4], ca[4];
    double tan[2][4];     /* per eye: left, right, bottom, top */
} prw_compose_params;

/* HMD composition for eyes rendered with prw_hmd_eye_fov (tangents taken from views). */
void prw_compose_params_hmd(const prw_hmd *h, const prw_view eyes[2], uint32_t out_w, uint32_t out_h,
                            prw_compose_params *out);
void prw_compose_params_sbs(uint32_t eye_w, uint32_t eye_h, uint32_t out_w, uint32_t out_h, prw_compose_params *out);
/* Eye-image position (pixels, corner convention) panel pixel (i, j)'s centre samples in channel c;
 * eye receives the eye index. */
void prw_compose_source(const prw_compose_params *p, uint32_t i, uint32_t j, int channel, int *eye, double *u,
                        double *v);
/* Bilinear sample of channel c of an RGBA float image at (u, v) (pixel centres at +0.5; clamped to
 * the edge inside the image, 0 outside [0, w] x [0, h]). */
double prw_compose_sample(const float *rgba, uint32_t w, uint32_t h, int channel, double u, double v);
/* out (out_w * out_h RGBA, alpha 1) from the two eye images (eye_w * eye_h RGBA each). */
void prw_compose_cpu(const prw_compose_params *p, const float *left, const float *right, float *out);

/* ---- a stereo frame's setup: eyes, eye-image size, composition ---- */
typedef struct prw_stereo_setup {
    prw_view eyes[2];             /* left, right */
    uint32_t eye_w, eye_h;        /* per eye */
    prw_compose_params compose;   /* to the composed image (out_w x out_h) */
} prw_stereo_setup;

/* Desktop: off-axis eyes of the centre view (its size per eye); composed = side-by-side 2W x H. */
bool prw_stereo_setup_desktop(const prw_view *centre, double ipd, double screen_distance, prw_stereo_setup *out,
                              prw_error *e);
/* HMD: pose, exposure and znear from centre; eyes from the profile's FOVs and IPD, eye size from the
 * panel (panel_w x panel_h, 0 = the profile's) and eye-buffer scale; composed = pre-distorted panel. */
bool prw_stereo_setup_hmd(const prw_view *centre, const prw_hmd *h, uint32_t panel_w, uint32_t panel_h,
                          prw_stereo_setup *out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif

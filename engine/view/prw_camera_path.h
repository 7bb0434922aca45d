/* prw_camera_path — scripted camera paths: load, save, record, interpolate, play back.
 *
 * File format (JSON, version 1; see assets/paths/ for examples):
 *   {"prw_camera_path": 1, "fps": 30,
 *    "keyframes": [{"t": 0.0, "position": [x, y, z],
 *                   "orientation": [x, y, z, w]  |  "look_at": [x, y, z] (+ "up": [x, y, z], default +Y),
 *                   "yfov_deg": 60, "ipd_m": 0.063}, ...]}
 *   - "fps" optional (default 30, range (0, 1000]); "yfov_deg" (0, 180) and "ipd_m" [0, 0.2] are
 *     optional per keyframe: absent means the previous keyframe's value (first keyframe: 60 deg,
 *     0.063 m).  Coordinates |x| <= 1e9 m, times |t| <= 1e9 s, >= 2 keyframes, times strictly
 *     increasing by at least PRW_CAMERA_PATH_MIN_DT.  Orientation quaternions must be unit within
 *     1e-3 (they are renormalised).  Unknown and duplicate keys are errors.
 *   - Errors are one line "<file>:<place>: <reason>", place = line:col (syntax) or a JSON path
 *     (keyframes[2].look_at).
 *   - The camera looks down its local -Z with +Y up (glTF); `orientation` rotates camera-local
 *     axes into world axes.
 *
 * Interpolation (t in seconds, all in double):
 *   - Position: one cubic Hermite in TIME per segment [t_i, t_i+1], through the keyframe positions
 *     with velocities v_i shared by both segments meeting at key i, so the path is exact at keyframes
 *     and C1 in time by construction.  Interior v_i = (dP/du)(u_i) * (du/dt)_i where dP/du is the
 *     derivative at P_i of the centripetal (alpha = 0.5) Catmull-Rom curve through P_i-1, P_i, P_i+1
 *     (Barry-Goldman; knots u_j+1 - u_j = |P_j+1 - P_j|^0.5) and (du/dt)_i is the mean of the two
 *     adjacent segments' rates (u_i - u_i-1)/(t_i - t_i-1) and (u_i+1 - u_i)/(t_i+1 - t_i); this
 *     choice reproduces constant-speed straight-line motion exactly for any keyframe spacing.  A
 *     keyframe next to a zero-length segment gets v_i = 0 (the limit of the formula).
 *     End keyframes: natural end condition (zero acceleration at the first and last keyframe):
 *     v_0 = (3 (P_1 - P_0) / (t_1 - t_0) - v_1) / 2, and likewise at the end; two keyframes give a
 *     straight line at constant speed.
 *   - Orientation: squad (Shoemake's spherical quadrangle) over hemisphere-consistent unit
 *     quaternions (each stored keyframe is flipped into its predecessor's hemisphere when it is
 *     added), renormalised.  The intermediate quaternions are time-aware: at interior key i the
 *     log-space angular tangent is T_i = (L+ - L-) / (t_i+1 - t_i-1) with L+ = log(q_i^-1 q_i+1),
 *     L- = log(q_i^-1 q_i-1), and each side gets its own intermediate
 *     s_i+ = q_i exp((T_i (t_i+1 - t_i) - L+) / 2),  s_i- = q_i exp(-(L- + T_i (t_i - t_i-1)) / 2),
 *     which makes the angular velocity continuous in time; with uniform spacing both equal
 *     Shoemake's s_i = q_i exp(-(L+ + L-) / 4).  End keys use s = q (so two keyframes give slerp).
 *   - yfov and ipd: linear in time.
 *   - Outside [t_first, t_last] the pose holds at the end keyframe (velocity 0).
 *
 * Playback: frame k (0 <= k < frame count) is at t_k = min(t_first + k / fps, t_last), independent
 * of render speed; frame count = floor((t_last - t_first) * fps + 1e-9) + 1.
 */
#ifndef PRW_CAMERA_PATH_H
#define PRW_CAMERA_PATH_H

#include "prw_core.h"
#include "prw_math.h"
#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_CAMERA_PATH_VERSION 1
#define PRW_CAMERA_PATH_MIN_DT 1e-6        /* seconds between keyframes, at least */
#define PRW_CAMERA_PATH_MAX_KEYS 1000000u
#define PRW_CAMERA_PATH_DEFAULT_FPS 30.0
#define PRW_CAMERA_PATH_DEFAULT_YFOV_DEG 60.0
#define PRW_CAMERA_PATH_DEFAULT_IPD_M 0.063

typedef struct prw_camera_keyframe {
    double t;              /* seconds */
    prw_dvec3 position;    /* metres, world */
    prw_dquat orientation; /* unit; camera-local -> world; camera looks down local -Z, +Y up */
    double yfov_deg;       /* vertical field of view, degrees, (0, 180) */
    double ipd_m;          /* eye separation for stereo, metres, [0, 0.2] */
} prw_camera_keyframe;

/* Owns its keyframes.  Zero-initialised ({0}) is a valid empty path; fps 0 means the default. */
typedef struct prw_camera_path {
    prw_camera_keyframe *keys;
    uint32_t count, capacity;
    double fps;
} prw_camera_path;

/* The interpolated camera at one time. */
typedef struct prw_camera_sample {
    double t;
    prw_dvec3 position;
    prw_dvec3 velocity;    /* dP/dt, m/s (the right-hand limit at keyframes) */
    prw_dquat orientation; /* unit */
    double yfov;           /* radians */
    double ipd_m;
} prw_camera_sample;

void prw_camera_path_init(prw_camera_path *p, double fps);
void prw_camera_path_free(prw_camera_path *p); /* leaves an empty path */

/* Appends a keyframe (validated: finite, ranges above, t > last t + PRW_CAMERA_PATH_MIN_DT).  The
 * orientation is renormalised (it must be unit within 1e-3) and flipped into the previous keyframe's
 * hemisphere.  Errors name `who` (e.g. "recorder") as the file part. */
bool prw_camera_path_append(prw_camera_path *p, const prw_camera_keyframe *k, const char *who, prw_error *e);
/* Recorder helper for walk mode: appends (t, position, orientation, yfov in radians) keeping the
 * previous keyframe's ipd (first: the default). */
bool prw_camera_path_record(prw_camera_path *p, double t, prw_dvec3 position, prw_dquat orientation, double yfov,
                            prw_error *e);

/* Orientation of a camera at `position` looking at `target` with `up` (the same frame as the scene's
 * cameras, prw_node_look_at).  Fails when target == position or up is zero / parallel to the view. */
bool prw_camera_orientation_look_at(prw_dvec3 position, prw_dvec3 target, prw_dvec3 up, prw_dquat *out,
                                    prw_error *e);

/* Parses a camera-path file held in memory (need not be NUL-terminated).  `name` is the file name
 * used in messages.  On success *out is a new path (free with prw_camera_path_free); on failure *out
 * is empty and e holds one line. */
bool prw_camera_path_parse(const char *text, size_t size, const char *name, prw_camera_path *out, prw_error *e);
bool prw_camera_path_load(const char *path, prw_camera_path *out, prw_error *e);
/* Whether the file at path is meant as a camera path: a JSON object with the key "prw_camera_path"
 * (or, when it does not parse, text that names that key).  Unreadable files: false. */
bool prw_camera_path_sniff(const char *path);

/* Serialises with "%.17g" so that parse(to_json(p)) reproduces p bit for bit (orientation written as
 * a quaternion; yfov_deg and ipd_m on every keyframe).  *text is NUL-terminated; caller frees. */
bool prw_camera_path_to_json(const prw_camera_path *p, char **text, size_t *size, prw_error *e);
bool prw_camera_path_save(const prw_camera_path *p, const char *path, prw_error *e); /* atomic write */

/* Evaluation (any parsed path holds >= 2 keyframes; a recorder's path with 1 keyframe holds still at
 * it, an empty one gives the origin and the identity).  Times outside the path clamp to its ends. */
double prw_camera_path_duration(const prw_camera_path *p);
prw_camera_sample prw_camera_path_eval(const prw_camera_path *p, double t);
prw_dvec3 prw_camera_path_position(const prw_camera_path *p, double t);
prw_dquat prw_camera_path_orientation(const prw_camera_path *p, double t);
/* Analytic dP/dt.  side < 0: the limit from the left (the segment ending at t), otherwise from the
 * right; at a keyframe both are the shared keyframe velocity.  0 outside [t_first, t_last]. */
prw_dvec3 prw_camera_path_velocity(const prw_camera_path *p, double t, int side);

/* Fixed-step playback. */
double prw_camera_path_fps(const prw_camera_path *p); /* p->fps, or the default when 0 */
uint64_t prw_camera_path_frame_count(const prw_camera_path *p);
double prw_camera_path_frame_time(const prw_camera_path *p, uint64_t k);

/* One eye's view for a sample: eye 0 = centre, -1 = left, +1 = right (offset by ipd/2 along the
 * camera's right axis, parallel optical axes, symmetric frusta). */
prw_view prw_camera_sample_view(const prw_camera_sample *s, uint32_t width, uint32_t height, double znear,
                                double ev100, int eye);
/* The view for playback frame k.  Fails when k >= frame count, the image is empty or znear <= 0. */
bool prw_camera_path_frame_view(const prw_camera_path *p, uint64_t k, uint32_t width, uint32_t height,
                                double znear, double ev100, int eye, prw_view *out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif

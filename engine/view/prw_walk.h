/* prw_walk — the walkthrough's camera simulation, without a window: testable in pure C.
 *
 * Promises:
 *  - State in double: eye position (metres, world), yaw and pitch (radians; yaw 0 looks along -Z,
 *    positive yaw turns towards -X, positive pitch looks up), speed (m/s), vertical velocity.
 *  - Fixed simulation step: prw_walk_advance() runs whole steps of 1/step_hz seconds until the
 *    simulation clock (steps * dt, computed from the integer step count, never accumulated) reaches
 *    the given clock time.  The outcome after N steps depends only on the inputs delivered before
 *    each step, never on how many frames the steps were spread over (the render rate).
 *  - Input is pending until the next step consumes it: held movement buttons (a bit set), mouse-look
 *    deltas in pixels (accumulated; applied at the next step as yaw -= dx * look_rad_per_px,
 *    pitch -= dy * look_rad_per_px, pitch clamped to [-pitch_limit, +pitch_limit]), speed clicks
 *    (speed *= speed_factor^clicks, clamped to [min_speed, max_speed]) and mode toggles.
 *  - Fly mode: W/S move along the view direction, A/D along the horizontal right axis, E/Q along
 *    world +Y/-Y; diagonal input is normalised, so speed is the speed in any direction.
 *  - Walk mode (ground following): W/S/A/D move horizontally (the view direction projected on the
 *    ground plane); Q/E do nothing.  The feet are eye_height (1.7 m) below the eye.  Each step the
 *    ground is the highest scene surface under the eye's (x, z) that lies at most max_step_up above
 *    the feet (so stairs up to that riser height are climbed and ceilings above are ignored); when
 *    there is none, the highest surface below the eye itself (the feet sank into the floor, e.g. after
 *    flying low in fly mode: the viewer stands up on it).  Feet
 *    above the ground fall with gravity (semi-implicit Euler: v -= g dt, y += v dt) and land exactly
 *    on it (y = ground, v = 0); feet below the ground by at most max_step_up snap up onto it.  Where
 *    there is no ground below (outside the scene) the eye keeps its height: the mode never drops the
 *    viewer into the void.  Walls do not collide (documented limitation).
 *  - Ground queries: prw_walk_ground holds world-space triangles in double in a uniform XZ grid;
 *    a query tests the triangles of one grid cell with a vertical line (barycentric test in XZ,
 *    exact for points inside the triangle, edges inclusive).  Vertical triangles (walls) are ignored.
 *  - Dynamic resolution (prw_dynres): a damped controller of the render scale s in [min, max]
 *    (default 0.5..1.0).  Frame cost is modelled as proportional to s^2 (pixel count): from a
 *    smoothed frame time T (exponential moving average, weight `smoothing`) the ideal scale is
 *    s* = s sqrt(target / T); the controller moves s a fraction `gain` of the way to s* when T is
 *    outside the dead band |T/target - 1| > dead_band, and never by more than max_change per update.
 *    For a cost c s^2 the scale converges monotonically to clamp(sqrt(target / c)).
 */
#ifndef PRW_WALK_H
#define PRW_WALK_H

#include "prw_camera_path.h"
#include "prw_core.h"
#include "prw_math.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- ground queries */
typedef struct prw_walk_ground prw_walk_ground;

/* From world-space triangles: tri_count * 9 doubles (x0 y0 z0 x1 ...).  Non-finite vertices fail. */
bool prw_walk_ground_create(const double *tris, size_t tri_count, prw_walk_ground **out, prw_error *e);
/* From every mesh instance of a scene (after prw_scene_update), transformed to world space. */
bool prw_walk_ground_create_scene(const prw_scene *s, prw_walk_ground **out, prw_error *e);
void prw_walk_ground_destroy(prw_walk_ground *g);
size_t prw_walk_ground_triangle_count(const prw_walk_ground *g);
/* Highest surface height at (x, z) that is <= y_max; false when there is none. */
bool prw_walk_ground_height(const prw_walk_ground *g, double x, double z, double y_max, double *height);

/* ---- simulation */
typedef enum prw_walk_mode { PRW_WALK_FLY = 0, PRW_WALK_GROUND = 1 } prw_walk_mode;

enum {
    PRW_WALK_FORWARD = 1u << 0,
    PRW_WALK_BACK = 1u << 1,
    PRW_WALK_LEFT = 1u << 2,
    PRW_WALK_RIGHT = 1u << 3,
    PRW_WALK_UP = 1u << 4,
    PRW_WALK_DOWN = 1u << 5,
};

typedef struct prw_walk_params {
    double step_hz;          /* simulation steps per second; 0 -> 120 */
    double eye_height;       /* walk mode, metres; 0 -> 1.7 */
    double gravity;          /* m/s^2; 0 -> 9.81 */
    double max_step_up;      /* walk mode riser height, metres; 0 -> 0.45 */
    double look_rad_per_px;  /* 0 -> 0.003 */
    double pitch_limit;      /* radians; 0 -> 89 degrees */
    double speed_factor;     /* per speed click; 0 -> 1.25 */
    double min_speed, max_speed; /* m/s; 0 -> 0.05 and 100 */
} prw_walk_params;

typedef struct prw_walk_state {
    prw_dvec3 eye;
    double yaw, pitch;
    double speed;            /* m/s */
    double vy;               /* walk mode vertical velocity, m/s */
    prw_walk_mode mode;
    bool on_ground;
} prw_walk_state;

/* Input waiting for the next step. */
typedef struct prw_walk_input {
    uint32_t held;            /* PRW_WALK_* bits currently held */
    double look_dx, look_dy;  /* pixels, accumulated since the last step */
    int speed_clicks;         /* +n faster, -n slower */
    int mode_toggles;
} prw_walk_input;

typedef struct prw_walk_sim {
    prw_walk_params params;   /* defaults filled in by prw_walk_sim_init */
    prw_walk_state state;
    prw_walk_input input;
    const prw_walk_ground *ground; /* not owned; NULL: walk mode behaves like "no ground below" */
    uint64_t steps;           /* steps taken */
} prw_walk_sim;

/* params may be NULL (all defaults). */
void prw_walk_sim_init(prw_walk_sim *s, const prw_walk_params *params, prw_dvec3 eye, double yaw, double pitch,
                       double speed);
/* Yaw and pitch of a view direction (need not be unit). */
void prw_walk_yaw_pitch(prw_dvec3 forward, double *yaw, double *pitch);
prw_dvec3 prw_walk_forward(const prw_walk_state *st);
/* Camera orientation (camera-local -> world; looks down local -Z, +Y up): R_y(yaw) R_x(pitch). */
prw_dquat prw_walk_orientation(const prw_walk_state *st);
double prw_walk_dt(const prw_walk_sim *s);
double prw_walk_time(const prw_walk_sim *s); /* steps * dt */

/* One fixed step: consumes the pending look deltas, speed clicks and toggles; uses held buttons. */
void prw_walk_step(prw_walk_sim *s);

/* Called before each step with the step's start time (steps * dt): deliver input due by then. */
typedef void (*prw_walk_before_step_fn)(void *user, prw_walk_sim *s, double t);
/* Runs steps while (steps + 1) * dt <= clock (+1e-9 s tolerance).  before may be NULL.  At most
 * max_steps steps per call (0 = no limit; the rest is left for later calls).  A wall-clock caller
 * should drop time after a stall rather than race to catch up (prw walk keeps the simulation at most
 * 0.25 s behind the clock).  Returns the number of steps taken. */
uint64_t prw_walk_advance(prw_walk_sim *s, double clock, uint64_t max_steps, prw_walk_before_step_fn before,
                          void *user);

/* ---- dynamic resolution */
typedef struct prw_dynres {
    double target_ms;
    double min_scale, max_scale; /* 0 -> 0.5 and 1.0 */
    double gain;                 /* 0 -> 0.25 */
    double smoothing;            /* EMA weight of a new sample; 0 -> 0.3 */
    double dead_band;            /* 0 -> 0.05 */
    double max_change;           /* per update; 0 -> 0.1 */
    double scale;                /* current, starts at max_scale */
    double smoothed_ms;          /* 0 until the first sample */
} prw_dynres;

void prw_dynres_init(prw_dynres *d, double target_ms, double min_scale, double max_scale);
/* Feeds one frame time measured at the current scale; returns the new scale.  Non-finite or
 * non-positive samples are ignored. */
double prw_dynres_update(prw_dynres *d, double frame_ms);
/* Render size for a scale: round(full * scale), at least 1 pixel, at most full. */
uint32_t prw_dynres_size(uint32_t full, double scale);

#ifdef __cplusplus
}
#endif
#endif

/* Walkthrough simulation (engine/view/prw_walk.h), no window: fixed-step independence of the render
 * rate (with a variable-step control that must differ), pitch clamp, orientation, ground queries
 * against brute force, walk mode on planes (landing, slopes, stairs, ceilings), the
 * dynamic-resolution controller on a closed-form cost model. */
#include <stdlib.h>
#include <string.h>

#include "prw_test.h"
#include "prw_walk.h"

#define PI 3.14159265358979323846

static uint64_t rng = 0x243f6a8885a308d3ull;
static double urand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

/* ---------------------------------------------------------------- a timed input script */
typedef struct ev {
    double t;
    int kind; /* 0 hold bits, 1 look, 2 speed click, 3 toggle */
    uint32_t held;
    double dx, dy;
} ev;

static const ev script[] = {
    {0.00, 0, PRW_WALK_FORWARD, 0, 0},
    {0.13, 1, 0, 37, -11},
    {0.41, 2, 0, 0, 0},
    {0.52, 1, 0, -80, 25},
    {0.77, 0, PRW_WALK_FORWARD | PRW_WALK_RIGHT, 0, 0},
    {0.93, 1, 0, 120, 3},
    {1.20, 0, PRW_WALK_UP | PRW_WALK_LEFT, 0, 0},
    {1.31, 2, 0, 0, 0},
    {1.55, 1, 0, -15, -40},
    {1.80, 0, PRW_WALK_BACK, 0, 0},
    {2.05, 0, 0, 0, 0},
};
#define SCRIPT_N (sizeof script / sizeof script[0])

typedef struct player {
    size_t next;
} player;

static void deliver(void *user, prw_walk_sim *s, double t)
{
    player *p = user;
    while (p->next < SCRIPT_N && script[p->next].t <= t + 1e-9) {
        const ev *e = &script[p->next++];
        if (e->kind == 0) s->input.held = e->held;
        else if (e->kind == 1) s->input.look_dx += e->dx, s->input.look_dy += e->dy;
        else if (e->kind == 2) s->input.speed_clicks++;
        else s->input.mode_toggles++;
    }
}

/* Plays the script with frames at the given clock times; returns the final state at t_end. */
static prw_walk_state play(const double *frame_clock, int frames)
{
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(1, 2, 3), 0.3, -0.1, 1.5);
    player p = {0};
    for (int f = 0; f < frames; f++) prw_walk_advance(&s, frame_clock[f], 0, deliver, &p);
    return s.state;
}

static double pos_err(prw_walk_state a, prw_walk_state b) { return prw_v3_len(prw_v3_sub(a.eye, b.eye)); }
static bool same_state(prw_walk_state a, prw_walk_state b)
{
    return a.eye.x == b.eye.x && a.eye.y == b.eye.y && a.eye.z == b.eye.z && a.yaw == b.yaw && a.pitch == b.pitch &&
           a.speed == b.speed && a.vy == b.vy && a.mode == b.mode && a.on_ground == b.on_ground;
}

static void test_fixed_step_independent_of_frame_rate(void)
{
    const double t_end = 2.5;
    static double clocks[4][4000];
    int counts[4];
    const double fps[3] = {10, 60, 37}; /* 37 fps: frame times not multiples of the step */
    for (int r = 0; r < 3; r++) {
        int n = (int)(t_end * fps[r]) + 1;
        for (int f = 0; f < n; f++) clocks[r][f] = f / fps[r];
        clocks[r][n - 1] = t_end;
        counts[r] = n;
    }
    /* irregular frame times 1..90 ms */
    int n = 0;
    for (double t = 0; t < t_end; t += 0.001 + 0.089 * urand()) clocks[3][n++] = t;
    clocks[3][n++] = t_end;
    counts[3] = n;
    prw_walk_state ref = play(clocks[0], counts[0]);
    CHECK(pos_err(ref, play(clocks[0], 1)) > 0.1); /* sanity: the script moves the camera */
    for (int r = 1; r < 4; r++) {
        prw_walk_state s = play(clocks[r], counts[r]);
        CHECK_MSG(same_state(s, ref), "rate %d: |dp| = %.3g m, dyaw %.3g", r, pos_err(s, ref),
                  s.yaw - ref.yaw);
    }
}

/* Control: the same script integrated with the frame time as the step (input applied at frames)
 * differs between 10 and 60 fps by far more than 1 mm, so the test above can fail. */
static prw_walk_state play_variable(double fps, double t_end)
{
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(1, 2, 3), 0.3, -0.1, 1.5);
    player p = {0};
    int n = (int)(t_end * fps + 0.5);
    for (int f = 0; f < n; f++) {
        deliver(&p, &s, f / fps);
        s.params.step_hz = fps; /* one step of 1/fps */
        prw_walk_step(&s);
    }
    return s.state;
}

static void test_variable_step_control_differs(void)
{
    prw_walk_state a = play_variable(10, 2.5), b = play_variable(60, 2.5);
    CHECK_MSG(pos_err(a, b) > 0.01, "variable-step control differs by only %.3g m", pos_err(a, b));
}

static void test_advance_counts(void)
{
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 0, 1);
    CHECK(prw_walk_advance(&s, 0.5 / 120.0, 0, NULL, NULL) == 0);
    CHECK(prw_walk_advance(&s, 1.0 / 120.0, 0, NULL, NULL) == 1);
    CHECK(prw_walk_advance(&s, 0.1, 0, NULL, NULL) == 11); /* 12 steps by t = 0.1 exactly */
    CHECK(prw_walk_advance(&s, 0.1, 0, NULL, NULL) == 0);
    CHECK(prw_walk_advance(&s, 100.0, 5, NULL, NULL) == 5); /* a stall drops time */
    CHECK(s.steps == 17);
    CHECK_NEAR(prw_walk_time(&s), 17.0 / 120.0, 1e-15);
    CHECK(prw_walk_advance(&s, NAN, 0, NULL, NULL) == 0);
    /* straight flight: distance = speed * time */
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 0, 2.0);
    s.input.held = PRW_WALK_FORWARD;
    prw_walk_advance(&s, 3.0, 0, NULL, NULL);
    CHECK_NEAR(s.state.eye.z, -6.0, 1e-12);
    CHECK_NEAR(s.state.eye.x, 0.0, 1e-12);
}

static void test_pitch_clamp_and_orientation(void)
{
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 0, 1);
    s.input.look_dy = -1e6; /* mouse up a lot: look up */
    prw_walk_step(&s);
    CHECK_NEAR(s.state.pitch, 89.0 * PI / 180.0, 1e-15);
    s.input.look_dy = 3e6;
    prw_walk_step(&s);
    CHECK_NEAR(s.state.pitch, -89.0 * PI / 180.0, 1e-15);
    /* init clamps too */
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 2.0, 1);
    CHECK_NEAR(s.state.pitch, 89.0 * PI / 180.0, 1e-15);
    /* orientation rotates -Z to the forward vector, +Y to an up vector with no roll */
    for (int i = 0; i < 200; i++) {
        prw_walk_state st = {.yaw = (urand() * 2 - 1) * PI, .pitch = (urand() * 2 - 1) * 1.5};
        prw_dquat q = prw_walk_orientation(&st);
        prw_dmat4 m = prw_dm4_trs(prw_v3(0, 0, 0), q, prw_v3(1, 1, 1));
        prw_dvec3 f = prw_dm4_dir(m, prw_v3(0, 0, -1)), x = prw_dm4_dir(m, prw_v3(1, 0, 0));
        prw_dvec3 want = prw_walk_forward(&st);
        CHECK(prw_v3_len(prw_v3_sub(f, want)) < 1e-12);
        CHECK(fabs(x.y) < 1e-12); /* right axis horizontal: no roll */
        double yaw, pitch;
        prw_walk_yaw_pitch(prw_v3_scale(f, 3.0), &yaw, &pitch);
        CHECK_NEAR(yaw, st.yaw, 1e-9);
        CHECK_NEAR(pitch, st.pitch, 1e-9);
    }
    /* speed clicks: factor 1.25, clamped */
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 0, 1);
    s.input.speed_clicks = 2;
    prw_walk_step(&s);
    CHECK_NEAR(s.state.speed, 1.5625, 1e-15);
    s.input.speed_clicks = -100;
    prw_walk_step(&s);
    CHECK_NEAR(s.state.speed, 0.05, 1e-15);
}

/* ---------------------------------------------------------------- ground */
static void add_quad(double *v, size_t *n, double x0, double z0, double x1, double z1, double y00, double y10,
                     double y01, double y11)
{
    double q[18] = {x0, y00, z0, x1, y10, z0, x1, y11, z1, x0, y00, z0, x1, y11, z1, x0, y01, z1};
    memcpy(v + 9 * *n, q, sizeof q);
    *n += 2;
}

static void test_ground_query_matches_brute_force(void)
{
    enum { N = 400 };
    double *v = malloc(sizeof(double) * 9 * N);
    for (int i = 0; i < 9 * N; i++) v[i] = (i % 3 == 1) ? urand() * 4 - 2 : urand() * 20 - 10;
    for (int i = 0; i < N; i++) /* smaller triangles around random centres */
        for (int c = 1; c < 3; c++)
            for (int k = 0; k < 3; k += 2) v[9 * i + 3 * c + k] = v[9 * i + k] + (urand() - 0.5) * 5;
    prw_walk_ground *g;
    prw_error e;
    CHECK_OK(prw_walk_ground_create(v, N, &g, &e), &e);
    int hits = 0;
    for (int q = 0; q < 5000; q++) {
        double x = urand() * 24 - 12, z = urand() * 24 - 12, ymax = urand() * 4 - 2;
        /* brute force, independent barycentrics via signed areas */
        double best = -INFINITY;
        for (int i = 0; i < N; i++) {
            const double *p = v + 9 * i;
            double a = (p[3] - p[0]) * (p[8] - p[2]) - (p[6] - p[0]) * (p[5] - p[2]);
            if (fabs(a) < 1e-9) continue;
            double w0 = ((p[3] - x) * (p[8] - z) - (p[6] - x) * (p[5] - z)) / a;
            double w1 = ((p[6] - x) * (p[2] - z) - (p[0] - x) * (p[8] - z)) / a;
            double w2 = 1 - w0 - w1;
            if (w0 < 1e-9 || w1 < 1e-9 || w2 < 1e-9) continue; /* strictly inside: no edge ambiguity */
            double y = w0 * p[1] + w1 * p[4] + w2 * p[7];
            if (y <= ymax && y > best) best = y;
        }
        double h = -INFINITY;
        bool found = prw_walk_ground_height(g, x, z, ymax, &h);
        if (isfinite(best)) {
            hits++;
            CHECK_MSG(found && h >= best - 1e-9, "query %d: got %d %.9g, want %.9g", q, found, h, best);
        }
        if (found) CHECK(h <= ymax);
    }
    CHECK_MSG(hits > 1000, "only %d hits", hits);
    prw_walk_ground_destroy(g);
    free(v);
}

/* Many large overlapping layers over many small triangles: the grid coarsens instead of exploding,
 * and queries still return the highest layer under y_max. */
static void test_ground_overlapping_layers(void)
{
    enum { LAYERS = 3000, SMALL = 20000 };
    size_t n = 0;
    double *v = malloc(sizeof(double) * 9 * (2 * LAYERS + SMALL));
    for (int i = 0; i < LAYERS; i++) add_quad(v, &n, -100, -100, 100, 100, i * 0.01, i * 0.01, i * 0.01, i * 0.01);
    for (int i = 0; i < SMALL; i++) {
        double x = urand() * 190 - 95, z = urand() * 190 - 95;
        double t[9] = {x, -1, z, x + 0.5, -1, z, x, -1, z + 0.5};
        memcpy(v + 9 * n++, t, sizeof t);
    }
    prw_walk_ground *g;
    prw_error e;
    CHECK_OK(prw_walk_ground_create(v, n, &g, &e), &e);
    for (int q = 0; q < 200; q++) {
        double x = urand() * 180 - 90, z = urand() * 180 - 90, ymax = urand() * 35 - 2, h;
        bool found = prw_walk_ground_height(g, x, z, ymax, &h);
        double want = ymax < 0 ? -INFINITY : fmin(floor(ymax / 0.01 + 1e-9) * 0.01, (LAYERS - 1) * 0.01);
        if (ymax < 0) CHECK(!found || h == -1); /* only small triangles at y = -1 (maybe) */
        else CHECK_MSG(found && fabs(h - want) < 1e-9, "q %d: %d %.6f want %.6f", q, found, h, want);
    }
    prw_walk_ground_destroy(g);
    free(v);
}

static void test_walk_mode_on_plane(void)
{
    double v[9 * 16];
    size_t n = 0;
    add_quad(v, &n, -50, -50, 50, 50, 0, 0, 0, 0);          /* floor y = 0 */
    add_quad(v, &n, -50, -50, 50, 50, 3, 3, 3, 3);          /* ceiling y = 3 */
    add_quad(v, &n, 10, -50, 20, 50, 0.3, 0.3, 0.3, 0.3);   /* a 0.3 m step for x in [10, 20] */
    add_quad(v, &n, -20, -50, -10, 50, 1.0, 1.0, 1.0, 1.0); /* a 1 m block for x in [-20, -10] */
    add_quad(v, &n, 30, -50, 40, 50, 0, 1, 0, 1);           /* slope 0.1 for x in [30, 40] */
    prw_walk_ground *g;
    prw_error e;
    CHECK_OK(prw_walk_ground_create(v, n, &g, &e), &e);
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(0, 2.5, 0), -PI / 2, 0, 1.5); /* yaw -pi/2 looks along +X */
    s.ground = g;
    s.input.mode_toggles = 1;
    /* fall from feet 0.8 m: lands exactly at eye 1.7 after about sqrt(2 h / g) */
    double t_land = -1;
    for (int i = 0; i < 240; i++) {
        prw_walk_step(&s);
        if (t_land < 0 && s.state.on_ground) t_land = prw_walk_time(&s);
    }
    CHECK(s.state.mode == PRW_WALK_GROUND);
    CHECK(s.state.eye.y == 1.7);
    CHECK_NEAR(t_land, sqrt(2 * 0.8 / 9.81), 2.0 / 120.0);
    /* walking forward (looking a little up: movement stays horizontal) onto the step, ceiling ignored */
    s.input.look_dy = -100;
    s.input.held = PRW_WALK_FORWARD;
    while (s.state.eye.x < 15) prw_walk_step(&s);
    CHECK_NEAR(s.state.eye.y, 2.0, 1e-12);
    CHECK_NEAR(s.state.eye.z, 0.0, 1e-9);
    while (s.state.eye.x < 25) prw_walk_step(&s);
    for (int i = 0; i < 120; i++) prw_walk_step(&s); /* stepped down: falls and lands */
    CHECK(s.state.eye.y == 1.7);
    /* uphill on the slope: follows y = 0.1 (x - 30) + 1.7 */
    while (s.state.eye.x < 31) prw_walk_step(&s);
    for (int i = 0; i < 300 && s.state.eye.x < 39; i++) {
        prw_walk_step(&s);
        CHECK_NEAR(s.state.eye.y, 0.1 * (s.state.eye.x - 30) + 1.7, 1e-9);
    }
    /* back to the 1 m block: too high to climb, no wall collision -> the floor stays the ground */
    s.state.eye = prw_v3(-15, 1.7, 0);
    prw_walk_step(&s);
    CHECK(s.state.eye.y == 1.7);
    /* feet sunk 1.2 m into the floor (flew low, then switched to walk): stands up on it */
    s.state.eye = prw_v3(0, 0.5, 0);
    prw_walk_step(&s);
    CHECK(s.state.eye.y == 1.7);
    /* no ground below (outside the scene): holds its height */
    s.state.eye = prw_v3(500, 9.0, 0);
    prw_walk_step(&s);
    CHECK(s.state.eye.y == 9.0);
    /* fly mode ignores the ground; E climbs */
    s.input.mode_toggles = 1;
    s.input.held = PRW_WALK_UP;
    prw_walk_step(&s);
    CHECK(s.state.mode == PRW_WALK_FLY);
    CHECK_NEAR(s.state.eye.y, 9.0 + 1.5 / 120.0, 1e-12);
    prw_walk_ground_destroy(g);
    /* bad input */
    double bad[9] = {0, 0, 0, 1, NAN, 0, 0, 0, 1};
    CHECK(!prw_walk_ground_create(bad, 1, &g, &e) && strstr(e.msg, "triangle 0"));
}

/* ---------------------------------------------------------------- dynamic resolution */
static void test_dynres_converges(void)
{
    const double costs[] = {20, 40, 60, 100, 200}; /* ms at scale 1 */
    for (size_t i = 0; i < sizeof costs / sizeof costs[0]; i++) {
        prw_dynres d;
        prw_dynres_init(&d, 33.0, 0, 0);
        double want = fmin(1.0, fmax(0.5, sqrt(33.0 / costs[i]))), prev = d.scale;
        bool monotone = true;
        for (int f = 0; f < 200; f++) {
            double s = prw_dynres_update(&d, costs[i] * d.scale * d.scale);
            if (f > 0 && ((want < 1.0 && s > prev + 1e-12) || (want >= 1.0 && s < prev - 1e-12))) monotone = false;
            prev = s;
            CHECK(s >= 0.5 && s <= 1.0);
        }
        CHECK_MSG(monotone, "cost %g: scale oscillates", costs[i]);
        /* within the dead band of the target cost (5 % in time = 2.5 % in scale) */
        CHECK_MSG(fabs(d.scale - want) <= 0.026 * want, "cost %g: scale %.4f, want %.4f", costs[i], d.scale, want);
    }
    /* noisy measurements (+-15 %): stays near the fixed point, small jitter */
    prw_dynres d;
    prw_dynres_init(&d, 33.0, 0.5, 1.0);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int f = 0; f < 600; f++) {
        double s = prw_dynres_update(&d, 66.0 * d.scale * d.scale * (1 + 0.3 * (urand() - 0.5)));
        if (f >= 100) sum += s, sum2 += s * s, n++;
    }
    double mean = sum / n, sd = sqrt(fmax(0, sum2 / n - mean * mean));
    CHECK_NEAR(mean, sqrt(0.5), 0.03);
    CHECK_MSG(sd < 0.02, "scale jitter %.4f", sd);
    /* a load step responds within 30 frames */
    int f = 0;
    while (f < 30 && d.scale > 0.51) prw_dynres_update(&d, 400.0 * d.scale * d.scale), f++;
    CHECK(d.scale <= 0.51);
    /* garbage samples are ignored */
    double s0 = d.scale;
    CHECK(prw_dynres_update(&d, NAN) == s0 && prw_dynres_update(&d, -1) == s0 && prw_dynres_update(&d, INFINITY) == s0);
    CHECK(prw_dynres_size(1280, 0.5) == 640 && prw_dynres_size(1280, 1.0) == 1280 && prw_dynres_size(3, 0.01) == 1);
    CHECK(prw_dynres_size(720, 0.75) == 540 && prw_dynres_size(100, 2.0) == 100);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"fixed_step_independent_of_frame_rate", test_fixed_step_independent_of_frame_rate},
        {"variable_step_control_differs", test_variable_step_control_differs},
        {"advance_counts", test_advance_counts},
        {"pitch_clamp_and_orientation", test_pitch_clamp_and_orientation},
        {"ground_query_matches_brute_force", test_ground_query_matches_brute_force},
        {"ground_overlapping_layers", test_ground_overlapping_layers},
        {"walk_mode_on_plane", test_walk_mode_on_plane},
        {"dynres_converges", test_dynres_converges},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

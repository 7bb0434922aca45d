/* walk_sim — fixed-step walkthrough camera simulation and the dynamic-resolution controller
 * (contracts in prw_walk.h). */
#include <math.h>
#include <string.h>

#include "prw_walk.h"

#define PI 3.14159265358979323846

static double def(double v, double d) { return v > 0 ? v : d; }

void prw_walk_sim_init(prw_walk_sim *s, const prw_walk_params *params, prw_dvec3 eye, double yaw, double pitch,
                       double speed)
{
    memset(s, 0, sizeof *s);
    if (params) s->params = *params;
    prw_walk_params *p = &s->params;
    p->step_hz = def(p->step_hz, 120.0);
    p->eye_height = def(p->eye_height, 1.7);
    p->gravity = def(p->gravity, 9.81);
    p->max_step_up = def(p->max_step_up, 0.45);
    p->look_rad_per_px = def(p->look_rad_per_px, 0.003);
    p->pitch_limit = def(p->pitch_limit, 89.0 * PI / 180.0);
    p->speed_factor = def(p->speed_factor, 1.25);
    p->min_speed = def(p->min_speed, 0.05);
    p->max_speed = def(p->max_speed, 100.0);
    s->state.eye = eye;
    s->state.yaw = yaw;
    s->state.pitch = fmax(-p->pitch_limit, fmin(p->pitch_limit, pitch));
    s->state.speed = fmax(p->min_speed, fmin(p->max_speed, speed > 0 ? speed : 1.5));
    s->state.mode = PRW_WALK_FLY;
}

void prw_walk_yaw_pitch(prw_dvec3 f, double *yaw, double *pitch)
{
    double len = prw_v3_len(f);
    if (!(len > 0)) {
        *yaw = *pitch = 0;
        return;
    }
    f = prw_v3_scale(f, 1.0 / len);
    *yaw = atan2(-f.x, -f.z);
    *pitch = asin(fmax(-1.0, fmin(1.0, f.y)));
}

prw_dvec3 prw_walk_forward(const prw_walk_state *st)
{
    return prw_v3(-sin(st->yaw) * cos(st->pitch), sin(st->pitch), -cos(st->yaw) * cos(st->pitch));
}

prw_dquat prw_walk_orientation(const prw_walk_state *st)
{
    double sy = sin(0.5 * st->yaw), cy = cos(0.5 * st->yaw), sp = sin(0.5 * st->pitch), cp = cos(0.5 * st->pitch);
    prw_dquat q = {cy * sp, sy * cp, -sy * sp, cy * cp}; /* (0, sy, 0, cy) * (sp, 0, 0, cp) */
    return q;
}

double prw_walk_dt(const prw_walk_sim *s) { return 1.0 / s->params.step_hz; }
double prw_walk_time(const prw_walk_sim *s) { return (double)s->steps / s->params.step_hz; }

static void walk_vertical(prw_walk_sim *s, double dt)
{
    prw_walk_state *st = &s->state;
    const prw_walk_params *p = &s->params;
    double feet = st->eye.y - p->eye_height, ground;
    /* the ground within a riser of the feet; else (the feet sank into it, e.g. after flying low) the
     * surface under the eye itself */
    if (!s->ground || (!prw_walk_ground_height(s->ground, st->eye.x, st->eye.z, feet + p->max_step_up, &ground) &&
                       !prw_walk_ground_height(s->ground, st->eye.x, st->eye.z, st->eye.y, &ground))) {
        st->vy = 0; /* no ground below: hold the height */
        st->on_ground = false;
        return;
    }
    if (feet <= ground) { /* on it, or a step up within max_step_up: snap */
        feet = ground;
        st->vy = 0;
        st->on_ground = true;
    } else {
        st->vy -= p->gravity * dt;
        feet += st->vy * dt;
        st->on_ground = false;
        if (feet <= ground) {
            feet = ground;
            st->vy = 0;
            st->on_ground = true;
        }
    }
    st->eye.y = feet + p->eye_height;
}

void prw_walk_step(prw_walk_sim *s)
{
    prw_walk_state *st = &s->state;
    prw_walk_input *in = &s->input;
    const prw_walk_params *p = &s->params;
    double dt = prw_walk_dt(s);

    st->yaw -= in->look_dx * p->look_rad_per_px;
    st->yaw = remainder(st->yaw, 2 * PI); /* keep it in [-pi, pi] */
    st->pitch = fmax(-p->pitch_limit, fmin(p->pitch_limit, st->pitch - in->look_dy * p->look_rad_per_px));
    if (in->speed_clicks) st->speed = fmax(p->min_speed, fmin(p->max_speed, st->speed * pow(p->speed_factor, in->speed_clicks)));
    if (in->mode_toggles & 1) {
        st->mode = st->mode == PRW_WALK_FLY ? PRW_WALK_GROUND : PRW_WALK_FLY;
        st->vy = 0;
    }
    in->look_dx = in->look_dy = 0;
    in->speed_clicks = 0;
    in->mode_toggles = 0;

    double fwd = ((in->held & PRW_WALK_FORWARD) ? 1 : 0) - ((in->held & PRW_WALK_BACK) ? 1 : 0);
    double side = ((in->held & PRW_WALK_RIGHT) ? 1 : 0) - ((in->held & PRW_WALK_LEFT) ? 1 : 0);
    double up = ((in->held & PRW_WALK_UP) ? 1 : 0) - ((in->held & PRW_WALK_DOWN) ? 1 : 0);
    prw_dvec3 right = prw_v3(cos(st->yaw), 0, -sin(st->yaw)); /* horizontal, = forward x +Y normalised */
    prw_dvec3 dir;
    if (st->mode == PRW_WALK_FLY) {
        dir = prw_v3_add(prw_v3_add(prw_v3_scale(prw_walk_forward(st), fwd), prw_v3_scale(right, side)),
                         prw_v3(0, up, 0));
    } else {
        prw_dvec3 flat = prw_v3(-sin(st->yaw), 0, -cos(st->yaw));
        dir = prw_v3_add(prw_v3_scale(flat, fwd), prw_v3_scale(right, side));
    }
    double len = prw_v3_len(dir);
    if (len > 1e-12) st->eye = prw_v3_add(st->eye, prw_v3_scale(dir, st->speed * dt / len));
    if (st->mode == PRW_WALK_GROUND) walk_vertical(s, dt);
    else st->on_ground = false;
    s->steps++;
}

uint64_t prw_walk_advance(prw_walk_sim *s, double clock, uint64_t max_steps, prw_walk_before_step_fn before,
                          void *user)
{
    if (!isfinite(clock)) return 0;
    double want = floor(clock * s->params.step_hz + 1e-9 * s->params.step_hz);
    if (!(want > (double)s->steps)) return 0;
    uint64_t target = (uint64_t)want, n = 0;
    if (max_steps && target - s->steps > max_steps) target = s->steps + max_steps;
    while (s->steps < target) {
        if (before) before(user, s, prw_walk_time(s));
        prw_walk_step(s);
        n++;
    }
    return n;
}

/* ---------------------------------------------------------------- dynamic resolution */

void prw_dynres_init(prw_dynres *d, double target_ms, double min_scale, double max_scale)
{
    memset(d, 0, sizeof *d);
    d->target_ms = target_ms;
    d->min_scale = def(min_scale, 0.5);
    d->max_scale = def(max_scale, 1.0);
    if (d->min_scale > d->max_scale) d->min_scale = d->max_scale;
    d->gain = 0.25;
    d->smoothing = 0.3;
    d->dead_band = 0.05;
    d->max_change = 0.1;
    d->scale = d->max_scale;
}

double prw_dynres_update(prw_dynres *d, double ms)
{
    if (!(ms > 0) || !isfinite(ms) || !(d->target_ms > 0)) return d->scale;
    d->smoothed_ms = d->smoothed_ms > 0 ? d->smoothed_ms + d->smoothing * (ms - d->smoothed_ms) : ms;
    double ratio = d->target_ms / d->smoothed_ms;
    if (fabs(1.0 / ratio - 1.0) <= d->dead_band) return d->scale;
    double ideal = d->scale * sqrt(ratio);
    double step = d->gain * (ideal - d->scale);
    step = fmax(-d->max_change, fmin(d->max_change, step));
    double old = d->scale;
    d->scale = fmax(d->min_scale, fmin(d->max_scale, d->scale + step));
    /* the smoothed time was measured at the old scale: carry it over with the s^2 cost model */
    if (d->scale != old) d->smoothed_ms *= (d->scale * d->scale) / (old * old);
    return d->scale;
}

uint32_t prw_dynres_size(uint32_t full, double scale)
{
    double v = floor((double)full * scale + 0.5);
    if (!(v >= 1)) v = 1;
    if (v > full) v = full;
    return (uint32_t)v;
}

/* Camera paths: exactness at keyframes, C1 in time, unit quaternions, squad, straight lines, playback,
 * save/load round trip, the recorder, error messages, the demo path and the asset paths. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdlib.h>
#include <string.h>

#include "prw_camera_path.h"
#include "prw_demo.h"
#include "prw_demo_path.h"
#include "prw_test.h"

#ifndef PRW_SOURCE_DIR
#error "PRW_SOURCE_DIR must be defined"
#endif

/* ---------------------------------------------------------------- helpers (independent of the library) */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double urand(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}
static double urange(double a, double b) { return a + (b - a) * urand(); }

static double qdot(prw_dquat a, prw_dquat b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }
static double qlen(prw_dquat a) { return sqrt(qdot(a, a)); }
static prw_dquat qscale(prw_dquat a, double s)
{
    prw_dquat r = {a.x * s, a.y * s, a.z * s, a.w * s};
    return r;
}
static prw_dquat qadd(prw_dquat a, prw_dquat b)
{
    prw_dquat r = {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
    return r;
}
static prw_dquat qmul(prw_dquat a, prw_dquat b)
{
    prw_dquat r = {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                   a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
    return r;
}
static prw_dquat qconj(prw_dquat a)
{
    prw_dquat r = {-a.x, -a.y, -a.z, a.w};
    return r;
}
static double qdist(prw_dquat a, prw_dquat b) /* component distance */
{
    return qlen(qadd(a, qscale(b, -1)));
}
static double qdist_rot(prw_dquat a, prw_dquat b) /* up to sign */
{
    double d1 = qdist(a, b), d2 = qlen(qadd(a, b));
    return d1 < d2 ? d1 : d2;
}
static prw_dquat qrand(void)
{
    prw_dquat q;
    double l;
    do {
        q.x = urange(-1, 1), q.y = urange(-1, 1), q.z = urange(-1, 1), q.w = urange(-1, 1);
        l = qlen(q);
    } while (l < 0.1 || l > 1);
    return qscale(q, 1.0 / l);
}
/* exp / log on the pure part, written independently of the library (series-free closed forms). */
static prw_dquat qexp(prw_dvec3 v)
{
    double a = prw_v3_len(v);
    prw_dquat r = {0, 0, 0, 1};
    if (a == 0) return r;
    r.x = v.x / a * sin(a), r.y = v.y / a * sin(a), r.z = v.z / a * sin(a), r.w = cos(a);
    return r;
}
static prw_dvec3 qlog(prw_dquat q)
{
    double s = sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    if (s == 0) return prw_v3(0, 0, 0);
    double th = atan2(s, q.w); /* not acos(w): that loses half the digits near the identity */
    return prw_v3(q.x / s * th, q.y / s * th, q.z / s * th);
}
/* Textbook slerp: (sin((1-h)O) a + sin(hO) b) / sin O. */
static prw_dquat slerp_ref(prw_dquat a, prw_dquat b, double h)
{
    double c = qdot(a, b);
    if (c > 1) c = 1;
    double om = acos(c);
    if (om < 1e-12) return a;
    return qadd(qscale(a, sin((1 - h) * om) / sin(om)), qscale(b, sin(h * om) / sin(om)));
}

static prw_dvec3 v3rand(double r) { return prw_v3(urange(-r, r), urange(-r, r), urange(-r, r)); }

/* A random path of n keyframes.  uneven: spacings spread over four decades (1 ms .. 10 s). */
static void random_path(prw_camera_path *p, int n, bool uneven, prw_dvec3 offset)
{
    prw_camera_path_init(p, 30);
    double t = urange(-5, 5);
    prw_error e;
    for (int i = 0; i < n; i++) {
        prw_camera_keyframe k;
        k.t = t;
        k.position = prw_v3_add(offset, v3rand(5));
        k.orientation = qrand();
        k.yfov_deg = urange(20, 100);
        k.ipd_m = urange(0, 0.1);
        if (!prw_camera_path_append(p, &k, "random", &e)) {
            fprintf(stderr, "%s\n", e.msg);
            prw_test_failures++;
            return;
        }
        t += uneven ? pow(10.0, urange(-3, 1)) : 0.5;
    }
}

static bool one_line_from(const char *msg, const char *file)
{
    return strncmp(msg, file, strlen(file)) == 0 && msg[strlen(file)] == ':' && !strchr(msg, '\n');
}

/* ---------------------------------------------------------------- cases */

static void test_keyframe_exact(void)
{
    double max_pos = 0, max_q = 0, max_q_input = 0;
    for (int r = 0; r < 20; r++) {
        prw_camera_path p;
        prw_dvec3 off = r % 4 == 3 ? prw_v3(1e6, -2e5, 3e4) : prw_v3(0, 0, 0);
        uint64_t seed = rng_state;
        random_path(&p, 2 + r % 9, r % 2 == 1, off);
        /* regenerate the inputs to compare with what was given (up to sign: paths store a consistent
         * hemisphere) */
        rng_state = seed;
        double t = urange(-5, 5);
        (void)t;
        for (uint32_t i = 0; i < p.count; i++) {
            const prw_camera_keyframe *k = &p.keys[i];
            prw_dvec3 v3 = prw_v3_add(off, v3rand(5));
            prw_dquat qin = qrand();
            urange(20, 100), urange(0, 0.1);
            if (r % 2 == 1) urange(-3, 1);
            CHECK(v3.x == k->position.x && v3.y == k->position.y && v3.z == k->position.z);
            max_q_input = fmax(max_q_input, qdist_rot(qin, k->orientation));
            prw_camera_sample s = prw_camera_path_eval(&p, k->t);
            max_pos = fmax(max_pos, prw_v3_len(prw_v3_sub(s.position, k->position)));
            max_q = fmax(max_q, qdist(s.orientation, k->orientation));
            CHECK_NEAR(s.yfov, k->yfov_deg * PRW_PI / 180.0, 1e-15);
            CHECK_NEAR(s.ipd_m, k->ipd_m, 1e-15);
            if (i > 0) CHECK(qdot(k->orientation, p.keys[i - 1].orientation) >= 0);
        }
        prw_camera_path_free(&p);
    }
    printf("keyframe error: position %.3g m, orientation %.3g, stored vs input (up to sign) %.3g\n", max_pos, max_q,
           max_q_input);
    CHECK(max_pos <= 1e-12);
    CHECK(max_q <= 1e-12);
    CHECK(max_q_input <= 1e-12);
}

/* One-sided derivative estimates (second order) of the position at t. */
static prw_dvec3 fd_right(const prw_camera_path *p, double t, double h)
{
    prw_dvec3 a = prw_camera_path_position(p, t), b = prw_camera_path_position(p, t + h),
              c = prw_camera_path_position(p, t + 2 * h);
    return prw_v3_scale(prw_v3_add(prw_v3_add(prw_v3_scale(a, -3), prw_v3_scale(b, 4)), prw_v3_scale(c, -1)),
                        1.0 / (2 * h));
}
static prw_dvec3 fd_left(const prw_camera_path *p, double t, double h) { return fd_right(p, t, -h); }

static void test_c1_velocity(void)
{
    double max_jump = 0, max_fd_rel = 0, max_fd_mid_rel = 0;
    int keys_checked = 0;
    for (int r = 0; r < 24; r++) {
        prw_camera_path p;
        prw_dvec3 off = r % 3 == 2 ? prw_v3(-4e5, 1e5, 7e5) : prw_v3(0, 0, 0);
        random_path(&p, 3 + r % 10, r % 4 != 0, off);
        for (uint32_t i = 1; i + 1 < p.count; i++) {
            double t = p.keys[i].t;
            prw_dvec3 vl = prw_camera_path_velocity(&p, t, -1), vr = prw_camera_path_velocity(&p, t, +1);
            max_jump = fmax(max_jump, prw_v3_len(prw_v3_sub(vl, vr)));
            keys_checked++;
            /* the analytic one-sided derivatives are the derivatives of the position (not just equal to
             * each other): compare with one-sided finite differences inside each adjacent segment */
            double hl = 1e-5 * (t - p.keys[i - 1].t), hr = 1e-5 * (p.keys[i + 1].t - t);
            prw_dvec3 fl = fd_left(&p, t, hl), fr = fd_right(&p, t, hr);
            /* truncation error scales with the velocities around the segment */
            double scale = 1.0 + fmax(prw_v3_len(vl), fmax(prw_v3_len(prw_camera_path_velocity(&p, p.keys[i - 1].t, +1)),
                                                          prw_v3_len(prw_camera_path_velocity(&p, p.keys[i + 1].t, -1))));
            /* rounding of positions ~1e-16 * |P| over h */
            double noise = 4e-16 * (prw_v3_len(off) + 10) / fmin(hl, hr);
            double rel_l = prw_v3_len(prw_v3_sub(fl, vl)) / (scale + noise / 1e-6),
                   rel_r = prw_v3_len(prw_v3_sub(fr, vr)) / (scale + noise / 1e-6);
            max_fd_rel = fmax(max_fd_rel, fmax(rel_l, rel_r));
        }
        /* and in the middle of every segment with a central difference */
        for (uint32_t i = 0; i + 1 < p.count; i++) {
            double dt = p.keys[i + 1].t - p.keys[i].t, t = p.keys[i].t + 0.37 * dt, h = 1e-5 * dt;
            prw_dvec3 v = prw_camera_path_velocity(&p, t, +1);
            prw_dvec3 fd = prw_v3_scale(
                prw_v3_sub(prw_camera_path_position(&p, t + h), prw_camera_path_position(&p, t - h)), 0.5 / h);
            double noise = 4e-16 * (prw_v3_len(off) + 10) / h;
            max_fd_mid_rel = fmax(max_fd_mid_rel, prw_v3_len(prw_v3_sub(fd, v)) / (1.0 + prw_v3_len(v) + noise / 1e-6));
        }
        prw_camera_path_free(&p);
    }
    printf("C1: %d interior keyframes, max velocity jump %.3g m/s; analytic vs finite-difference velocity: "
           "at keys %.3g, mid-segment %.3g (relative)\n",
           keys_checked, max_jump, max_fd_rel, max_fd_mid_rel);
    CHECK(max_jump <= 1e-9);
    CHECK(max_fd_rel <= 1e-6);
    CHECK(max_fd_mid_rel <= 1e-6);
}

static void test_standing_still(void)
{
    /* rotation-only keyframes (same position) and a stop in the middle: the camera does not drift */
    prw_camera_path p;
    prw_camera_path_init(&p, 30);
    prw_error e;
    prw_dvec3 pos[] = {{0, 1.5, 0}, {1, 1.5, 0}, {1, 1.5, 0}, {1, 1.5, 0}, {2, 1.5, 1}};
    for (int i = 0; i < 5; i++) {
        prw_camera_keyframe k = {i * 0.7, pos[i], qrand(), 60, 0.063};
        CHECK_OK(prw_camera_path_append(&p, &k, "still", &e), &e);
    }
    double worst = 0;
    for (int s = 0; s <= 200; s++) {
        double t = p.keys[1].t + (p.keys[3].t - p.keys[1].t) * s / 200.0;
        worst = fmax(worst, prw_v3_len(prw_v3_sub(prw_camera_path_position(&p, t), pos[1])));
        worst = fmax(worst, prw_v3_len(prw_camera_path_velocity(&p, t, +1)));
    }
    CHECK(worst == 0);
    CHECK(prw_v3_len(prw_v3_sub(prw_camera_path_velocity(&p, p.keys[3].t, -1),
                                prw_camera_path_velocity(&p, p.keys[3].t, +1))) == 0);
    prw_camera_path_free(&p);
}

static void test_unit_quaternions(void)
{
    double worst = 0;
    long samples = 0;
    for (int r = 0; r < 12; r++) {
        prw_camera_path p;
        random_path(&p, 2 + r, r % 2 == 0, prw_v3(0, 0, 0));
        double t0 = p.keys[0].t, t1 = p.keys[p.count - 1].t;
        for (int s = -10; s <= 10010; s++) {
            double t = t0 + (t1 - t0) * s / 10000.0;
            prw_dquat q = prw_camera_path_orientation(&p, t);
            worst = fmax(worst, fabs(qlen(q) - 1));
            samples++;
        }
        /* near every keyframe, on both sides */
        for (uint32_t i = 0; i < p.count; i++)
            for (int s = -3; s <= 3; s++) {
                prw_dquat q = prw_camera_path_orientation(&p, p.keys[i].t + s * 1e-9);
                worst = fmax(worst, fabs(qlen(q) - 1));
                samples++;
            }
        prw_camera_path_free(&p);
    }
    printf("unit quaternions: %ld samples, max | |q| - 1 | = %.3g\n", samples, worst);
    CHECK(worst <= 1e-12);
}

static void test_squad(void)
{
    prw_error e;
    /* two keyframes: slerp, short arc even when the second quaternion is given in the far hemisphere */
    prw_dquat a = qrand(), b = qrand();
    if (qdot(a, b) > 0) b = qscale(b, -1);
    prw_camera_path p;
    prw_camera_path_init(&p, 30);
    prw_camera_keyframe k0 = {0, {0, 0, 0}, a, 60, 0.063}, k1 = {2, {1, 0, 0}, b, 60, 0.063};
    CHECK_OK(prw_camera_path_append(&p, &k0, "t", &e), &e);
    CHECK_OK(prw_camera_path_append(&p, &k1, "t", &e), &e);
    CHECK(qdist(p.keys[1].orientation, qscale(b, -1)) == 0); /* flipped into a's hemisphere */
    double worst = 0;
    for (int s = 0; s <= 100; s++) {
        double h = s / 100.0;
        prw_dquat q = prw_camera_path_orientation(&p, 2 * h);
        worst = fmax(worst, qdist(q, slerp_ref(a, qscale(b, -1), h)));
    }
    printf("two keyframes vs textbook slerp: %.3g\n", worst);
    CHECK(worst <= 1e-12);
    CHECK(qdist(prw_camera_path_orientation(&p, 0), a) <= 1e-15);
    CHECK(qdist(prw_camera_path_orientation(&p, 2), qscale(b, -1)) == 0);
    CHECK(qdist(prw_camera_path_orientation(&p, -1), a) == 0);
    CHECK(qdist(prw_camera_path_orientation(&p, 3), qscale(b, -1)) == 0);
    prw_camera_path_free(&p);

    /* uniform spacing: Shoemake's squad with s_i = q_i exp(-(log(q_i^-1 q_i+1) + log(q_i^-1 q_i-1)) / 4),
     * end controls s = q; hemisphere-consistent chain with some inputs given negated */
    prw_dquat q[6];
    prw_camera_path_init(&p, 30);
    for (int i = 0; i < 6; i++) {
        q[i] = qrand();
        if (i && qdot(q[i], q[i - 1]) < 0) q[i] = qscale(q[i], -1);
        prw_dquat given = i % 2 ? qscale(q[i], -1) : q[i];
        prw_camera_keyframe k = {i * 0.25, {0, 0, (double)i}, given, 60, 0.063};
        CHECK_OK(prw_camera_path_append(&p, &k, "t", &e), &e);
        CHECK(qdist(p.keys[i].orientation, q[i]) <= 1e-15);
    }
    prw_dquat sc[6];
    for (int i = 0; i < 6; i++) {
        if (i == 0 || i == 5) {
            sc[i] = q[i];
            continue;
        }
        prw_dvec3 l1 = qlog(qmul(qconj(q[i]), q[i + 1])), l2 = qlog(qmul(qconj(q[i]), q[i - 1]));
        sc[i] = qmul(q[i], qexp(prw_v3_scale(prw_v3_add(l1, l2), -0.25)));
    }
    worst = 0;
    for (int i = 0; i < 5; i++)
        for (int s = 0; s < 50; s++) {
            double h = s / 50.0;
            prw_dquat ref = slerp_ref(slerp_ref(q[i], q[i + 1], h), slerp_ref(sc[i], sc[i + 1], h), 2 * h * (1 - h));
            ref = qscale(ref, 1.0 / qlen(ref));
            worst = fmax(worst, qdist(prw_camera_path_orientation(&p, 0.25 * (i + h)), ref));
        }
    printf("uniform spacing vs textbook Shoemake squad: %.3g\n", worst);
    CHECK(worst <= 1e-9);
    prw_camera_path_free(&p);
}

/* Log-map derivative of the orientation (body frame) from one side, second order. */
static prw_dvec3 ang_fd(const prw_camera_path *p, double t, double h)
{
    prw_dquat q0 = prw_camera_path_orientation(p, t), inv = qconj(q0);
    prw_dvec3 f1 = qlog(qmul(inv, prw_camera_path_orientation(p, t + h)));
    prw_dvec3 f2 = qlog(qmul(inv, prw_camera_path_orientation(p, t + 2 * h)));
    if (qdot(q0, prw_camera_path_orientation(p, t + h)) < 0) f1 = prw_v3_scale(f1, -1);
    return prw_v3_scale(prw_v3_sub(prw_v3_scale(f1, 4), f2), 1.0 / (2 * h));
}

static void test_angular_velocity(void)
{
    /* constant angular velocity about a fixed axis at uneven times is reproduced exactly ... */
    prw_error e;
    prw_camera_path p;
    prw_camera_path_init(&p, 30);
    prw_dquat base = qrand();
    prw_dvec3 w = prw_v3(0.3, -0.5, 0.2);
    double times[] = {0, 0.1, 1.3, 1.35, 2.9, 4.0};
    for (int i = 0; i < 6; i++) {
        prw_camera_keyframe k = {times[i], {0, 0, 0}, qmul(base, qexp(prw_v3_scale(w, times[i]))), 60, 0.063};
        CHECK_OK(prw_camera_path_append(&p, &k, "t", &e), &e);
    }
    double worst = 0;
    for (int s = 0; s <= 1000; s++) {
        double t = 4.0 * s / 1000.0;
        worst = fmax(worst, qdist_rot(prw_camera_path_orientation(&p, t), qmul(base, qexp(prw_v3_scale(w, t)))));
    }
    printf("constant angular velocity at uneven times: max error %.3g\n", worst);
    CHECK(worst <= 1e-12);
    prw_camera_path_free(&p);

    /* ... and the angular velocity is continuous in time at interior keyframes of random paths */
    double max_jump_rel = 0;
    for (int r = 0; r < 10; r++) {
        random_path(&p, 4 + r % 5, true, prw_v3(0, 0, 0));
        for (uint32_t i = 1; i + 1 < p.count; i++) {
            double t = p.keys[i].t;
            double hl = 1e-5 * (t - p.keys[i - 1].t), hr = 1e-5 * (p.keys[i + 1].t - t);
            prw_dvec3 wl = ang_fd(&p, t, -hl), wr = ang_fd(&p, t, hr);
            double scale = 1.0 + prw_v3_len(wl) + 1e-15 / fmin(hl, hr) * 1e6;
            max_jump_rel = fmax(max_jump_rel, prw_v3_len(prw_v3_sub(wl, wr)) / scale);
        }
        prw_camera_path_free(&p);
    }
    printf("angular velocity jump at keyframes (finite differences, relative): %.3g\n", max_jump_rel);
    CHECK(max_jump_rel <= 1e-6);
}

static void test_linear_motion(void)
{
    prw_error e;
    double worst_v = 0, worst_p = 0;
    for (int r = 0; r < 10; r++) {
        prw_camera_path p;
        prw_camera_path_init(&p, 30);
        prw_dvec3 p0 = r % 2 ? prw_v3(1e5, 2e4, -3e5) : v3rand(3);
        prw_dvec3 dir = prw_v3_norm(v3rand(1));
        double speed = urange(0.1, 3), t0 = urange(-2, 2), t = t0;
        int n = 2 + r;
        for (int i = 0; i < n; i++) {
            prw_camera_keyframe k = {t, prw_v3_add(p0, prw_v3_scale(dir, speed * (t - t0))), qrand(), 60, 0.063};
            CHECK_OK(prw_camera_path_append(&p, &k, "line", &e), &e);
            t += pow(10.0, urange(-2, 1));
        }
        double t1 = p.keys[n - 1].t, dt_min = INFINITY;
        for (int i = 1; i < n; i++) dt_min = fmin(dt_min, p.keys[i].t - p.keys[i - 1].t);
        /* far from the origin the keyframe positions themselves are rounded (ulp(|P0|)), which moves
         * chord velocities by about ulp / dt: that much is input, not interpolation error */
        double input_noise = 4 * 2.220446049250313e-16 * prw_v3_len(p0) / (dt_min * speed);
        prw_dvec3 vel = prw_v3_scale(dir, speed);
        for (int s = 0; s <= 2000; s++) {
            double tt = fmin(t0 + (t1 - t0) * s / 2000.0, t1);
            double ev = fmax(prw_v3_len(prw_v3_sub(prw_camera_path_velocity(&p, tt, +1), vel)),
                             prw_v3_len(prw_v3_sub(prw_camera_path_velocity(&p, tt, -1), vel))) / speed;
            CHECK_MSG(ev <= 1e-12 + input_noise, "velocity error %.3g (input rounding %.3g)", ev, input_noise);
            if (r % 2 == 0) worst_v = fmax(worst_v, ev);
            prw_dvec3 expect = prw_v3_add(p0, prw_v3_scale(dir, speed * (tt - t0)));
            worst_p = fmax(worst_p, prw_v3_len(prw_v3_sub(prw_camera_path_position(&p, tt), expect)) /
                                        (1 + prw_v3_len(p0)));
        }
        prw_camera_path_free(&p);
    }
    printf("straight line at constant speed, uneven keyframes: velocity error near the origin %.3g "
           "(relative), position %.3g (relative to |P0|+1)\n",
           worst_v, worst_p);
    CHECK(worst_v <= 1e-11);
    CHECK(worst_p <= 1e-13);
}

static void test_playback(void)
{
    prw_error e;
    prw_camera_path p;
    prw_camera_path_init(&p, 30);
    prw_camera_keyframe k0 = {0.5, {0, 1.5, 0}, {0, 0, 0, 1}, 60, 0.063}, k1 = {2.5, {1, 1.5, 0}, {0, 0, 0, 1}, 60, 0.063};
    CHECK_OK(prw_camera_path_append(&p, &k0, "t", &e), &e);
    CHECK_OK(prw_camera_path_append(&p, &k1, "t", &e), &e);
    CHECK(prw_camera_path_frame_count(&p) == 61);
    for (uint64_t k = 0; k < 61; k++) CHECK(prw_camera_path_frame_time(&p, k) == 0.5 + (double)k / 30.0 || k == 60);
    CHECK(prw_camera_path_frame_time(&p, 60) == 2.5);
    p.fps = 0; /* default */
    CHECK(prw_camera_path_fps(&p) == 30.0 && prw_camera_path_frame_count(&p) == 61);
    p.fps = 7;
    CHECK(prw_camera_path_frame_count(&p) == 15); /* floor(14) + 1 */
    p.keys[1].t = 0.5 + 0.7;
    p.fps = 10;
    CHECK(prw_camera_path_frame_count(&p) == 8); /* 0.7 * 10 is 7 up to rounding */
    p.fps = 3;
    CHECK(prw_camera_path_frame_count(&p) == 3);
    CHECK(prw_camera_path_frame_time(&p, 2) == 0.5 + 2.0 / 3.0);
    prw_view v;
    CHECK(!prw_camera_path_frame_view(&p, 3, 64, 48, 0.05, 7, 0, &v, &e) && one_line_from(e.msg, "camera path"));
    CHECK(!prw_camera_path_frame_view(&p, 0, 0, 48, 0.05, 7, 0, &v, &e));
    CHECK(!prw_camera_path_frame_view(&p, 0, 64, 48, 0, 7, 0, &v, &e));
    prw_camera_path_free(&p);

    /* frame views agree with prw_view_look_at; stereo eyes sit ipd apart along the camera's right axis */
    CHECK_OK(prw_demo_path_build(&p, prw_v3(0, 0, 0), &e), &e);
    CHECK(prw_camera_path_frame_count(&p) == PRW_DEMO_PATH_FRAMES);
    CHECK(prw_camera_path_frame_time(&p, PRW_DEMO_PATH_FRAMES - 1) == p.keys[p.count - 1].t);
    prw_view c, l, r;
    CHECK_OK(prw_camera_path_frame_view(&p, 0, 640, 480, 0.05, 7.0, 0, &c, &e), &e);
    prw_view ref = prw_view_look_at(prw_v3(-2.6, 1.5, 2.2), prw_v3(0.6, 0.9, -0.8), prw_v3(0, 1, 0),
                                    60.0 * PRW_PI / 180.0, 0.05, 640, 480, 7.0);
    double dm = 0;
    for (int i = 0; i < 16; i++) dm = fmax(dm, fabs(c.view.m[i] - ref.view.m[i]));
    printf("frame 0 view matrix vs prw_view_look_at: %.3g\n", dm);
    CHECK(dm <= 1e-12);
    CHECK_NEAR(c.tan_top, ref.tan_top, 1e-15);
    CHECK_NEAR(c.tan_right, ref.tan_right, 1e-15);
    CHECK(c.width == 640 && c.height == 480 && c.znear == 0.05 && c.ev100 == 7.0);
    for (uint64_t k = 0; k < PRW_DEMO_PATH_FRAMES; k += 7) {
        CHECK_OK(prw_camera_path_frame_view(&p, k, 64, 64, 0.05, 7.0, -1, &l, &e), &e);
        CHECK_OK(prw_camera_path_frame_view(&p, k, 64, 64, 0.05, 7.0, +1, &r, &e), &e);
        CHECK_OK(prw_camera_path_frame_view(&p, k, 64, 64, 0.05, 7.0, 0, &c, &e), &e);
        prw_dvec3 right = prw_v3(c.view.m[0], c.view.m[4], c.view.m[8]);
        prw_dvec3 d = prw_v3_sub(r.eye, l.eye);
        CHECK_NEAR(prw_v3_len(d), 0.063, 1e-12);
        CHECK_NEAR(prw_v3_dot(d, right), 0.063, 1e-12);
        CHECK(prw_v3_len(prw_v3_sub(prw_v3_scale(prw_v3_add(l.eye, r.eye), 0.5), c.eye)) <= 1e-12);
        /* the same rotation for both eyes (parallel axes); the eye maps to the view-space origin */
        for (int i = 0; i < 12; i++)
            if (i % 4 != 3) CHECK(l.view.m[i] == r.view.m[i]);
        prw_dvec3 o = prw_dm4_point(l.view, l.eye);
        CHECK(prw_v3_len(o) <= 1e-12);
    }
    prw_camera_path_free(&p);
}

static bool paths_equal(const prw_camera_path *a, const prw_camera_path *b)
{
    if (a->count != b->count || memcmp(&a->fps, &b->fps, sizeof a->fps) != 0) return false;
    for (uint32_t i = 0; i < a->count; i++)
        if (memcmp(&a->keys[i], &b->keys[i], sizeof a->keys[i]) != 0) return false;
    return true;
}

static void test_round_trip(void)
{
    prw_error e;
    for (int r = 0; r < 10; r++) {
        prw_camera_path p, q;
        random_path(&p, 2 + r * 3, r % 2 == 0, r % 3 ? prw_v3(0, 0, 0) : prw_v3(123456.789, -1e8, 3.3e-7));
        if (r == 4) p.fps = 0;
        if (r == 5) p.fps = 1.0 / 3.0;
        if (r == 6) p.keys[1].position.x = -0.0;
        char *text = NULL;
        size_t n = 0;
        CHECK_OK(prw_camera_path_to_json(&p, &text, &n, &e), &e);
        CHECK(strlen(text) == n);
        CHECK_OK(prw_camera_path_parse(text, n, "roundtrip.json", &q, &e), &e);
        CHECK(paths_equal(&p, &q));
        prw_camera_path_free(&q);
        free(text);
        const char *file = prw_test_path("rt.json");
        CHECK_OK(prw_camera_path_save(&p, file, &e), &e);
        CHECK_OK(prw_camera_path_load(file, &q, &e), &e);
        CHECK(paths_equal(&p, &q));
        prw_camera_path_free(&q);
        prw_camera_path_free(&p);
    }
    /* a file with look_at, defaults and a non-normalised quaternion: load -> save -> load is stable */
    const char *src = "{\"prw_camera_path\": 1, \"keyframes\": ["
                      "{\"t\": 0, \"position\": [0, 1.5, 0], \"look_at\": [1, 1, -1], \"up\": [0, 2, 0]},"
                      "{\"t\": 0.3, \"position\": [0.1, 1.5, 0], \"orientation\": [0, 0.0001, 0, -1.0001]}]}";
    prw_camera_path a, b;
    CHECK_OK(prw_camera_path_parse(src, strlen(src), "src.json", &a, &e), &e);
    CHECK(a.fps == 0 && a.keys[0].yfov_deg == 60 && a.keys[1].ipd_m == 0.063);
    CHECK(a.keys[1].orientation.w > 0); /* flipped */
    CHECK(fabs(qlen(a.keys[1].orientation) - 1) <= 1e-15);
    char *text;
    size_t n;
    CHECK_OK(prw_camera_path_to_json(&a, &text, &n, &e), &e);
    CHECK(strstr(text, "\"fps\"") == NULL);
    CHECK_OK(prw_camera_path_parse(text, n, "src2.json", &b, &e), &e);
    CHECK(paths_equal(&a, &b));
    free(text);
    prw_camera_path_free(&a);
    prw_camera_path_free(&b);
}

static void test_recorder(void)
{
    prw_error e;
    prw_camera_path p;
    prw_camera_path_init(&p, 60);
    /* a walk recorded at an irregular frame rate */
    double t = 10.0;
    prw_dquat q = {0, 0, 0, 1};
    for (int i = 0; i < 200; i++) {
        prw_dvec3 pos = prw_v3(cos(t), 1.5 + 0.02 * sin(5 * t), sin(t));
        q = qmul(q, qexp(prw_v3(0, 0.01, 0.001)));
        if (i % 17 == 3) q = qscale(q, -1); /* sign flips in the input are harmless */
        CHECK_OK(prw_camera_path_record(&p, t, pos, q, (50 + i * 0.05) * PRW_PI / 180, &e), &e);
        t += 1.0 / 60 + 0.004 * urand();
    }
    CHECK(p.count == 200 && p.keys[0].ipd_m == PRW_CAMERA_PATH_DEFAULT_IPD_M);
    {
        /* a path being recorded can be evaluated at any size */
        prw_camera_path z = {0};
        prw_camera_sample s0 = prw_camera_path_eval(&z, 1.0);
        CHECK(s0.orientation.w == 1 && s0.position.x == 0 && prw_camera_path_frame_count(&z) == 0);
        CHECK_OK(prw_camera_path_record(&z, 2.0, prw_v3(1, 2, 3), q, 1.0, &e), &e);
        prw_camera_sample s1 = prw_camera_path_eval(&z, 0.5), s2 = prw_camera_path_eval(&z, 9.0);
        CHECK(s1.position.y == 2 && s2.position.z == 3 && s1.yfov == 1.0 * (180.0 / PRW_PI) * (PRW_PI / 180.0));
        CHECK(prw_v3_len(s1.velocity) == 0 && qdist(s1.orientation, z.keys[0].orientation) == 0);
        prw_camera_path_free(&z);
    }
    for (uint32_t i = 1; i < p.count; i++) CHECK(qdot(p.keys[i].orientation, p.keys[i - 1].orientation) > 0);
    CHECK(!prw_camera_path_record(&p, t - 1.0, prw_v3(0, 0, 0), q, 1.0, &e));
    CHECK(one_line_from(e.msg, "recorder") && strstr(e.msg, "keyframe 200.t"));
    CHECK(!prw_camera_path_record(&p, t, prw_v3(NAN, 0, 0), q, 1.0, &e));
    CHECK(one_line_from(e.msg, "recorder") && strstr(e.msg, "position"));
    CHECK(!prw_camera_path_record(&p, t, prw_v3(0, 0, 0), q, PRW_PI, &e) && strstr(e.msg, "yfov_deg"));
    prw_dquat bad = {0, 0, 0, 0.5};
    CHECK(!prw_camera_path_record(&p, t, prw_v3(0, 0, 0), bad, 1.0, &e) && strstr(e.msg, "orientation"));
    CHECK(p.count == 200);
    const char *file = prw_test_path("recorded.json");
    CHECK_OK(prw_camera_path_save(&p, file, &e), &e);
    prw_camera_path r;
    CHECK_OK(prw_camera_path_load(file, &r, &e), &e);
    CHECK(paths_equal(&p, &r));
    CHECK_NEAR(prw_camera_path_eval(&r, r.keys[7].t).yfov, (50 + 7 * 0.05) * PRW_PI / 180, 1e-14);
    prw_camera_path_free(&r);
    prw_camera_path_free(&p);
}

static void expect_error(const char *text, const char *needle)
{
    prw_camera_path p;
    prw_error e;
    e.msg[0] = '\0';
    const char *file = "dir/bad path.json";
    bool ok = prw_camera_path_parse(text, strlen(text), file, &p, &e);
    CHECK_MSG(!ok, "accepted: %s", text);
    if (ok) {
        prw_camera_path_free(&p);
        return;
    }
    CHECK(p.count == 0 && p.keys == NULL);
    CHECK_MSG(one_line_from(e.msg, file), "%s", e.msg);
    CHECK_MSG(strstr(e.msg, needle) != NULL, "'%s' lacks '%s'", e.msg, needle);
    printf("  %s\n", e.msg);
}

#define HDR "{\"prw_camera_path\": 1, \"keyframes\": ["
#define K0 "{\"t\": 0, \"position\": [0, 1, 0], \"orientation\": [0, 0, 0, 1]}"
#define K1 "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}"

static void test_errors(void)
{
    expect_error("{\n  \"prw_camera_path\": 1,\n  \"keyframes\": [\n    {\"t\": 0,, }\n  ]\n}",
                 "bad path.json:4:14: JSON syntax error");
    expect_error(HDR K0 "," K1, "bad path.json:1:");                      /* truncated */
    expect_error(HDR K0 "," K1 "]} x", ":1:");                             /* trailing text */
    expect_error("", "1:1: JSON syntax error");
    expect_error(HDR K0 "," "{\"t\": NaN, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}]}", "1:");
    expect_error(HDR K0 "," "{\"t\": 0, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].t: 0 must exceed the previous keyframe's time 0");
    expect_error(HDR K1 "," K0 "]}", ":keyframes[1].t:");
    expect_error(HDR K0 "," "{\"t\": 1e-7, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].t:");
    expect_error(HDR K0 "]}", ":keyframes: needs at least 2 keyframes (has 1)");
    expect_error(HDR "]}", ":keyframes: needs at least 2");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1e999, 1, 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].position: must be an array of 3 finite numbers");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [2e9, 1, 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].position:");
    expect_error(HDR K0 "," "{\"t\": 1e10, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].t: must be a finite number");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].position:");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, \"a\", 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1].position:");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1], \"fov\": 3}]}",
                 ":keyframes[1]: unknown key 'fov'");
    expect_error("{\"prw_camera_path\": 1, \"speed\": 2, \"keyframes\": [" K0 "," K1 "]}", ": unknown key 'speed'");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1], \"look_at\": [0, 0, 0]}]}",
                 ":keyframes[1]: give either 'orientation' or 'look_at', not both");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0]}]}", ":keyframes[1]: needs 'orientation' or 'look_at'");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"look_at\": [1, 1, 0]}]}",
                 ":keyframes[1].look_at: the target must differ");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"look_at\": [1, 3, 0]}]}",
                 ":keyframes[1].up: 'up' must not be parallel");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1], \"up\": [0, 1, 0]}]}",
                 ":keyframes[1].up: only applies together with 'look_at'");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 0.9]}]}",
                 ":keyframes[1].orientation: must be a unit quaternion");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1], \"yfov_deg\": 180}]}",
                 ":keyframes[1].yfov_deg:");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1], \"yfov_deg\": 0}]}",
                 ":keyframes[1].yfov_deg:");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1], \"ipd_m\": 0.3}]}",
                 ":keyframes[1].ipd_m:");
    expect_error(HDR K0 "," "{\"t\": 1, \"t\": 2, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}]}",
                 ":keyframes[1]: duplicate key 't'");
    expect_error(HDR K0 ", 3]}", ":keyframes[1]: must be an object");
    expect_error("{\"keyframes\": [" K0 "," K1 "]}", ":prw_camera_path: missing");
    expect_error("{\"prw_camera_path\": 2, \"keyframes\": [" K0 "," K1 "]}", ":prw_camera_path: unsupported version");
    expect_error("{\"prw_camera_path\": 1, \"fps\": 0, \"keyframes\": [" K0 "," K1 "]}", ":fps: must be");
    expect_error("{\"prw_camera_path\": 1}", ":keyframes: missing");
    expect_error("[1, 2]", ": top level must be a JSON object");
    expect_error(HDR K0 "," "{\"t\": 1, \"position\": [1, 1, 0], \"orientation\": [0, 0, 0, 1]}]}\n\n  junk",
                 ":3:3: unexpected text after the JSON document");

    prw_camera_path p;
    prw_error e;
    CHECK(!prw_camera_path_load(prw_test_path("does-not-exist.json"), &p, &e) && !strchr(e.msg, '\n'));
    CHECK(strstr(e.msg, "does-not-exist.json") != NULL);
    CHECK(p.count == 0);
    prw_camera_path_init(&p, 30);
    CHECK(!prw_camera_path_to_json(&p, &(char *){NULL}, NULL, &e));
}

/* Inside the demo room with a margin, at eye height, clear of the objects. */
static void check_in_room(const prw_camera_path *p, double margin, double ylo, double yhi, const char *what)
{
    double t0 = p->keys[0].t, t1 = p->keys[p->count - 1].t;
    for (int s = 0; s <= 4000; s++) {
        prw_dvec3 c = prw_camera_path_position(p, t0 + (t1 - t0) * s / 4000.0);
        bool ok = c.x > -3 + margin && c.x < 3 - margin && c.z > -2.5 + margin && c.z < 2.5 - margin && c.y >= ylo &&
                  c.y <= yhi;
        /* column (-2.2..-1.7, -2.2..-1.7) with the margin */
        ok = ok && !(c.x > -2.2 - margin && c.x < -1.7 + margin && c.z > -2.2 - margin && c.z < -1.7 + margin);
        CHECK_MSG(ok, "%s leaves the room or hits the column at t = %g: (%g, %g, %g)", what,
                  t0 + (t1 - t0) * s / 4000.0, c.x, c.y, c.z);
        if (!ok) return;
    }
}

static void test_demo_path(void)
{
    prw_error e;
    prw_camera_path p, f;
    CHECK_OK(prw_demo_path_build(&p, prw_v3(0, 0, 0), &e), &e);
    char file[1024];
    snprintf(file, sizeof file, "%s/assets/paths/demo_walk.json", PRW_SOURCE_DIR);
    CHECK_OK(prw_camera_path_load(file, &f, &e), &e);
    CHECK(paths_equal(&p, &f)); /* the file and the built-in path are the same path */
    prw_camera_path_free(&f);
    CHECK(prw_camera_path_frame_count(&p) == 60);
    CHECK_NEAR(prw_camera_path_duration(&p), 59.0 / 15.0, 0);
    check_in_room(&p, 0.25, 1.4, 1.6, "demo path");
    /* the demo scene's main camera is frame 0 */
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_demo_build(s, prw_v3(0, 0, 0), &e), &e);
    prw_view cam, v;
    CHECK_OK(prw_view_from_camera(s, 0, 320, 240, &cam, &e), &e);
    CHECK_OK(prw_camera_path_frame_view(&p, 0, 320, 240, 0.05, 7.0, 0, &v, &e), &e);
    double dm = 0;
    for (int i = 0; i < 16; i++) dm = fmax(dm, fabs(cam.view.m[i] - v.view.m[i]));
    CHECK(dm <= 1e-12);
    CHECK_NEAR(v.tan_top, cam.tan_top, 1e-15);
    prw_scene_destroy(s);
    /* every frame sees the objects: the gold sphere's and the red box's centres are inside the frustum */
    double speed_max = 0;
    for (uint64_t k = 0; k < 60; k++) {
        CHECK_OK(prw_camera_path_frame_view(&p, k, 320, 240, 0.05, 7.0, 0, &v, &e), &e);
        prw_dvec3 targets[2] = {{0.2, 1.1, -1.2}, {0.2, 0.4, -1.2}};
        for (int j = 0; j < 2; j++) {
            prw_dvec3 q = prw_dm4_point(v.view, targets[j]);
            double x = q.x / -q.z, y = q.y / -q.z;
            CHECK_MSG(q.z < 0 && x > v.tan_left && x < v.tan_right && y > v.tan_bottom && y < v.tan_top,
                      "frame %d: object %d off screen", (int)k, j);
        }
        speed_max = fmax(speed_max, prw_v3_len(prw_camera_path_velocity(&p, prw_camera_path_frame_time(&p, k), +1)));
    }
    printf("demo path: 60 frames over %.4f s, max speed %.3f m/s\n", prw_camera_path_duration(&p), speed_max);
    CHECK(speed_max < 2.5);
    prw_camera_path_free(&p);
    /* the offset moves the path with the scene */
    CHECK_OK(prw_demo_path_build(&p, prw_v3(1e6, 0, -1e6), &e), &e);
    CHECK_NEAR(p.keys[2].position.x, 1e6 + 0.2, 1e-9);
    prw_camera_path_free(&p);
}

static void test_asset_paths(void)
{
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/assets/paths", PRW_SOURCE_DIR);
    DIR *d = opendir(dir);
    CHECK(d != NULL);
    if (!d) return;
    int files = 0;
    for (struct dirent *de; (de = readdir(d));) {
        size_t n = strlen(de->d_name);
        if (n < 5 || strcmp(de->d_name + n - 5, ".json") != 0) continue;
        char file[1400];
        snprintf(file, sizeof file, "%s/%s", dir, de->d_name);
        prw_camera_path p, q;
        prw_error e;
        if (!prw_camera_path_load(file, &p, &e)) {
            CHECK_MSG(false, "%s", e.msg);
            continue;
        }
        files++;
        /* the demo's walkthroughs stay inside its room at eye height; other paths (e.g. floor_tilt.json, an
         * overview of gi-room-white-floor) only round-trip */
        if (strncmp(de->d_name, "demo_", 5) == 0) check_in_room(&p, 0.25, 1.3, 1.7, de->d_name);
        char *text;
        size_t len;
        CHECK_OK(prw_camera_path_to_json(&p, &text, &len, &e), &e);
        CHECK_OK(prw_camera_path_parse(text, len, de->d_name, &q, &e), &e);
        CHECK(paths_equal(&p, &q));
        printf("  %s: %u keyframes, %.3f s, %llu frames at %g fps\n", de->d_name, p.count,
               prw_camera_path_duration(&p), (unsigned long long)prw_camera_path_frame_count(&p),
               prw_camera_path_fps(&p));
        free(text);
        prw_camera_path_free(&p);
        prw_camera_path_free(&q);
    }
    closedir(d);
    CHECK(files >= 3);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"keyframe_exact", test_keyframe_exact},
        {"c1_velocity", test_c1_velocity},
        {"standing_still", test_standing_still},
        {"unit_quaternions", test_unit_quaternions},
        {"squad", test_squad},
        {"angular_velocity", test_angular_velocity},
        {"linear_motion", test_linear_motion},
        {"playback", test_playback},
        {"round_trip", test_round_trip},
        {"recorder", test_recorder},
        {"errors", test_errors},
        {"demo_path", test_demo_path},
        {"asset_paths", test_asset_paths},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

/* libFuzzer target: input scripts (app/walk_script.c) on arbitrary bytes, played into the walk
 * simulation over a small scene (a floor, a step and a slope).  Beyond "no crash / no leak / no UB"
 * it checks the contracts: a failure leaves an empty script and one line "<name>:..." ; a success
 * has events with non-decreasing times in [0, 1e6]; playing it (events delivered before the fixed
 * steps they are due at, at most 20 simulated seconds) keeps the pose finite, the pitch within its
 * clamp and the speed within its limits, and in walk mode an eye above the floor is never closer to
 * it than the eye height (below the floor, e.g. after flying down, nothing is under the eye and the
 * height holds, as documented). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_walk.h"
#include "walk_script.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void die(const char *what)
{
    fprintf(stderr, "fuzz_walk_script: contract violated: %s\n", what);
    abort();
}

typedef struct player {
    walk_script *sc;
    walk_input *in;
} player;

static void before(void *user, prw_walk_sim *s, double t)
{
    (void)s;
    player *p = user;
    walk_script_deliver(p->sc, t, p->in);
}

static prw_walk_ground *scene_ground(void)
{
    static const double tris[] = {
        -50, 0, -50, 50, 0, -50, 50, 0, 50, -50, 0, -50, 50, 0, 50, -50, 0, 50, /* floor */
        1, 0.3, -1, 3, 0.3, -1, 3, 0.3, 1, 1, 0.3, -1, 3, 0.3, 1, 1, 0.3, 1,     /* a step */
        -5, 0, -2, -3, 1, -2, -3, 1, 2,                                          /* a slope */
    };
    prw_walk_ground *g;
    prw_error e;
    if (!prw_walk_ground_create(tris, sizeof tris / sizeof tris[0] / 9, &g, &e)) die(e.msg);
    return g;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static prw_walk_ground *ground;
    if (!ground) ground = scene_ground();
    walk_script sc;
    prw_error e = {{0}};
    if (!walk_script_parse((const char *)data, size, "fuzz.txt", &sc, &e)) {
        if (sc.events || sc.count) die("failure left events");
        if (strncmp(e.msg, "fuzz.txt", 8) != 0 || strchr(e.msg, '\n')) die("error message format");
        return 0;
    }
    double last = 0;
    for (size_t i = 0; i < sc.count; i++) {
        if (!(sc.events[i].t >= last && sc.events[i].t <= 1e6)) die("event times");
        last = sc.events[i].t;
    }
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(0, 1.7, 0), 0, 0, 1.5);
    s.ground = ground;
    walk_input in;
    walk_input_init(&in, &s);
    player p = {&sc, &in};
    double end = fmin(last + 0.5, 20.0);
    for (double clock = 0; clock <= end; clock += 0.05) {
        prw_walk_advance(&s, clock, 0, before, &p);
        walk_script_deliver(&sc, prw_walk_time(&s), &in);
        const prw_walk_state *st = &s.state;
        if (!isfinite(st->eye.x) || !isfinite(st->eye.y) || !isfinite(st->eye.z) || !isfinite(st->yaw))
            die("pose not finite");
        if (fabs(st->pitch) > s.params.pitch_limit) die("pitch clamp");
        if (!(st->speed >= s.params.min_speed && st->speed <= s.params.max_speed)) die("speed limits");
        if (st->mode == PRW_WALK_GROUND && fabs(st->eye.x) < 49 && fabs(st->eye.z) < 49 && st->eye.y >= 0 &&
            st->eye.y < s.params.eye_height - 1e-9) /* above the floor yet closer than the eye height */
            die("walk mode sank below the floor");
        if (in.quit) break;
        in.screenshot = false;
    }
    walk_script_free(&sc);
    return 0;
}

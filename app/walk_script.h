/* walk_script — timed input scripts for `prw walk --input-script FILE` (tests, demos).
 *
 * Format: plain text, one event per line; '#' starts a comment; blank lines are ignored.
 *     TIME  key NAME down|up          a key (names: walk_input_key_from_name)
 *     TIME  button left|right|middle down|up
 *     TIME  mouse X Y                 cursor position in window pixels (as GLFW reports it)
 *     TIME  wheel DY                  scroll (+1 = faster)
 *     TIME  screenshot [NAME]         EXR + PNG; NAME: [A-Za-z0-9_.-], at most 63 characters
 *     TIME  quit
 * TIME is simulation time in seconds (finite, 0 <= TIME <= 1e6, non-decreasing down the file).
 * Events are delivered to the same handlers as GLFW's callbacks (walk_input.h) when the simulation
 * clock reaches TIME: before the first fixed step that starts at or after TIME, so the outcome does
 * not depend on the render rate.  Errors: "<file>:<line>: <reason>".
 */
#ifndef PRW_WALK_SCRIPT_H
#define PRW_WALK_SCRIPT_H

#include "walk_input.h"

typedef enum walk_event_kind {
    WALK_EV_KEY,
    WALK_EV_BUTTON,
    WALK_EV_MOUSE,
    WALK_EV_WHEEL,
    WALK_EV_SCREENSHOT,
    WALK_EV_QUIT,
} walk_event_kind;

typedef struct walk_event {
    double t;
    walk_event_kind kind;
    int code, action;  /* GLFW key/button and GLFW_PRESS/RELEASE */
    double x, y;       /* mouse position; wheel: y */
    char name[64];     /* screenshot name, "" = automatic */
    int line;
} walk_event;

typedef struct walk_script {
    walk_event *events;
    size_t count, next;
} walk_script;

bool walk_script_parse(const char *text, size_t size, const char *name, walk_script *out, prw_error *e);
bool walk_script_load(const char *path, walk_script *out, prw_error *e);
void walk_script_free(walk_script *s);
/* Delivers every not yet delivered event with TIME <= t (+1e-9) to the handlers, in file order. */
void walk_script_deliver(walk_script *s, double t, walk_input *in);
bool walk_script_finished(const walk_script *s);

#endif

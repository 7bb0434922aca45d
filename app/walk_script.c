/* walk_script — parser and player of input scripts (format in walk_script.h). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "walk_script.h"

#define MAX_TOKENS 6
#define MAX_EVENTS 10000000u

static bool parse_num(const char *s, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || !isfinite(v)) return false;
    *out = v;
    return true;
}

static bool parse_action(const char *s, int *action)
{
    if (strcasecmp(s, "down") == 0) *action = GLFW_PRESS;
    else if (strcasecmp(s, "up") == 0) *action = GLFW_RELEASE;
    else return false;
    return true;
}

static bool name_ok(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || n > 63 || s[0] == '.') return false;
    for (size_t i = 0; i < n; i++)
        if (!isalnum((unsigned char)s[i]) && s[i] != '_' && s[i] != '-' && s[i] != '.') return false;
    return true;
}

/* Parses one line's tokens into ev; returns false with the reason in e. */
static bool parse_event(char **tok, int nt, walk_event *ev, prw_error *e)
{
    if (!parse_num(tok[0], &ev->t)) return prw_fail(e, "time '%s' is not a number", tok[0]);
    if (ev->t < 0 || ev->t > 1e6) return prw_fail(e, "time %s outside [0, 1e6] s", tok[0]);
    if (nt < 2) return prw_fail(e, "missing event after the time");
    const char *what = tok[1];
    if (strcmp(what, "key") == 0) {
        if (nt != 4) return prw_fail(e, "'key' needs NAME down|up");
        ev->kind = WALK_EV_KEY;
        if ((ev->code = walk_input_key_from_name(tok[2])) < 0) return prw_fail(e, "unknown key '%s'", tok[2]);
        if (!parse_action(tok[3], &ev->action)) return prw_fail(e, "key action '%s': expected down or up", tok[3]);
    } else if (strcmp(what, "button") == 0) {
        if (nt != 4) return prw_fail(e, "'button' needs left|right|middle down|up");
        ev->kind = WALK_EV_BUTTON;
        if ((ev->code = walk_input_button_from_name(tok[2])) < 0) return prw_fail(e, "unknown button '%s'", tok[2]);
        if (!parse_action(tok[3], &ev->action)) return prw_fail(e, "button action '%s': expected down or up", tok[3]);
    } else if (strcmp(what, "mouse") == 0) {
        if (nt != 4) return prw_fail(e, "'mouse' needs X Y");
        ev->kind = WALK_EV_MOUSE;
        if (!parse_num(tok[2], &ev->x) || !parse_num(tok[3], &ev->y) || fabs(ev->x) > 1e6 || fabs(ev->y) > 1e6)
            return prw_fail(e, "mouse position '%s %s': expected two numbers within +-1e6", tok[2], tok[3]);
    } else if (strcmp(what, "wheel") == 0) {
        if (nt != 3) return prw_fail(e, "'wheel' needs DY");
        ev->kind = WALK_EV_WHEEL;
        if (!parse_num(tok[2], &ev->y) || fabs(ev->y) > 1e3) return prw_fail(e, "wheel '%s': expected a number within +-1000", tok[2]);
    } else if (strcmp(what, "screenshot") == 0) {
        if (nt > 3) return prw_fail(e, "'screenshot' takes at most a NAME");
        ev->kind = WALK_EV_SCREENSHOT;
        if (nt == 3) {
            if (!name_ok(tok[2])) return prw_fail(e, "screenshot name '%s': use 1-63 of [A-Za-z0-9_.-], not starting with '.'", tok[2]);
            strcpy(ev->name, tok[2]);
        }
    } else if (strcmp(what, "quit") == 0) {
        if (nt != 2) return prw_fail(e, "'quit' takes no arguments");
        ev->kind = WALK_EV_QUIT;
    } else {
        return prw_fail(e, "unknown event '%s' (key, button, mouse, wheel, screenshot, quit)", what);
    }
    return true;
}

bool walk_script_parse(const char *text, size_t size, const char *name, walk_script *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    size_t cap = 0;
    int line = 0;
    double last_t = 0;
    for (size_t pos = 0; pos < size;) {
        size_t end = pos;
        while (end < size && text[end] != '\n') end++;
        line++;
        char buf[512];
        size_t n = end - pos;
        if (n >= sizeof buf) {
            walk_script_free(out);
            return prw_fail(e, "%s:%d: line longer than %zu characters", name, line, sizeof buf - 1);
        }
        memcpy(buf, text + pos, n);
        buf[n] = '\0';
        pos = end + 1;
        for (size_t i = 0; i < n; i++) {
            if (buf[i] == '#') {
                buf[i] = '\0';
                break;
            }
            if (buf[i] == '\0' || ((unsigned char)buf[i] < 32 && buf[i] != '\t' && buf[i] != '\r')) {
                walk_script_free(out);
                return prw_fail(e, "%s:%d: control character 0x%02x", name, line, (unsigned char)buf[i]);
            }
        }
        char *tok[MAX_TOKENS + 1];
        int nt = 0;
        for (char *s = strtok(buf, " \t\r"); s; s = strtok(NULL, " \t\r")) {
            if (nt == MAX_TOKENS) {
                walk_script_free(out);
                return prw_fail(e, "%s:%d: too many fields", name, line);
            }
            tok[nt++] = s;
        }
        if (nt == 0) continue;
        walk_event ev = {.line = line};
        prw_error why;
        if (!parse_event(tok, nt, &ev, &why)) {
            walk_script_free(out);
            return prw_fail(e, "%s:%d: %s", name, line, why.msg);
        }
        if (ev.t < last_t) {
            walk_script_free(out);
            return prw_fail(e, "%s:%d: time %.17g is before the previous event's %.17g (times must not decrease)", name,
                            line, ev.t, last_t);
        }
        last_t = ev.t;
        if (out->count == cap) {
            if (cap >= MAX_EVENTS) {
                walk_script_free(out);
                return prw_fail(e, "%s:%d: more than %u events", name, line, MAX_EVENTS);
            }
            cap = cap ? 2 * cap : 64;
            out->events = prw_realloc(out->events, cap * sizeof *out->events);
        }
        out->events[out->count++] = ev;
    }
    if (out->count == 0) {
        walk_script_free(out);
        return prw_fail(e, "%s: no events (an empty script does nothing; end it with 'TIME quit')", name);
    }
    return true;
}

bool walk_script_load(const char *path, walk_script *out, prw_error *e)
{
    char *data;
    size_t size;
    memset(out, 0, sizeof *out);
    if (!prw_read_file(path, &data, &size, e)) return false;
    bool ok = walk_script_parse(data, size, path, out, e);
    free(data);
    return ok;
}

void walk_script_free(walk_script *s)
{
    free(s->events);
    memset(s, 0, sizeof *s);
}

void walk_script_deliver(walk_script *s, double t, walk_input *in)
{
    while (s->next < s->count && s->events[s->next].t <= t + 1e-9) {
        const walk_event *ev = &s->events[s->next++];
        switch (ev->kind) {
        case WALK_EV_KEY: walk_input_key(in, ev->code, ev->action); break;
        case WALK_EV_BUTTON: walk_input_button(in, ev->code, ev->action); break;
        case WALK_EV_MOUSE: walk_input_cursor(in, ev->x, ev->y); break;
        case WALK_EV_WHEEL: walk_input_scroll(in, 0, ev->y); break;
        case WALK_EV_SCREENSHOT:
            in->screenshot = true;
            memcpy(in->screenshot_name, ev->name, sizeof in->screenshot_name);
            break;
        case WALK_EV_QUIT: in->quit = true; break;
        }
    }
}

bool walk_script_finished(const walk_script *s) { return s->next >= s->count; }

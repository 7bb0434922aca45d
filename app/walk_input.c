/* walk_input — key/mouse handlers shared by GLFW callbacks and input scripts (walk_input.h). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "walk_input.h"

void walk_input_init(walk_input *in, prw_walk_sim *sim)
{
    memset(in, 0, sizeof *in);
    in->sim = sim;
}

static uint32_t move_bit(int key)
{
    switch (key) {
    case GLFW_KEY_W: return PRW_WALK_FORWARD;
    case GLFW_KEY_S: return PRW_WALK_BACK;
    case GLFW_KEY_A: return PRW_WALK_LEFT;
    case GLFW_KEY_D: return PRW_WALK_RIGHT;
    case GLFW_KEY_E: return PRW_WALK_UP;
    case GLFW_KEY_Q: return PRW_WALK_DOWN;
    default: return 0;
    }
}

void walk_input_key(walk_input *in, int key, int action)
{
    uint32_t bit = move_bit(key);
    if (bit) {
        if (action == GLFW_PRESS) in->held |= bit;
        else if (action == GLFW_RELEASE) in->held &= ~bit;
        in->sim->input.held = in->held;
        return;
    }
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    switch (key) {
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: in->sim->input.speed_clicks++; break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: in->sim->input.speed_clicks--; break;
    default: break;
    }
    if (action != GLFW_PRESS) return;
    switch (key) {
    case GLFW_KEY_F: in->sim->input.mode_toggles++; break;
    case GLFW_KEY_H: in->hud_toggle = !in->hud_toggle; break;
    case GLFW_KEY_F12: in->screenshot = true; break;
    case GLFW_KEY_R: in->measure = true; break;
    case GLFW_KEY_ESCAPE: in->quit = true; break;
    default: break;
    }
}

void walk_input_cursor(walk_input *in, double x, double y)
{
    if (in->have_cursor && in->look_held) {
        in->sim->input.look_dx += x - in->cursor_x;
        in->sim->input.look_dy += y - in->cursor_y;
    }
    in->cursor_x = x;
    in->cursor_y = y;
    in->have_cursor = true;
}

void walk_input_button(walk_input *in, int button, int action)
{
    if (button == GLFW_MOUSE_BUTTON_RIGHT) in->look_held = action == GLFW_PRESS;
}

void walk_input_scroll(walk_input *in, double dx, double dy)
{
    (void)dx;
    if (dy > 0) in->sim->input.speed_clicks++;
    else if (dy < 0) in->sim->input.speed_clicks--;
}

int walk_input_key_from_name(const char *name)
{
    size_t n = strlen(name);
    if (n == 1) {
        char c = name[0];
        if (c >= 'a' && c <= 'z') return GLFW_KEY_A + (c - 'a');
        if (c >= 'A' && c <= 'Z') return GLFW_KEY_A + (c - 'A');
        if (c >= '0' && c <= '9') return GLFW_KEY_0 + (c - '0');
        if (c == '+' || c == '=') return GLFW_KEY_EQUAL;
        if (c == '-') return GLFW_KEY_MINUS;
        return -1;
    }
    if ((name[0] == 'F' || name[0] == 'f') && n <= 3) {
        char *end;
        long k = strtol(name + 1, &end, 10);
        if (*end == '\0' && end != name + 1 && k >= 1 && k <= 12) return GLFW_KEY_F1 + (int)(k - 1);
        return -1;
    }
    static const struct {
        const char *name;
        int key;
    } named[] = {
        {"ESCAPE", GLFW_KEY_ESCAPE}, {"ESC", GLFW_KEY_ESCAPE}, {"EQUAL", GLFW_KEY_EQUAL},
        {"PLUS", GLFW_KEY_EQUAL},    {"MINUS", GLFW_KEY_MINUS}, {"KP_ADD", GLFW_KEY_KP_ADD},
        {"KP_SUBTRACT", GLFW_KEY_KP_SUBTRACT}, {"SPACE", GLFW_KEY_SPACE}, {"TAB", GLFW_KEY_TAB},
        {"ENTER", GLFW_KEY_ENTER},
    };
    for (size_t i = 0; i < sizeof named / sizeof named[0]; i++)
        if (strcasecmp(name, named[i].name) == 0) return named[i].key;
    return -1;
}

int walk_input_button_from_name(const char *name)
{
    if (strcasecmp(name, "left") == 0) return GLFW_MOUSE_BUTTON_LEFT;
    if (strcasecmp(name, "right") == 0) return GLFW_MOUSE_BUTTON_RIGHT;
    if (strcasecmp(name, "middle") == 0) return GLFW_MOUSE_BUTTON_MIDDLE;
    return -1;
}

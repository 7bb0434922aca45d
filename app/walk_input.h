/* walk_input — the walkthrough's input handlers.  GLFW's callbacks and the input-script player
 * (walk_script.h) call exactly these functions with GLFW key/button/action codes, so a script
 * exercises the same code paths as a person at the keyboard.
 *
 * Bindings: W/S forward/back, A/D left/right, E/Q up/down (fly mode), right mouse button held +
 * cursor motion = look, +/- (also keypad, key repeat counts) and the mouse wheel = speed x1.25 per
 * click, F = toggle fly / walk (ground following), H = toggle the HUD, F12 = screenshot, R = measure
 * the error against the reference, Esc = quit.
 * Movement and look go to the simulation's pending input (prw_walk_input); the rest sets flags
 * the window loop reads and clears.
 */
#ifndef PRW_WALK_INPUT_H
#define PRW_WALK_INPUT_H

#include "prw_walk.h"

typedef struct walk_input {
    prw_walk_sim *sim;          /* receives movement and look */
    bool quit, screenshot, hud_toggle, measure;
    char screenshot_name[64];   /* "" = automatic name */
    bool look_held;             /* right mouse button down */
    bool have_cursor;
    double cursor_x, cursor_y;  /* last position, window pixels */
    uint32_t held;              /* PRW_WALK_* bits from keys */
} walk_input;

void walk_input_init(walk_input *in, prw_walk_sim *sim);
/* key: GLFW_KEY_*, action: GLFW_PRESS, GLFW_RELEASE or GLFW_REPEAT. */
void walk_input_key(walk_input *in, int key, int action);
/* Absolute cursor position in window pixels (GLFW's cursor-position callback). */
void walk_input_cursor(walk_input *in, double x, double y);
/* button: GLFW_MOUSE_BUTTON_*, action: GLFW_PRESS or GLFW_RELEASE. */
void walk_input_button(walk_input *in, int button, int action);
void walk_input_scroll(walk_input *in, double dx, double dy);

/* Key names for scripts: a letter or digit, F1..F12, ESCAPE (ESC), EQUAL (PLUS), MINUS, KP_ADD,
 * KP_SUBTRACT, SPACE, TAB, ENTER (case-insensitive).  Returns the GLFW key code or -1. */
int walk_input_key_from_name(const char *name);
/* LEFT, RIGHT, MIDDLE -> GLFW_MOUSE_BUTTON_*, else -1. */
int walk_input_button_from_name(const char *name);

#endif

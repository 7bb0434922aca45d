/* Walkthrough app pieces without a window: the input handlers (what GLFW callbacks and scripts
 * call), the input-script parser (errors with line numbers) and player, the HUD font and layout. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "prw_test.h"
#include "walk_hud.h"
#include "walk_input.h"
#include "walk_script.h"

static void test_handlers(void)
{
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 0, 1);
    walk_input in;
    walk_input_init(&in, &s);
    walk_input_key(&in, GLFW_KEY_W, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_D, GLFW_PRESS);
    CHECK(s.input.held == (PRW_WALK_FORWARD | PRW_WALK_RIGHT));
    walk_input_key(&in, GLFW_KEY_W, GLFW_REPEAT);
    walk_input_key(&in, GLFW_KEY_W, GLFW_RELEASE);
    CHECK(s.input.held == PRW_WALK_RIGHT);
    /* look only while the right button is held; deltas from the previous cursor position */
    walk_input_cursor(&in, 10, 10);
    walk_input_cursor(&in, 30, 5);
    CHECK(s.input.look_dx == 0 && s.input.look_dy == 0);
    walk_input_button(&in, GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS);
    walk_input_cursor(&in, 40, 0);
    walk_input_cursor(&in, 45, 2);
    CHECK(s.input.look_dx == 15 && s.input.look_dy == -3);
    walk_input_button(&in, GLFW_MOUSE_BUTTON_RIGHT, GLFW_RELEASE);
    walk_input_cursor(&in, 100, 100);
    CHECK(s.input.look_dx == 15 && s.input.look_dy == -3);
    /* speed: +, keypad +, repeat, -, wheel */
    walk_input_key(&in, GLFW_KEY_EQUAL, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_EQUAL, GLFW_REPEAT);
    walk_input_key(&in, GLFW_KEY_KP_ADD, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_MINUS, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_EQUAL, GLFW_RELEASE);
    walk_input_scroll(&in, 0, 2.0);
    walk_input_scroll(&in, 0, -1.0);
    CHECK(s.input.speed_clicks == 2);
    walk_input_key(&in, GLFW_KEY_F, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_F, GLFW_REPEAT); /* no second toggle */
    CHECK(s.input.mode_toggles == 1);
    CHECK(!in.quit && !in.screenshot && !in.hud_toggle);
    walk_input_key(&in, GLFW_KEY_F12, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_H, GLFW_PRESS);
    walk_input_key(&in, GLFW_KEY_ESCAPE, GLFW_PRESS);
    CHECK(in.quit && in.screenshot && in.hud_toggle);
    /* the step consumes the pending input */
    prw_walk_step(&s);
    CHECK(s.input.look_dx == 0 && s.input.speed_clicks == 0 && s.input.mode_toggles == 0);
    CHECK(s.state.mode == PRW_WALK_GROUND);
    CHECK_NEAR(s.state.yaw, -15 * 0.003, 1e-15);
    CHECK_NEAR(s.state.speed, 1.5625, 1e-15);
    /* key names */
    CHECK(walk_input_key_from_name("w") == GLFW_KEY_W && walk_input_key_from_name("W") == GLFW_KEY_W);
    CHECK(walk_input_key_from_name("F12") == GLFW_KEY_F12 && walk_input_key_from_name("f1") == GLFW_KEY_F1);
    CHECK(walk_input_key_from_name("plus") == GLFW_KEY_EQUAL && walk_input_key_from_name("Esc") == GLFW_KEY_ESCAPE);
    CHECK(walk_input_key_from_name("F13") < 0 && walk_input_key_from_name("F0") < 0 && walk_input_key_from_name("") < 0);
    CHECK(walk_input_key_from_name("shift") < 0 && walk_input_key_from_name("F1x") < 0);
}

static const char good[] = "# comment\n"
                           "\n"
                           "0     key W down   # trailing comment\n"
                           "0.25  button right down\n"
                           "0.25  mouse 10 20\r\n"
                           "0.5   mouse 16 18\n"
                           "0.5   wheel -1\n"
                           "1e0   screenshot shot_1.a\n"
                           "1.0   screenshot\n"
                           "2     key W up\n"
                           "2.5   quit\n";

static void test_script_parse_and_play(void)
{
    walk_script sc;
    prw_error e;
    CHECK_OK(walk_script_parse(good, strlen(good), "good.txt", &sc, &e), &e);
    CHECK(sc.count == 9);
    CHECK(sc.events[0].kind == WALK_EV_KEY && sc.events[0].code == GLFW_KEY_W && sc.events[0].action == GLFW_PRESS);
    CHECK(sc.events[0].line == 3 && sc.events[8].line == 11);
    CHECK(sc.events[2].kind == WALK_EV_MOUSE && sc.events[2].x == 10 && sc.events[2].y == 20);
    CHECK(sc.events[5].kind == WALK_EV_SCREENSHOT && strcmp(sc.events[5].name, "shot_1.a") == 0);
    CHECK(sc.events[6].name[0] == '\0');
    prw_walk_sim s;
    prw_walk_sim_init(&s, NULL, prw_v3(0, 0, 0), 0, 0, 1);
    walk_input in;
    walk_input_init(&in, &s);
    walk_script_deliver(&sc, 0.2, &in);
    CHECK(sc.next == 1 && s.input.held == PRW_WALK_FORWARD);
    walk_script_deliver(&sc, 0.5 - 1e-12, &in); /* within the 1e-9 s tolerance */
    CHECK(sc.next == 5 && s.input.look_dx == 6 && s.input.look_dy == -2 && s.input.speed_clicks == -1);
    walk_script_deliver(&sc, 1.0, &in);
    CHECK(in.screenshot && in.screenshot_name[0] == '\0'); /* the later, unnamed one wins the frame */
    CHECK(!walk_script_finished(&sc));
    walk_script_deliver(&sc, 10, &in);
    CHECK(in.quit && s.input.held == 0 && walk_script_finished(&sc));
    walk_script_free(&sc);

    static const struct {
        const char *text, *want;
    } bad[] = {
        {"0 key W down\n0.5 jump\n", "bad.txt:2: unknown event 'jump'"},
        {"x key W down\n", "bad.txt:1: time 'x' is not a number"},
        {"-1 quit\n", "bad.txt:1: time -1 outside"},
        {"nan quit\n", "bad.txt:1: time 'nan' is not a number"},
        {"1 quit\n0.5 quit\n", "bad.txt:2: time 0.5 is before"},
        {"\n\n0 key shift down\n", "bad.txt:3: unknown key 'shift'"},
        {"0 key W\n", "bad.txt:1: 'key' needs NAME down|up"},
        {"0 key W sideways\n", "bad.txt:1: key action 'sideways'"},
        {"0 button left\n", "bad.txt:1: 'button' needs"},
        {"0 button top down\n", "bad.txt:1: unknown button 'top'"},
        {"0 mouse 1\n", "bad.txt:1: 'mouse' needs X Y"},
        {"0 mouse 1 y\n", "bad.txt:1: mouse position '1 y'"},
        {"0 wheel\n", "bad.txt:1: 'wheel' needs DY"},
        {"0 screenshot ../etc\n", "bad.txt:1: screenshot name '../etc'"},
        {"0 screenshot a b\n", "bad.txt:1: 'screenshot' takes at most a NAME"},
        {"0 quit now\n", "bad.txt:1: 'quit' takes no arguments"},
        {"0\n", "bad.txt:1: missing event"},
        {"# nothing\n\n", "bad.txt: no events"},
        {"0 quit\n0 key W down \x01\n", "bad.txt:2: control character 0x01"},
        {"0 a b c d e f g\n", "bad.txt:1: too many fields"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        e.msg[0] = '\0';
        bool ok = walk_script_parse(bad[i].text, strlen(bad[i].text), "bad.txt", &sc, &e);
        CHECK_MSG(!ok && strncmp(e.msg, bad[i].want, strlen(bad[i].want)) == 0, "case %zu: got '%s', want '%s...'", i,
                  e.msg, bad[i].want);
        CHECK(sc.events == NULL && sc.count == 0);
        CHECK(strchr(e.msg, '\n') == NULL);
    }
    /* a NUL byte inside the text, an over-long line */
    const char nul[] = "0 quit\n0 key\0W down\n";
    CHECK(!walk_script_parse(nul, sizeof nul - 1, "bad.txt", &sc, &e) && strstr(e.msg, "bad.txt:2: control character 0x00"));
    char *longl = malloc(2000);
    memset(longl, ' ', 1999);
    longl[1999] = '\n';
    CHECK(!walk_script_parse(longl, 2000, "bad.txt", &sc, &e) && strstr(e.msg, "bad.txt:1: line longer"));
    free(longl);
    CHECK(!walk_script_load("/nonexistent/script.txt", &sc, &e) && strstr(e.msg, "/nonexistent/script.txt"));
}

static void test_font(void)
{
    const uint8_t *space = walk_font_glyph(' ');
    for (int r = 0; r < WALK_FONT_H; r++) CHECK(space[r] == 0);
    for (int c = 33; c <= 126; c++) {
        const uint8_t *g = walk_font_glyph((unsigned char)c);
        int ink = 0;
        for (int r = 0; r < WALK_FONT_H; r++) {
            CHECK(g[r] < 32); /* 5 columns */
            for (int b = 0; b < 5; b++) ink += (g[r] >> b) & 1;
        }
        CHECK_MSG(ink >= 2, "glyph '%c' has %d ink pixels", c, ink);
        for (int d = 32; d < c; d++)
            CHECK_MSG(memcmp(g, walk_font_glyph((unsigned char)d), WALK_FONT_H) != 0, "glyphs '%c' and '%c' are identical",
                      c, d);
    }
    /* non-printable characters draw a hollow box, distinct from every printable glyph */
    const uint8_t *box = walk_font_glyph(200);
    CHECK(box[0] == 0x1f && box[3] == 0x11 && box[6] == 0x1f);
    CHECK(memcmp(box, walk_font_glyph('\n'), WALK_FONT_H) == 0);
    /* known shapes: 'T' top bar + stem, 'L' stem + foot */
    const uint8_t *t = walk_font_glyph('T'), *l = walk_font_glyph('L');
    CHECK(t[0] == 0x1f && t[3] == 0x04 && t[6] == 0x04);
    CHECK(l[0] == 0x10 && l[6] == 0x1f);
}

static void test_text_render(void)
{
    enum { W = 40, H = 24 };
    uint8_t img[W * H * 4];
    memset(img, 0, sizeof img);
    const uint8_t red[4] = {255, 0, 0, 255};
    CHECK(walk_hud_text(img, W, H, 3, 2, 2, "A", red) == WALK_CELL_W * 2);
    const uint8_t *g = walk_font_glyph('A');
    int mismatches = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int gx = (x - 3) / 2, gy = (y - 2 - 2) / 2; /* scale 2, one empty row above the glyph */
            bool want = x >= 3 && y >= 4 && gx < WALK_FONT_W && gy < WALK_FONT_H &&
                        ((g[gy] >> (WALK_FONT_W - 1 - gx)) & 1);
            bool got = img[4 * (y * W + x)] == 255;
            mismatches += want != got;
        }
    CHECK_MSG(mismatches == 0, "%d pixels differ from the glyph", mismatches);
    /* clipped at every edge: nothing written outside, no crash (ASan) */
    uint8_t small[8 * 8 * 4 + 16];
    memset(small, 7, sizeof small);
    walk_hud_text(small, 8, 8, -5, -6, 3, "MW@#", red);
    walk_hud_text(small, 8, 8, 6, 6, 1, "MW@#", red);
    for (size_t i = 8 * 8 * 4; i < sizeof small; i++) CHECK(small[i] == 7);
    /* the panel: lines' extent + padding, clipped */
    uint8_t *panel = calloc(200 * 60, 4);
    const char *lines[] = {"frame 12.3 ms", "triangles 4454", "x"};
    int uw, uh;
    walk_hud_compose(panel, 200, 60, 1, lines, 3, &uw, &uh);
    CHECK(uw == 14 * WALK_CELL_W + 2 * WALK_HUD_PAD && uh == 3 * WALK_CELL_H + 2 * WALK_HUD_PAD);
    CHECK(panel[4 * (0 * 200 + 0) + 3] == 255 && panel[4 * (0 * 200 + uw) + 3] == 0); /* background ends at uw */
    walk_hud_compose(panel, 50, 20, 2, lines, 3, &uw, &uh);
    CHECK(uw == 50 && uh == 20);
    free(panel);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"handlers", test_handlers},
        {"script_parse_and_play", test_script_parse_and_play},
        {"font", test_font},
        {"text_render", test_text_render},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

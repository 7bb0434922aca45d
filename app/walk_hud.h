/* walk_hud — the walkthrough's heads-up display: a bitmap font designed for prw (5x7 glyphs in
 * 6x10 cells, printable ASCII 32..126; anything else draws as a hollow box), CPU text layout into an
 * RGBA8 image, and a GPU overlay that copies that image into the top-left corner of the presented
 * swapchain image.
 *
 * The overlay is an opaque panel (dark background, light text) blitted after the scene: the scene's
 * own images (and so screenshots) never contain the HUD.  It is uploaded once per frame with a
 * waited transfer and blitted with a write-after-write barrier after the scene blit, so it is
 * validation-clean (including synchronization validation).
 */
#ifndef PRW_WALK_HUD_H
#define PRW_WALK_HUD_H

#include "prw_gpu.h"

#define WALK_FONT_W 5
#define WALK_FONT_H 7
#define WALK_CELL_W 6
#define WALK_CELL_H 10
#define WALK_HUD_PAD 4

/* 7 bytes, row 0 at the top; bit 4 is the leftmost column, bit 0 the rightmost. */
const uint8_t *walk_font_glyph(unsigned char c);

/* Draws s at pixel (x, y) (top-left of its first cell) into rgba (w x h, 4 bytes per pixel, rows
 * top-down), each font pixel as a scale x scale block of `color`; clipped to the image.  Only text
 * pixels are written.  Returns the advance in pixels (strlen * WALK_CELL_W * scale). */
int walk_hud_text(uint8_t *rgba, int w, int h, int x, int y, int scale, const char *s, const uint8_t color[4]);

/* Fills the panel for `lines` (background box of the lines' extent + padding, clipped to w x h)
 * and draws them; *used_w, *used_h: the panel's size in pixels (clipped). */
void walk_hud_compose(uint8_t *rgba, int w, int h, int scale, const char *const *lines, int n, int *used_w,
                      int *used_h);

typedef struct walk_hud walk_hud;

/* An overlay of at most max_cols x max_lines characters at `scale`. */
bool walk_hud_create(prw_gpu *gpu, int max_cols, int max_lines, int scale, walk_hud **out, prw_error *e);
void walk_hud_destroy(prw_gpu *gpu, walk_hud *h);
/* Composes and uploads the panel (a waited transfer: call between frames' GPU work). */
bool walk_hud_upload(prw_gpu *gpu, walk_hud *h, const char *const *lines, int n, prw_error *e);
/* Records the blit of the panel into target's top-left corner (target: TRANSFER_DST_OPTIMAL after
 * an earlier transfer write; a barrier orders the two).  Clipped to the target. */
void walk_hud_record(VkCommandBuffer cmd, walk_hud *h, prw_gpu_image *target);

#endif

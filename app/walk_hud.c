/* walk_hud — bitmap font, text layout and the HUD overlay (walk_hud.h).
 *
 * The font below was drawn for prw: one string per glyph, 7 rows of 5 columns ('#' = ink),
 * rows separated by spaces, converted to bytes on first use.  In a 10-row cell a glyph starts at
 * row 1; the descender letters g p q y start at row 3 (their last two rows hang below the line). */
#include <stdlib.h>
#include <string.h>

#include "walk_hud.h"

static const char *const glyph_art[95] = {
    /*   */ "..... ..... ..... ..... ..... ..... .....",
    /* ! */ "..#.. ..#.. ..#.. ..#.. ..#.. ..... ..#..",
    /* " */ ".#.#. .#.#. ..... ..... ..... ..... .....",
    /* # */ ".#.#. .#.#. ##### .#.#. ##### .#.#. .#.#.",
    /* $ */ "..#.. .#### #.#.. .###. ..#.# ####. ..#..",
    /* % */ "##..# ##..# ...#. ..#.. .#... #..## #..##",
    /* & */ ".##.. #..#. #.#.. .#... #.#.# #..#. .##.#",
    /* ' */ "..#.. ..#.. ..... ..... ..... ..... .....",
    /* ( */ "...#. ..#.. .#... .#... .#... ..#.. ...#.",
    /* ) */ ".#... ..#.. ...#. ...#. ...#. ..#.. .#...",
    /* * */ "..... ..#.. #.#.# .###. #.#.# ..#.. .....",
    /* + */ "..... ..#.. ..#.. ##### ..#.. ..#.. .....",
    /* , */ "..... ..... ..... ..... ..##. ..#.. .#...",
    /* - */ "..... ..... ..... ##### ..... ..... .....",
    /* . */ "..... ..... ..... ..... ..... .##.. .##..",
    /* / */ "....# ....# ...#. ..#.. .#... #.... #....",
    /* 0 */ ".###. #...# #..## #.#.# ##..# #...# .###.",
    /* 1 */ "..#.. .##.. ..#.. ..#.. ..#.. ..#.. .###.",
    /* 2 */ ".###. #...# ....# ...#. ..#.. .#... #####",
    /* 3 */ "##### ...#. ..#.. ...#. ....# #...# .###.",
    /* 4 */ "...#. ..##. .#.#. #..#. ##### ...#. ...#.",
    /* 5 */ "##### #.... ####. ....# ....# #...# .###.",
    /* 6 */ "..##. .#... #.... ####. #...# #...# .###.",
    /* 7 */ "##### ....# ...#. ..#.. .#... .#... .#...",
    /* 8 */ ".###. #...# #...# .###. #...# #...# .###.",
    /* 9 */ ".###. #...# #...# .#### ....# ...#. .##..",
    /* : */ "..... .##.. .##.. ..... .##.. .##.. .....",
    /* ; */ "..... .##.. .##.. ..... .##.. ..#.. .#...",
    /* < */ "...#. ..#.. .#... #.... .#... ..#.. ...#.",
    /* = */ "..... ..... ##### ..... ##### ..... .....",
    /* > */ ".#... ..#.. ...#. ....# ...#. ..#.. .#...",
    /* ? */ ".###. #...# ....# ...#. ..#.. ..... ..#..",
    /* @ */ ".###. #...# ....# .##.# #.#.# #.#.# .###.",
    /* A */ ".###. #...# #...# ##### #...# #...# #...#",
    /* B */ "####. #...# #...# ####. #...# #...# ####.",
    /* C */ ".###. #...# #.... #.... #.... #...# .###.",
    /* D */ "###.. #..#. #...# #...# #...# #..#. ###..",
    /* E */ "##### #.... #.... ####. #.... #.... #####",
    /* F */ "##### #.... #.... ####. #.... #.... #....",
    /* G */ ".###. #...# #.... #.### #...# #...# .####",
    /* H */ "#...# #...# #...# ##### #...# #...# #...#",
    /* I */ ".###. ..#.. ..#.. ..#.. ..#.. ..#.. .###.",
    /* J */ "..### ...#. ...#. ...#. ...#. #..#. .##..",
    /* K */ "#...# #..#. #.#.. ##... #.#.. #..#. #...#",
    /* L */ "#.... #.... #.... #.... #.... #.... #####",
    /* M */ "#...# ##.## #.#.# #.#.# #...# #...# #...#",
    /* N */ "#...# #...# ##..# #.#.# #..## #...# #...#",
    /* O */ ".###. #...# #...# #...# #...# #...# .###.",
    /* P */ "####. #...# #...# ####. #.... #.... #....",
    /* Q */ ".###. #...# #...# #...# #.#.# #..#. .##.#",
    /* R */ "####. #...# #...# ####. #.#.. #..#. #...#",
    /* S */ ".#### #.... #.... .###. ....# ....# ####.",
    /* T */ "##### ..#.. ..#.. ..#.. ..#.. ..#.. ..#..",
    /* U */ "#...# #...# #...# #...# #...# #...# .###.",
    /* V */ "#...# #...# #...# #...# #...# .#.#. ..#..",
    /* W */ "#...# #...# #...# #.#.# #.#.# #.#.# .#.#.",
    /* X */ "#...# #...# .#.#. ..#.. .#.#. #...# #...#",
    /* Y */ "#...# #...# .#.#. ..#.. ..#.. ..#.. ..#..",
    /* Z */ "##### ....# ...#. ..#.. .#... #.... #####",
    /* [ */ ".###. .#... .#... .#... .#... .#... .###.",
    /* \ */ "#.... #.... .#... ..#.. ...#. ....# ....#",
    /* ] */ ".###. ...#. ...#. ...#. ...#. ...#. .###.",
    /* ^ */ "..#.. .#.#. #...# ..... ..... ..... .....",
    /* _ */ "..... ..... ..... ..... ..... ..... #####",
    /* ` */ ".#... ..#.. ..... ..... ..... ..... .....",
    /* a */ "..... ..... .###. ....# .#### #...# .####",
    /* b */ "#.... #.... #.##. ##..# #...# #...# ####.",
    /* c */ "..... ..... .###. #.... #.... #...# .###.",
    /* d */ "....# ....# .##.# #..## #...# #...# .####",
    /* e */ "..... ..... .###. #...# ##### #.... .###.",
    /* f */ "..##. .#..# .#... ###.. .#... .#... .#...",
    /* g */ ".#### #...# #...# #...# .#### ....# .###.",
    /* h */ "#.... #.... #.##. ##..# #...# #...# #...#",
    /* i */ "..#.. ..... .##.. ..#.. ..#.. ..#.. .###.",
    /* j */ "...#. ..... ..##. ...#. ...#. #..#. .##..",
    /* k */ "#.... #.... #..#. #.#.. ##... #.#.. #..#.",
    /* l */ ".##.. ..#.. ..#.. ..#.. ..#.. ..#.. .###.",
    /* m */ "..... ..... ##.#. #.#.# #.#.# #...# #...#",
    /* n */ "..... ..... #.##. ##..# #...# #...# #...#",
    /* o */ "..... ..... .###. #...# #...# #...# .###.",
    /* p */ "####. #...# #...# #...# ####. #.... #....",
    /* q */ ".#### #...# #...# #...# .#### ....# ....#",
    /* r */ "..... ..... #.##. ##..# #.... #.... #....",
    /* s */ "..... ..... .###. #.... .###. ....# ####.",
    /* t */ ".#... .#... ###.. .#... .#... .#..# ..##.",
    /* u */ "..... ..... #...# #...# #...# #..## .##.#",
    /* v */ "..... ..... #...# #...# #...# .#.#. ..#..",
    /* w */ "..... ..... #...# #...# #.#.# #.#.# .#.#.",
    /* x */ "..... ..... #...# .#.#. ..#.. .#.#. #...#",
    /* y */ "#...# #...# #...# #...# .#### ....# .###.",
    /* z */ "..... ..... ##### ...#. ..#.. .#... #####",
    /* { */ "...#. ..#.. ..#.. .#... ..#.. ..#.. ...#.",
    /* | */ "..#.. ..#.. ..#.. ..#.. ..#.. ..#.. ..#..",
    /* } */ ".#... ..#.. ..#.. ...#. ..#.. ..#.. .#...",
    /* ~ */ "..... ..... .#... #.#.# ...#. ..... .....",
};
static const char *const box_art = "##### #...# #...# #...# #...# #...# #####";

static uint8_t font[96][WALK_FONT_H]; /* [95] = the box */
static bool font_ready;

static void art_to_bytes(const char *art, uint8_t *rows)
{
    for (int r = 0; r < WALK_FONT_H; r++) {
        uint8_t b = 0;
        for (int c = 0; c < WALK_FONT_W; c++)
            if (art[r * (WALK_FONT_W + 1) + c] == '#') b |= (uint8_t)(1u << (WALK_FONT_W - 1 - c));
        rows[r] = b;
    }
}

const uint8_t *walk_font_glyph(unsigned char c)
{
    if (!font_ready) {
        for (int i = 0; i < 95; i++) art_to_bytes(glyph_art[i], font[i]);
        art_to_bytes(box_art, font[95]);
        font_ready = true;
    }
    return (c >= 32 && c <= 126) ? font[c - 32] : font[95];
}

/* Text into an image of row stride `stride` pixels, clipped to [0, w) x [0, h). */
static int draw_text(uint8_t *rgba, int stride, int w, int h, int x, int y, int scale, const char *s,
                     const uint8_t color[4])
{
    if (scale < 1) scale = 1;
    int n = 0;
    for (; s[n]; n++) {
        const uint8_t *g = walk_font_glyph((unsigned char)s[n]);
        bool descender = s[n] == 'g' || s[n] == 'p' || s[n] == 'q' || s[n] == 'y';
        int cx = x + n * WALK_CELL_W * scale, cy = y + (descender ? 3 : 1) * scale;
        for (int r = 0; r < WALK_FONT_H; r++)
            for (int c = 0; c < WALK_FONT_W; c++) {
                if (!(g[r] & (1u << (WALK_FONT_W - 1 - c)))) continue;
                for (int sy = 0; sy < scale; sy++)
                    for (int sx = 0; sx < scale; sx++) {
                        long px = (long)cx + (long)c * scale + sx, py = (long)cy + (long)r * scale + sy;
                        if (px < 0 || py < 0 || px >= w || py >= h) continue;
                        memcpy(rgba + 4 * ((size_t)py * (size_t)stride + (size_t)px), color, 4);
                    }
            }
    }
    return n * WALK_CELL_W * scale;
}

int walk_hud_text(uint8_t *rgba, int w, int h, int x, int y, int scale, const char *s, const uint8_t color[4])
{
    return draw_text(rgba, w, w, h, x, y, scale, s, color);
}

void walk_hud_compose(uint8_t *rgba, int w, int h, int scale, const char *const *lines, int n, int *used_w,
                      int *used_h)
{
    static const uint8_t bg[4] = {16, 16, 20, 255}, fg[4] = {255, 250, 200, 255};
    if (scale < 1) scale = 1;
    size_t cols = 0;
    for (int i = 0; i < n; i++) cols = strlen(lines[i]) > cols ? strlen(lines[i]) : cols;
    long pw = (long)cols * WALK_CELL_W * scale + 2 * WALK_HUD_PAD, ph = (long)n * WALK_CELL_H * scale + 2 * WALK_HUD_PAD;
    if (pw > w) pw = w;
    if (ph > h) ph = h;
    for (long y = 0; y < ph; y++)
        for (long x = 0; x < pw; x++) memcpy(rgba + 4 * ((size_t)y * (size_t)w + (size_t)x), bg, 4);
    for (int i = 0; i < n; i++)
        draw_text(rgba, w, (int)pw, (int)ph, WALK_HUD_PAD, WALK_HUD_PAD + i * WALK_CELL_H * scale, scale, lines[i], fg);
    *used_w = (int)pw;
    *used_h = (int)ph;
}

/* ---------------------------------------------------------------- GPU overlay */

struct walk_hud {
    prw_gpu_image img;
    int w, h, scale;
    int used_w, used_h;
    uint8_t *pixels;
};

bool walk_hud_create(prw_gpu *gpu, int max_cols, int max_lines, int scale, walk_hud **out, prw_error *e)
{
    *out = NULL;
    walk_hud *h = prw_calloc(1, sizeof *h);
    h->scale = scale < 1 ? 1 : scale;
    h->w = max_cols * WALK_CELL_W * h->scale + 2 * WALK_HUD_PAD;
    h->h = max_lines * WALK_CELL_H * h->scale + 2 * WALK_HUD_PAD;
    h->pixels = prw_calloc((size_t)h->w * (size_t)h->h, 4);
    prw_image_desc d = {.width = (uint32_t)h->w, .height = (uint32_t)h->h, .format = VK_FORMAT_R8G8B8A8_UNORM,
                        .usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
    if (!prw_image_create(gpu, &d, &h->img, e)) {
        free(h->pixels);
        free(h);
        return prw_fail_wrap(e, "walk HUD: overlay image");
    }
    *out = h;
    return true;
}

void walk_hud_destroy(prw_gpu *gpu, walk_hud *h)
{
    if (!h) return;
    prw_image_destroy(gpu, &h->img);
    free(h->pixels);
    free(h);
}

bool walk_hud_upload(prw_gpu *gpu, walk_hud *h, const char *const *lines, int n, prw_error *e)
{
    memset(h->pixels, 0, (size_t)h->w * (size_t)h->h * 4);
    walk_hud_compose(h->pixels, h->w, h->h, h->scale, lines, n, &h->used_w, &h->used_h);
    return prw_image_upload(gpu, &h->img, 0, h->pixels, (size_t)h->w * (size_t)h->h * 4, e);
}

void walk_hud_record(VkCommandBuffer cmd, walk_hud *h, prw_gpu_image *target)
{
    int w = h->used_w < (int)target->width ? h->used_w : (int)target->width;
    int ht = h->used_h < (int)target->height ? h->used_h : (int)target->height;
    if (w <= 0 || ht <= 0) return;
    prw_cmd_transition(cmd, &h->img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    if (target->layout != VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL) {
        prw_cmd_transition(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    } else { /* write-after-write on the target: the scene blit, then this one */
        VkImageMemoryBarrier2 b = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
            .srcStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
            .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
            .dstStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
            .dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
            .oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .image = target->image,
            .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
        };
        VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .imageMemoryBarrierCount = 1,
                                .pImageMemoryBarriers = &b};
        vkCmdPipelineBarrier2(cmd, &dep);
    }
    VkImageBlit2 region = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_BLIT_2,
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .srcOffsets = {{0, 0, 0}, {w, ht, 1}},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstOffsets = {{0, 0, 0}, {w, ht, 1}},
    };
    VkBlitImageInfo2 info = {
        .sType = VK_STRUCTURE_TYPE_BLIT_IMAGE_INFO_2,
        .srcImage = h->img.image,
        .srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
        .dstImage = target->image,
        .dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
        .regionCount = 1,
        .pRegions = &region,
        .filter = VK_FILTER_NEAREST,
    };
    vkCmdBlitImage2(cmd, &info);
}

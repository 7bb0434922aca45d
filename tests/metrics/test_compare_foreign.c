/* test_compare_foreign — `prw compare` on images other tools wrote (issue "Real inputs and
 * hardening", must-show 1): EXRs written with the OpenEXR C API and no prw attributes (half
 * floats, no chromaticities, no prw:ev100), and PNG pairs written with libpng.  No flags needed:
 * the EXR exposure is derived from the reference and printed, and passing the printed value as
 * --ev100 reproduces every figure; PNGs are compared as display values (LDR-FLIP on the
 * sRGB-decoded values, RMSE/PSNR on the same linear display values, checked in closed form). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "exr_gen.h"
#include "prw_test.h"

#define W 64
#define H 48

/* Runs prw with args; stdout into out (cap bytes), stderr into err; returns the exit code. */
static int run(const char *args, char *out, size_t cap, char *err, size_t ecap)
{
    char cmd[4096], errf[1200];
    snprintf(errf, sizeof errf, "%s", prw_test_path("stderr.txt"));
    snprintf(cmd, sizeof cmd, "'%s' %s 2>'%s'", PRW_EXE, args, errf);
    FILE *p = popen(cmd, "r");
    size_t n = 0;
    if (p) {
        for (size_t r; n + 1 < cap && (r = fread(out + n, 1, cap - 1 - n, p)) > 0;) n += r;
        out[n] = '\0';
    }
    int st = p ? pclose(p) : -1;
    FILE *f = fopen(errf, "r");
    size_t m = f ? fread(err, 1, ecap - 1, f) : 0;
    err[m] = '\0';
    if (f) fclose(f);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The table rows and distributions: everything from the "metric" header on. */
static const char *metrics_part(const char *out) { return strstr(out, "  metric "); }

/* ---- EXR as another renderer writes it ---- */

static const float k_a = 2.0f, k_b = 32.0f; /* checkerboard luminances (exact in half) */

static float checker(int x, int y, char c, void *u)
{
    (void)c;
    float v = ((x / 4 + y / 4) % 2) ? k_b : k_a;
    if (u && x >= W / 2 && y >= H / 2) v *= 1.25f; /* the test image: one quadrant brighter */
    return c == 'A' ? 1.0f : v;
}

static bool write_exr(const char *path, bool test_image)
{
    exr_gen_opts o = {.width = W, .height = H, .type = EXR_PIXEL_HALF, .channels = "RGB",
                      .compression = EXR_COMPRESSION_PIZ};
    uint8_t *bytes = NULL;
    size_t size = 0;
    char err[256];
    if (!exr_gen_write(&o, checker, test_image ? (void *)1 : NULL, &bytes, &size, err, sizeof err)) {
        fprintf(stderr, "exr_gen_write: %s\n", err);
        return false;
    }
    prw_test_write_file(path, bytes, size);
    free(bytes);
    return true;
}

static void test_exr_without_attributes(void)
{
    char ref[1100], tst[1100];
    snprintf(ref, sizeof ref, "%s", prw_test_path("foreign-ref.exr"));
    snprintf(tst, sizeof tst, "%s", prw_test_path("foreign-test.exr"));
    CHECK(write_exr(ref, false) && write_exr(tst, true));
    static char out[65536], out2[65536], err[4096];
    char args[4096];
    snprintf(args, sizeof args, "compare '%s' '%s'", ref, tst);
    int rc = run(args, out, sizeof out, err, sizeof err);
    printf("%s", out);
    CHECK_MSG(rc == 0, "rc %d, stderr %s", rc, err);
    /* the rule, in closed form: L_avg = sqrt((a + d)(b + d)) over the checkerboard */
    double la = sqrt((k_a + 1e-6) * (k_b + 1e-6));
    double expect = round(log2(la / (1.2 * 0.18)) * 1e4) / 1e4;
    const char *at = strstr(out, "EV100 ");
    double ev = at ? atof(at + 6) : NAN;
    CHECK_MSG(fabs(ev - expect) < 1e-9, "EV100 %.4f, expected %.4f", ev, expect);
    CHECK(strstr(out, "derived: REF has no prw:ev100") != NULL);
    /* --ev100 with the printed value reproduces every figure */
    snprintf(args, sizeof args, "compare '%s' '%s' --ev100 %.4f", ref, tst, ev);
    rc = run(args, out2, sizeof out2, err, sizeof err);
    CHECK_MSG(rc == 0, "rc %d, stderr %s", rc, err);
    const char *m1 = metrics_part(out), *m2 = metrics_part(out2);
    CHECK(m1 && m2);
    if (m1 && m2) CHECK_MSG(strcmp(m1, m2) == 0, "figures differ:\n%s\n---\n%s", m1, m2);
    CHECK(strstr(out2, "(--ev100)") != NULL);
    snprintf(args, sizeof args, "compare '%s' '%s' --json", ref, tst);
    rc = run(args, out2, sizeof out2, err, sizeof err);
    CHECK(rc == 0 && strstr(out2, "\"ev100_source\":\t\"derived") && strstr(out2, "\"reference_log_average_cd_m2\""));
}

/* ---- PNG as another tool writes it (libpng, 8-bit) ---- */

static bool write_png(const char *path, int color_type, int channels, const uint8_t *px)
{
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        return false;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, W, H, 8, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (int y = 0; y < H; y++) png_write_row(png, px + (size_t)y * W * channels);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return fclose(f) == 0;
}

static double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }

static void test_png_pairs(void)
{
    static uint8_t a[W * H * 3], b[W * H * 3], g[W * H * 2];
    memset(a, 128, sizeof a);
    memset(b, 130, sizeof b);
    for (int i = 0; i < W * H; i++) g[2 * i] = 128, g[2 * i + 1] = 7; /* grey + alpha: alpha is ignored */
    char pa[1100], pb[1100], pg[1100];
    snprintf(pa, sizeof pa, "%s", prw_test_path("a.png"));
    snprintf(pb, sizeof pb, "%s", prw_test_path("b.png"));
    snprintf(pg, sizeof pg, "%s", prw_test_path("g.png"));
    CHECK(write_png(pa, PNG_COLOR_TYPE_RGB, 3, a) && write_png(pb, PNG_COLOR_TYPE_RGB, 3, b) &&
          write_png(pg, PNG_COLOR_TYPE_GRAY_ALPHA, 2, g));
    static char out[65536], err[4096];
    char args[4096];
    snprintf(args, sizeof args, "compare '%s' '%s'", pa, pb);
    int rc = run(args, out, sizeof out, err, sizeof err);
    printf("%s", out);
    CHECK_MSG(rc == 0, "rc %d, stderr %s", rc, err);
    char na[64];
    snprintf(na, sizeof na, "  %-22s %14s\n", "HDR-FLIP (mean)", "n/a");
    CHECK(strstr(out, "inputs: PNG display values") && strstr(out, na));
    /* closed form on the linear display values: every pixel differs by decode(130/255) - decode(128/255) */
    double d = srgb_decode(130.0 / 255) - srgb_decode(128.0 / 255);
    const char *r = strstr(out, "RMSE ");
    double rmse = r ? atof(r + 5) : NAN;
    CHECK_NEAR(rmse, d, 1e-5 * d + 1e-7);
    const char *ps = strstr(out, "PSNR (dB) ");
    double psnr = ps ? atof(ps + 10) : NAN;
    CHECK_NEAR(psnr, -20 * log10(d), 1e-3);
    const char *lf = strstr(out, "LDR-FLIP (mean) ");
    double flip = lf ? atof(lf + 16) : NAN;
    CHECK_MSG(flip > 0 && flip < 0.1, "LDR-FLIP %g", flip);
    /* a grey + alpha PNG of the same codes as a.png: identical display values */
    snprintf(args, sizeof args, "compare '%s' '%s' --json", pa, pg);
    rc = run(args, out, sizeof out, err, sizeof err);
    CHECK_MSG(rc == 0 && strstr(out, "\"rmse\":\t0,") && strstr(out, "\"hdr_flip\":\tnull"), "rc %d: %s %s", rc, out, err);
    /* an EXR against a PNG, and --ev100 with PNGs: refused with one line */
    write_exr(prw_test_path("x.exr"), false);
    snprintf(args, sizeof args, "compare '%s' '%s'", pa, prw_test_path("x.exr"));
    rc = run(args, out, sizeof out, err, sizeof err);
    CHECK_MSG(rc == 1 && strstr(err, "x.exr: an OpenEXR file, but REF") && strchr(err, '\n') == strrchr(err, '\n'), "%s", err);
    snprintf(args, sizeof args, "compare '%s' '%s' --ev100 3", pa, pb);
    rc = run(args, out, sizeof out, err, sizeof err);
    CHECK_MSG(rc == 2 && strstr(err, "--ev100: PNG inputs are display values"), "%s", err);
    prw_test_write_file(prw_test_path("t.txt"), "hello", 5);
    snprintf(args, sizeof args, "compare '%s' '%s'", prw_test_path("t.txt"), pa);
    rc = run(args, out, sizeof out, err, sizeof err);
    CHECK_MSG(rc == 1 && strstr(err, "t.txt: not an OpenEXR or PNG file"), "%s", err);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"exr_without_attributes", test_exr_without_attributes},
        {"png_pairs", test_png_pairs},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

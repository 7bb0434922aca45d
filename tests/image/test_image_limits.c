/* test_image_limits — limits before allocation in the image readers (issue "Real inputs and
 * hardening", must-show 2): a small file whose header claims a huge image is refused from the
 * header, fast and without the memory; sizes beyond the memory budget are refused with a message.
 *
 * Time and memory are measured on a child process (fork, or fork + exec of `prw compare`) with
 * wait4: CPU time (user + system, so a busy machine does not make it fail) and peak RSS. */
#define _DEFAULT_SOURCE
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include "exr_gen.h"
#include "prw_image.h"
#include "prw_test.h"

/* peak RSS means nothing under ASan (shadow memory, quarantine): checked in plain builds only */
#ifdef PRW_ASAN
#define RSS_OK(kb) ((void)(kb), 1)
#else
#define RSS_OK(kb) ((kb) < 50 * 1024)
#endif
#define CLAIM 16384            /* claimed width and height */
#define CPU_LIMIT_S 0.1

static float grey(int x, int y, char c, void *u)
{
    (void)u, (void)c;
    return (float)((x + y) % 4) * 0.25f;
}

/* Finds attribute `name` of `type` in the header and writes the box (xmin, ymin, xmax, ymax). */
static bool patch_box(uint8_t *bytes, size_t size, const char *name, const int32_t box[4])
{
    char key[64];
    int n = snprintf(key, sizeof key, "%s%cbox2i", name, 0) + 1;
    for (size_t i = 0; i + (size_t)n + 4 + 16 <= size; i++)
        if (memcmp(bytes + i, key, (size_t)n) == 0) {
            memcpy(bytes + i + n + 4, box, 16);
            return true;
        }
    return false;
}

/* A valid 4x4 EXR (written by the OpenEXR C API, no prw attributes) whose data and display windows
 * are then patched to claim CLAIM x CLAIM pixels: what a truncated or hostile file looks like. */
static bool write_claiming_exr(const char *path, exr_compression_t comp, bool tiled, size_t *size_out)
{
    exr_gen_opts o = {.width = 4, .height = 4, .type = EXR_PIXEL_HALF, .channels = "RGBA", .tiled = tiled,
                      .tile_w = 4, .tile_h = 4, .compression = comp};
    uint8_t *bytes = NULL;
    size_t size = 0;
    char err[256];
    if (!exr_gen_write(&o, grey, NULL, &bytes, &size, err, sizeof err)) {
        fprintf(stderr, "exr_gen_write: %s\n", err);
        return false;
    }
    const int32_t box[4] = {0, 0, CLAIM - 1, CLAIM - 1};
    bool ok = patch_box(bytes, size, "dataWindow", box) && patch_box(bytes, size, "displayWindow", box);
    if (ok) prw_test_write_file(path, bytes, size);
    free(bytes);
    if (size_out) *size_out = size;
    return ok;
}

typedef struct child_cost {
    int status;
    double cpu_s;
    long maxrss_kb;
} child_cost;

static void wait_child(pid_t pid, child_cost *c)
{
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    c->status = -1;
    if (wait4(pid, &c->status, 0, &ru) != pid) return;
    c->cpu_s = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
               1e-6 * (double)ru.ru_stime.tv_usec;
    c->maxrss_kb = ru.ru_maxrss;
}

/* Reads path with prw_exr_read in a child; exit 0 = refused with the path and "header" in the message. */
static child_cost read_in_child(const char *path)
{
    child_cost c = {0};
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        prw_image img;
        prw_error e = {{0}};
        bool ok = prw_exr_read(path, NULL, &img, &e);
        if (!ok) printf("    refused: %s\n", e.msg);
        fflush(stdout);
        _exit(!ok && strstr(e.msg, path) && strstr(e.msg, "header") && !img.rgba ? 0 : 1);
    }
    wait_child(pid, &c);
    return c;
}

static void test_exr_claim_every_compression(void)
{
    static const struct {
        exr_compression_t c;
        bool tiled;
        const char *name;
    } kinds[] = {{EXR_COMPRESSION_NONE, false, "none"},   {EXR_COMPRESSION_RLE, false, "rle"},
                 {EXR_COMPRESSION_ZIPS, false, "zips"},   {EXR_COMPRESSION_ZIP, false, "zip"},
                 {EXR_COMPRESSION_PIZ, false, "piz"},     {EXR_COMPRESSION_PXR24, false, "pxr24"},
                 {EXR_COMPRESSION_B44, false, "b44"},     {EXR_COMPRESSION_B44A, false, "b44a"},
                 {EXR_COMPRESSION_ZIP, true, "zip-tiled"}, {EXR_COMPRESSION_NONE, true, "none-tiled"}};
    for (size_t k = 0; k < PRW_ARRAY_LEN(kinds); k++) {
        char name[64];
        snprintf(name, sizeof name, "claim-%s.exr", kinds[k].name);
        const char *path = prw_test_path(name);
        size_t size = 0;
        CHECK(write_claiming_exr(path, kinds[k].c, kinds[k].tiled, &size));
        child_cost c = read_in_child(path);
        printf("  %-10s %zu bytes claiming %dx%d: exit %d, CPU %.3f s, peak RSS %ld KiB\n", kinds[k].name, size, CLAIM,
               CLAIM, WIFEXITED(c.status) ? WEXITSTATUS(c.status) : -1, c.cpu_s, c.maxrss_kb);
        CHECK_MSG(WIFEXITED(c.status) && WEXITSTATUS(c.status) == 0, "%s not refused from its header", name);
        CHECK_MSG(c.cpu_s < CPU_LIMIT_S, "%s: %.3f s CPU", name, c.cpu_s);
        CHECK_MSG(RSS_OK(c.maxrss_kb), "%s: peak RSS %ld KiB", name, c.maxrss_kb);
    }
}

/* The same through the command line: `prw compare claim.exr claim.exr`. */
static void test_compare_cli_claim(void)
{
#ifdef PRW_EXE
    /* as prw writes it (float RGBA, ZIP, chromaticities): 4x4, then the windows patched */
    const char *path = prw_test_path("claim-cli.exr");
    prw_error e = {{0}};
    prw_image small;
    CHECK_OK(prw_image_alloc(&small, 4, 4, &e), &e);
    CHECK_OK(prw_exr_write(path, &small, NULL, 0, &e), &e);
    prw_image_free(&small);
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &bytes, &size, &e), &e);
    const int32_t box[4] = {0, 0, CLAIM - 1, CLAIM - 1};
    CHECK(patch_box((uint8_t *)bytes, size, "dataWindow", box) && patch_box((uint8_t *)bytes, size, "displayWindow", box));
    prw_test_write_file(path, bytes, size);
    free(bytes);
    int errpipe[2];
    CHECK(pipe(errpipe) == 0);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(errpipe[1], 2);
        close(errpipe[0]);
        execl(PRW_EXE, PRW_EXE, "compare", path, path, (char *)NULL);
        _exit(127);
    }
    close(errpipe[1]);
    char err[2048] = "";
    size_t n = 0;
    for (ssize_t r; n + 1 < sizeof err && (r = read(errpipe[0], err + n, sizeof err - 1 - n)) > 0;) n += (size_t)r;
    err[n] = '\0';
    close(errpipe[0]);
    child_cost c;
    wait_child(pid, &c);
    int lines = 0;
    for (const char *p = err; *p; p++) lines += *p == '\n';
    printf("  prw compare on a %zu-byte file claiming %dx%d: exit %d, CPU %.3f s, peak RSS %ld KiB\n  stderr: %s", size,
           CLAIM, CLAIM, WIFEXITED(c.status) ? WEXITSTATUS(c.status) : -1, c.cpu_s, c.maxrss_kb, err);
    CHECK(WIFEXITED(c.status) && WEXITSTATUS(c.status) == 1);
    CHECK_MSG(lines == 1 && strstr(err, path) && strstr(err, "header"), "%s", err);
    CHECK_MSG(c.cpu_s < CPU_LIMIT_S, "%.3f s CPU", c.cpu_s);
    CHECK_MSG(RSS_OK(c.maxrss_kb), "peak RSS %ld KiB", c.maxrss_kb);
#else
    printf("  prw not built: skipped\n");
#endif
}

/* Sizes the file could hold but the budget cannot: refused with a message, smaller ones read. */
static void test_exr_memory_budget(void)
{
    prw_error e = {{0}};
    const char *path = prw_test_path("budget.exr");
    exr_gen_opts o = {.width = 1024, .height = 1024, .type = EXR_PIXEL_HALF, .channels = "RGB",
                      .compression = EXR_COMPRESSION_ZIP};
    uint8_t *bytes = NULL;
    size_t size = 0;
    char err[256];
    CHECK(exr_gen_write(&o, grey, NULL, &bytes, &size, err, sizeof err));
    prw_test_write_file(path, bytes, size);
    free(bytes);
    prw_image img;
    prw_mem_set_budget((uint64_t)8 << 20); /* 8 MiB < 16 MiB of RGBA float */
    CHECK(!prw_exr_read(path, NULL, &img, &e) && !img.rgba);
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "memory budget of 8.00 MiB") && strstr(e.msg, "--max-memory"), "%s",
              e.msg);
    printf("  %s\n", e.msg);
    CHECK(!prw_image_alloc(&img, 1024, 1024, &e) && strstr(e.msg, "memory budget"));
    prw_mem_set_budget((uint64_t)64 << 20);
    CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
    CHECK(img.width == 1024 && img.height == 1024);
    prw_image_free(&img);
    /* what the caller allocates per pixel counts too (an environment map's tables) */
    prw_exr_read_opts ro = {.extra_bytes_per_pixel = 64};
    CHECK(!prw_exr_read(path, &ro, &img, &e) && strstr(e.msg, "memory budget"));
    prw_mem_set_budget(0);
    CHECK(prw_mem_budget() > 0);
}

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24), p[1] = (uint8_t)(v >> 16), p[2] = (uint8_t)(v >> 8), p[3] = (uint8_t)v;
}

/* A valid 4x4 PNG with IHDR patched (CRC fixed) to claim CLAIM x CLAIM: refused before decoding. */
static void test_png_claim(void)
{
    prw_error e = {{0}};
    const char *path = prw_test_path("claim.png");
    uint8_t px[4 * 4 * 3];
    memset(px, 128, sizeof px);
    CHECK_OK(prw_png_write8(path, 4, 4, 3, px, &e), &e);
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &bytes, &size, &e), &e);
    uint8_t *b = (uint8_t *)bytes;
    CHECK(size > 33 && memcmp(b + 12, "IHDR", 4) == 0);
    put_be32(b + 16, CLAIM);
    put_be32(b + 20, CLAIM);
    put_be32(b + 29, (uint32_t)crc32(0, b + 12, 17));
    prw_test_write_file(path, bytes, size);
    free(bytes);
    int w, h;
    uint8_t *pixels = NULL;
    double t0 = prw_now();
    CHECK(!prw_png_read8(path, &w, &h, &pixels, &e) && !pixels);
    printf("  %zu-byte PNG claiming %dx%d: %s (%.4f s)\n", size, CLAIM, CLAIM, e.msg, prw_now() - t0);
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "IHDR") && strstr(e.msg, "bytes"), "%s", e.msg);
}

int main(int argc, char **argv)
{
    signal(SIGPIPE, SIG_IGN);
    static const prw_test_case cases[] = {
        {"exr_claim_every_compression", test_exr_claim_every_compression},
        {"compare_cli_claim", test_compare_cli_claim},
        {"exr_memory_budget", test_exr_memory_budget},
        {"png_claim", test_png_claim},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

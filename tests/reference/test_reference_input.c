/* Bad input: unknown camera, absurd sample counts and tiles, filter spellings, malformed .acc files
 * (truncated, wrong magic, mismatched sizes, corrupt payload), merge mismatches, and a fuzz-style
 * replay of deterministic mutations of a valid .acc through the reader. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include "prw_image.h"
#include "prw_test.h" /* PRW_ASAN */

/* peak RSS means nothing under ASan (shadow memory, quarantine): checked in plain builds only */
#ifdef PRW_ASAN
#define RSS_OK(kb) ((void)(kb), 1)
#else
#define RSS_OK(kb) ((kb) < 50 * 1024)
#endif

#include "ref_scenes.h"

static prw_scene *tiny_scene(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    int m = lambert_material(s, "floor", 0.5, 0);
    CHECK(prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(5, 0, 0), prw_v3(0, 0, -5), m, &e) >= 0);
    prw_camera c;
    memset(&c, 0, sizeof c);
    snprintf(c.name, sizeof c.name, "main");
    c.yfov = 0.8;
    c.znear = 0.05;
    prw_node n = prw_node_look_at("main", prw_v3(0, 1, 0), prw_v3(0, 0, 0), prw_v3(0, 0, -1));
    c.node = prw_scene_add_node(s, &n);
    s->nodes[c.node].camera = 0;
    prw_scene_add_camera(s, &c);
    s->environment.present = true;
    s->environment.uniform[0] = s->environment.uniform[1] = s->environment.uniform[2] = 10;
    snprintf(s->source, sizeof s->source, "tiny.json");
    prw_scene_update(s);
    return s;
}

static void expect_msg(bool ok, const prw_error *e, const char *n1, const char *n2)
{
    CHECK_MSG(!ok, "expected failure (%s)", n1);
    if (ok) return;
    if (getenv("PRW_TEST_VERBOSE")) printf("  error: %s\n", e->msg);
    CHECK_MSG(strstr(e->msg, n1) != NULL, "'%s' lacks '%s'", e->msg, n1);
    if (n2) CHECK_MSG(strstr(e->msg, n2) != NULL, "'%s' lacks '%s'", e->msg, n2);
    CHECK_MSG(strchr(e->msg, '\n') == NULL, "'%s' is not one line", e->msg);
}

static void test_render_args(void)
{
    prw_scene *s = tiny_scene();
    prw_error e;
    prw_view v;
    expect_msg(prw_ref_view_for_camera(s, "nope", 16, 16, &v, &e), &e, "tiny.json: no camera named 'nope'", "'main'");
    CHECK_OK(prw_ref_view_for_camera(s, "main", 8, 8, &v, &e), &e);
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 1, &r, &e), &e);
    prw_ref_acc acc;
    prw_ref_desc d = {.s0 = 0, .s1 = 0};
    expect_msg(prw_ref_render(r, &v, &d, &acc, NULL, &e), &e, "sample range", "1..10000000");
    d.s1 = 10000001;
    expect_msg(prw_ref_render(r, &v, &d, &acc, NULL, &e), &e, "sample range", NULL);
    d.s0 = 5, d.s1 = 3;
    expect_msg(prw_ref_render(r, &v, &d, &acc, NULL, &e), &e, "sample range", NULL);
    d.s0 = 0, d.s1 = 1, d.x0 = 2, d.x1 = 9, d.y1 = 4;
    expect_msg(prw_ref_render(r, &v, &d, &acc, NULL, &e), &e, "tile 2,0,9,4", "outside");
    d.x0 = 4, d.x1 = 4;
    expect_msg(prw_ref_render(r, &v, &d, &acc, NULL, &e), &e, "tile", "empty");
    prw_ref_filter f;
    expect_msg(prw_ref_filter_parse("direkt", &f, &e), &e, "filter 'direkt'", "depth:N");
    expect_msg(prw_ref_filter_parse("depth:", &f, &e), &e, "filter 'depth:'", NULL);
    expect_msg(prw_ref_filter_parse("depth:-1", &f, &e), &e, "filter", NULL);
    expect_msg(prw_ref_filter_parse("maxdepth:2x", &f, &e), &e, "filter", NULL);
    CHECK(prw_ref_filter_parse("depth:3", &f, &e) && f.kind == PRW_REF_DEPTH && f.depth == 3);
    /* time limit: stops after whole batches and records the real sample count */
    prw_ref_desc dt = {.s0 = 0, .s1 = 10000000, .seed = 1, .time_limit_s = 0.2};
    prw_ref_stats st;
    CHECK_OK(prw_ref_render(r, &v, &dt, &acc, &st, &e), &e);
    printf("  time limit 0.2 s: %llu spp in %.3f s\n", (unsigned long long)st.spp, st.seconds);
    CHECK(st.time_limited && st.spp >= 1 && st.spp < 10000000 && acc.s1 - acc.s0 == st.spp);
    CHECK(st.seconds < 2.0);
    prw_ref_acc_free(&acc);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

/* A valid accumulation of the tiny scene (8x6 image, tile 1,1,5,4, samples [2, 6)). */
static bool make_acc(prw_ref_acc *acc, uint64_t seed, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, uint64_t s0,
                     uint64_t s1)
{
    prw_scene *s = tiny_scene();
    prw_error e;
    prw_view v;
    bool ok = prw_ref_view_for_camera(s, NULL, 8, 6, &v, &e);
    prw_ref_renderer *r = NULL;
    ok = ok && prw_ref_create(s, v.eye, 1, &r, &e);
    prw_ref_desc d = {.x0 = x0, .y0 = y0, .x1 = x1, .y1 = y1, .s0 = s0, .s1 = s1, .seed = seed};
    ok = ok && prw_ref_render(r, &v, &d, acc, NULL, &e);
    CHECK_MSG(ok, "%s", e.msg);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
    return ok;
}

static void test_acc_files(void)
{
    prw_ref_acc a;
    if (!make_acc(&a, 9, 1, 1, 5, 4, 2, 6)) return;
    prw_error e;
    const char *path = prw_test_path("a.acc");
    CHECK_OK(prw_ref_acc_write(path, &a, &e), &e);
    char *data = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &data, &size, &e), &e);
    prw_ref_acc b;
    CHECK_OK(prw_ref_acc_read_memory(data, size, "a.acc", &b, &e), &e);
    CHECK(b.x0 == 1 && b.y1 == 4 && b.s0 == 2 && b.s1 == 6 && b.seed == 9 && b.scene_hash == a.scene_hash);
    CHECK(memcmp(a.sum, b.sum, 12 * 3 * sizeof *a.sum) == 0);
    prw_ref_acc_free(&b);

    expect_msg(prw_ref_acc_read(prw_test_path("missing.acc"), &b, &e), &e, "missing.acc", "cannot open");
    expect_msg(prw_ref_acc_read_memory(data, 100, "t.acc", &b, &e), &e, "t.acc: offset 100: truncated header", NULL);
    expect_msg(prw_ref_acc_read_memory(data, size - 1, "t.acc", &b, &e), &e, "t.acc: offset", "truncated");
    expect_msg(prw_ref_acc_read_memory(data, 3, "t.acc", &b, &e), &e, "t.acc: header: not a prw accumulation", NULL);
    char *copy = malloc(size + 8);
    memcpy(copy, data, size);
    copy[0] = 'X';
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "m.acc: header:", "wrong magic");
    memcpy(copy, data, size);
    copy[7] = '2';
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "m.acc: header:", "revision");
    memcpy(copy, data, size);
    copy[6] = '\n', copy[7] = '\r'; /* raw bytes never reach the message */
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "m.acc: header: unsupported format revision '\?\?'", NULL);
    memcpy(copy, data, size);
    copy[32] = 9; /* x1 = 9 > width 8 */
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "tile 1,1,9,4", "outside");
    memcpy(copy, data, size);
    copy[32] = 4; /* x1 = 4: the payload no longer matches the tile */
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "payload size", "does not match");
    memcpy(copy, data, size);
    copy[size - 5] ^= 0x40;
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "m.acc: payload: checksum", NULL);
    memcpy(copy, data, size);
    memset(copy + size, 0, 8);
    expect_msg(prw_ref_acc_read_memory(copy, size + 8, "m.acc", &b, &e), &e, "unexpected bytes", NULL);
    memcpy(copy, data, size);
    copy[48] = 2; /* s1 = s0 */
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "sample range", NULL);
    memcpy(copy, data, size);
    copy[80] = 99;
    expect_msg(prw_ref_acc_read_memory(copy, size, "m.acc", &b, &e), &e, "unknown filter", NULL);
    free(copy);
    free(data);

    /* merge mismatches */
    prw_ref_acc other, left, right, over;
    if (make_acc(&other, 10, 1, 1, 5, 4, 6, 8)) {
        const prw_ref_acc *in[2] = {&a, &other};
        const char *nm[2] = {"a.acc", "b.acc"};
        expect_msg(prw_ref_acc_merge(in, nm, 2, &b, &e), &e, "b.acc: merge: seed 10 differs from a.acc", NULL);
        prw_ref_acc_free(&other);
    }
    if (make_acc(&left, 9, 0, 0, 4, 6, 0, 4) && make_acc(&right, 9, 4, 0, 8, 6, 0, 4) &&
        make_acc(&over, 9, 3, 0, 8, 6, 2, 5)) {
        const prw_ref_acc *in[3] = {&left, &right, &over};
        const char *nm[3] = {"l.acc", "r.acc", "o.acc"};
        expect_msg(prw_ref_acc_merge(in, nm, 3, &b, &e), &e, "o.acc: merge: samples [2, 5) overlap", "l.acc");
        expect_msg(prw_ref_acc_merge(in, nm, 1, &b, &e), &e, "merge: 24 pixels are not covered", "4,0");
        prw_ref_acc extra;
        if (make_acc(&extra, 9, 0, 0, 2, 2, 4, 6)) {
            const prw_ref_acc *in2[3] = {&left, &right, &extra};
            expect_msg(prw_ref_acc_merge(in2, nm, 3, &b, &e), &e, "different sample counts", "2,0");
            prw_ref_acc_free(&extra);
        }
        const prw_ref_acc *in3[2] = {&left, &right};
        CHECK_OK(prw_ref_acc_merge(in3, nm, 2, &b, &e), &e);
        CHECK(b.s0 == 0 && b.s1 == 4 && b.x1 == 8 && b.y1 == 6);
        float *m = NULL;
        expect_msg(prw_ref_acc_images(&left, &m, NULL, &e), &e, "not the whole", NULL);
        prw_ref_acc_free(&b);
        other = left;
        other.width = 9;
        const prw_ref_acc *in4[2] = {&right, &other};
        expect_msg(prw_ref_acc_merge(in4, nm, 2, &b, &e), &e, "image size 9x6 differs", NULL);
        other.width = 8;
        other.filter.kind = PRW_REF_DIRECT;
        expect_msg(prw_ref_acc_merge(in4, nm, 2, &b, &e), &e, "filter 'direct' differs", NULL);
    }
    prw_ref_acc_free(&left);
    prw_ref_acc_free(&right);
    prw_ref_acc_free(&over);
    prw_ref_acc_free(&a);
}

static void put32le(char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (char)(v >> (8 * i));
}
static void put64le(char *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (char)(v >> (8 * i));
}

/* Limits before allocation: a header that claims a tile the file cannot hold is refused from the
 * header (the payload is never read), and the arrays must fit the memory budget. */
static void test_acc_limits(void)
{
    prw_ref_acc a;
    if (!make_acc(&a, 9, 1, 1, 5, 4, 2, 6)) return;
    prw_error e;
    const char *path = prw_test_path("l.acc");
    CHECK_OK(prw_ref_acc_write(path, &a, &e), &e);
    char *data = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &data, &size, &e), &e);
    /* 16384 x 16384 image, whole-image tile, consistent payload field: 24 GiB claimed by a small file */
    char hdr[136];
    memcpy(hdr, data, sizeof hdr);
    put32le(hdr + 16, 16384), put32le(hdr + 20, 16384);
    put32le(hdr + 24, 0), put32le(hdr + 28, 0), put32le(hdr + 32, 16384), put32le(hdr + 36, 16384);
    put64le(hdr + 96, (uint64_t)16384 * 16384 * 96);
    const char *big = prw_test_path("claim.acc");
    prw_test_write_file(big, hdr, sizeof hdr);
    prw_ref_acc b;
    double t0 = prw_now();
    expect_msg(prw_ref_acc_read(big, &b, &e), &e, "claim.acc: offset 136: truncated", "25769803912 expected");
    printf("  %s (%.4f s)\n", e.msg, prw_now() - t0);
    CHECK(!b.sum && !b.sq);
    prw_ref_acc left, right;
    bool have = make_acc(&left, 9, 0, 0, 4, 6, 0, 4) && make_acc(&right, 9, 4, 0, 8, 6, 0, 4);
    prw_mem_set_budget(1000);
    expect_msg(prw_ref_acc_read(path, &b, &e), &e, "l.acc: reading the accumulation needs", "memory budget of 1000 B");
    expect_msg(prw_ref_acc_read_memory(data, size, "m.acc", &b, &e), &e, "m.acc: the accumulation needs", "memory budget");
    if (have) {
        const prw_ref_acc *in[2] = {&left, &right};
        const char *nm[2] = {"l.acc", "r.acc"};
        prw_mem_set_budget(2000);
        expect_msg(prw_ref_acc_merge(in, nm, 2, &b, &e), &e, "l.acc: merging the accumulations needs", "memory budget");
        prw_mem_set_budget(0);
        CHECK_OK(prw_ref_acc_merge(in, nm, 2, &b, &e), &e);
        prw_mem_set_budget(1000);
        float *m = NULL, *v = NULL;
        expect_msg(prw_ref_acc_images(&b, &m, &v, &e), &e, "the mean and variance images need", "memory budget");
        prw_ref_acc_free(&b);
    }
    prw_mem_set_budget(0);
    CHECK(prw_ref_memory_bytes(16384, 16384, (uint64_t)16384 * 16384, true) == (uint64_t)16384 * 16384 * 144);
    prw_ref_acc_free(&left);
    prw_ref_acc_free(&right);
    prw_ref_acc_free(&a);
    free(data);
}

/* An environment map whose header claims 16384 x 16384 pixels in a few hundred bytes: the reference
 * refuses it from the header (a child process: CPU time and peak RSS measured with wait4). */
static void test_env_claim(void)
{
    prw_error e;
    const char *path = prw_test_path("env-claim.exr");
    prw_image small;
    CHECK_OK(prw_image_alloc(&small, 4, 2, &e), &e);
    CHECK_OK(prw_exr_write(path, &small, NULL, 0, &e), &e);
    prw_image_free(&small);
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &bytes, &size, &e), &e);
    const char key[] = "dataWindow\0box2i";
    for (size_t i = 0; i + sizeof key + 20 <= size; i++)
        if (memcmp(bytes + i, key, sizeof key) == 0) {
            const int32_t box[4] = {0, 0, 16383, 16383};
            memcpy(bytes + i + sizeof key + 4, box, 16);
        }
    prw_test_write_file(path, bytes, size);
    free(bytes);
    prw_scene *s = tiny_scene();
    s->environment.uniform[0] = s->environment.uniform[1] = s->environment.uniform[2] = 0;
    snprintf(s->environment.file, sizeof s->environment.file, "%s", path);
    s->environment.scale = 1;
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        prw_ref_renderer *r = NULL;
        prw_error ce;
        bool ok = prw_ref_create(s, prw_v3(0, 1, 0), 1, &r, &ce);
        printf("  %s\n", ok ? "accepted" : ce.msg);
        fflush(stdout);
        _exit(!ok && strstr(ce.msg, path) && strstr(ce.msg, "header: data window 16384x16384") ? 0 : 1);
    }
    int status = -1;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    CHECK(wait4(pid, &status, 0, &ru) == pid);
    double cpu = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
                 1e-6 * (double)ru.ru_stime.tv_usec;
    printf("  %zu-byte environment map claiming 16384x16384: CPU %.3f s, peak RSS %ld KiB\n", size, cpu, ru.ru_maxrss);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    CHECK(cpu < 0.1);
    CHECK(RSS_OK(ru.ru_maxrss));
    prw_scene_destroy(s);
}

/* Deterministic mutations (truncations, byte flips, header field splats) of a valid file: the reader
 * either accepts or fails with one line naming the file; never crashes (run under ASan in CI). */
static void test_fuzz_replay(void)
{
    prw_ref_acc a;
    if (!make_acc(&a, 3, 0, 0, 2, 2, 0, 2)) return;
    const char *path = prw_test_path("f.acc");
    prw_error e;
    CHECK_OK(prw_ref_acc_write(path, &a, &e), &e);
    prw_ref_acc_free(&a);
    char *data = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &data, &size, &e), &e);
    uint8_t *buf = malloc(size + 64);
    uint64_t rng = 0x1234567;
    int accepted = 0, rejected = 0;
    for (int it = 0; it < 20000; it++) {
        memcpy(buf, data, size);
        size_t n = size;
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint64_t x = rng >> 16;
        switch (it % 4) {
        case 0: n = (size_t)(x % (size + 33)); if (n > size) memset(buf + size, (int)(x >> 40), n - size); break;
        case 1: buf[x % size] ^= (uint8_t)(1u << ((x >> 20) % 8)); break;
        case 2: buf[(x % 136)] = (uint8_t)(x >> 24); break; /* header bytes */
        default: {
            size_t at = 16 + 4 * ((x >> 8) % 30);
            uint32_t vals[6] = {0, 1, 0xffffffffu, 0x7fffffffu, (uint32_t)(x >> 32), 8};
            uint32_t val = vals[(x >> 40) % 6];
            memcpy(buf + at, &val, 4);
        }
        }
        prw_ref_acc out;
        memset(&e, 0, sizeof e);
        if (prw_ref_acc_read_memory(buf, n, "fuzz.acc", &out, &e)) {
            accepted++;
            prw_ref_acc_free(&out);
        } else {
            rejected++;
            if (strncmp(e.msg, "fuzz.acc", 8) != 0 || strchr(e.msg, '\n')) {
                CHECK_MSG(false, "bad message '%s'", e.msg);
                break;
            }
        }
    }
    printf("  20000 mutations: %d accepted, %d rejected with a one-line message\n", accepted, rejected);
    CHECK(rejected > 15000);
    free(buf);
    free(data);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"render_args", test_render_args},
        {"acc_files", test_acc_files},
        {"acc_limits", test_acc_limits},
        {"env_claim", test_env_claim},
        {"fuzz_replay", test_fuzz_replay},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

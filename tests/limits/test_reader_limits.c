/* test_reader_limits — every text reader refuses what its bytes cannot back, before allocating
 * (issue "Real inputs and hardening", must-show 2): display and HMD profiles above their size limit,
 * camera paths, NURBS JSON models and scene manifests whose JSON tree would not fit the memory
 * budget, a NURBS net whose counts claim more points than the file holds, an environment map larger
 * than the budget.  (EXR, PNG and .acc: tests/image/test_image_limits, tests/reference; bench
 * directories: the bench_merge_* command-line cases next to this file.)
 *
 * The NURBS claim runs in a child under an address-space limit a little above its current use,
 * so an allocation for the claimed net (32 MB) aborts the child and fails the test; sanitizer
 * builds reserve huge shadow mappings, so there the limit is left out. */
#define _DEFAULT_SOURCE
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "prw_camera_path.h"
#include "prw_display.h"
#include "prw_hmd.h"
#include "prw_nurbs_json.h"
#include "prw_scene.h"
#include "prw_test.h"


static void expect(bool ok, const prw_error *e, const char *a, const char *b)
{
    CHECK_MSG(!ok, "accepted (expected '%s')", a);
    if (ok) return;
    printf("  %s\n", e->msg);
    CHECK_MSG(strstr(e->msg, a) != NULL, "'%s' lacks '%s'", e->msg, a);
    if (b) CHECK_MSG(strstr(e->msg, b) != NULL, "'%s' lacks '%s'", e->msg, b);
    CHECK_MSG(strchr(e->msg, '\n') == NULL, "'%s' is not one line", e->msg);
}

/* A valid document followed by `pad` bytes of white space. */
static void write_padded(const char *path, const char *doc, size_t pad)
{
    size_t n = strlen(doc);
    char *buf = malloc(n + pad);
    memcpy(buf, doc, n);
    memset(buf + n, ' ', pad);
    prw_test_write_file(path, buf, n + pad);
    free(buf);
}

static void test_profiles(void)
{
    prw_error e;
    static const char display[] =
        "{\"prw_display\": 1, \"name\": \"t\", \"eotf\": \"srgb\", \"peak\": 100, \"black\": 0.1, \"reflectivity\": 0,"
        " \"ambient\": 0, \"reference_white_fraction\": 1}";
    const char *p = prw_test_path("display.json");
    write_padded(p, display, 16);
    prw_display d;
    CHECK_OK(prw_display_load(p, &d, &e), &e);
    write_padded(p, display, 1u << 20);
    expect(prw_display_load(p, &d, &e), &e, "display.json: file of", "exceeds the limit of 1048576 bytes for a display profile");
    prw_hmd h;
    const char *q = prw_test_path("hmd.json");
    write_padded(q, "{}", (1u << 20) + 1);
    expect(prw_hmd_load(q, &h, &e), &e, "hmd.json: file of", "exceeds the limit of 1048576 bytes for an HMD profile");
}

static void test_camera_path_budget(void)
{
    prw_error e;
    const char *p = prw_test_path("path.json");
    static const char doc[] = "{\"prw_camera_path\": 1, \"keyframes\": ["
                              "{\"t\": 0, \"position\": [0, 1, 0], \"look_at\": [0, 1, -1]},"
                              "{\"t\": 1, \"position\": [1, 1, 0], \"look_at\": [1, 1, -1]}]}";
    write_padded(p, doc, 64 * 1024);
    prw_camera_path path;
    CHECK_OK(prw_camera_path_load(p, &path, &e), &e);
    prw_camera_path_free(&path);
    prw_mem_set_budget(1u << 20); /* 64 KiB x 48 > 1 MiB */
    expect(prw_camera_path_load(p, &path, &e), &e, "path.json: a camera path of", "memory budget of 1.00 MiB");
    prw_mem_set_budget(0);
}

/* counts [1000, 1000] (a 32 MB net) with 4 points in the file */
static const char k_claim[] = "{\"prw_nurbs\": 1, \"surfaces\": [{\"nurbs\": {\"degree\": [1, 1], \"count\": [1000, 1000],"
                              " \"knots_u\": [0, 0, 1, 1], \"knots_v\": [0, 0, 1, 1],"
                              " \"points\": [[0,0,0], [1,0,0], [0,1,0], [1,1,0]]}}]}";

#ifndef PRW_ASAN
static long vm_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0;
    if (f) {
        if (fscanf(f, "%ld", &pages) != 1) pages = 0;
        fclose(f);
    }
    return pages * sysconf(_SC_PAGESIZE);
}
#endif

static void test_nurbs_json(void)
{
    prw_error e;
    const char *p = prw_test_path("claim-nurbs.json");
    prw_test_write_file(p, k_claim, strlen(k_claim));
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
#ifndef PRW_ASAN
        struct rlimit rl = {.rlim_cur = (rlim_t)vm_bytes() + (16u << 20), .rlim_max = RLIM_INFINITY};
        setrlimit(RLIMIT_AS, &rl);
#endif
        prw_nurbs_model m;
        prw_error ce;
        bool ok = prw_nurbs_json_load(p, &m, &ce);
        printf("  %s\n", ok ? "accepted" : ce.msg);
        fflush(stdout);
        _exit(!ok && strstr(ce.msg, "claim-nurbs.json:surfaces[0].nurbs.points: expected count[0] x count[1]") ? 0 : 1);
    }
    int status = -1;
    CHECK(waitpid(pid, &status, 0) == pid);
    CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 0, "child status %d (signal %d)", status,
              WIFSIGNALED(status) ? WTERMSIG(status) : 0);
#ifdef PRW_ASAN
    printf("  (sanitizer build: no address-space limit)\n");
#endif
    prw_mem_set_budget(1u << 20);
    write_padded(p, "{\"prw_nurbs\": 1, \"surfaces\": []}", 64 * 1024);
    prw_nurbs_model m;
    expect(prw_nurbs_json_load(p, &m, &e), &e, "claim-nurbs.json: a NURBS JSON model of", "memory budget");
    prw_mem_set_budget(0);
}

static void test_manifest(void)
{
    prw_error e;
    const char *env = prw_test_path("env.exr");
    int fd = open(env, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    CHECK(fd >= 0 && ftruncate(fd, 4 << 20) == 0); /* a sparse 4 MiB file */
    if (fd >= 0) close(fd);
    const char *p = prw_test_path("scene.json");
    static const char doc[] = "{\"prw_manifest\": 1, \"environment\": {\"file\": \"env.exr\"}}";
    prw_test_write_file(p, doc, strlen(doc));
    prw_mem_set_budget(2u << 20);
    prw_scene *s = prw_scene_create();
    expect(prw_scene_load_manifest(s, p, &e), &e, "env.exr: an environment map of 4194304 bytes", "memory budget");
    write_padded(p, doc, 64 * 1024);
    expect(prw_scene_load_manifest(s, p, &e), &e, "scene.json: a scene manifest of", "memory budget");
    prw_scene_destroy(s);
    prw_mem_set_budget(0);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"profiles", test_profiles},
        {"camera_path_budget", test_camera_path_budget},
        {"nurbs_json", test_nurbs_json},
        {"manifest", test_manifest},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

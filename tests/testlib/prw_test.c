#define _POSIX_C_SOURCE 200809L
#include "prw_test.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int prw_test_failures = 0;

int prw_test_main(int argc, char **argv, const prw_test_case *cases, int count)
{
    int passed = 0, failed = 0;
    double t_all = prw_now();
    if (prw_test_light()) printf("light mode (sanitizer build or PRW_TEST_LIGHT): reduced trial counts\n");
    for (int i = 0; i < count; i++) {
        bool selected = argc <= 1;
        for (int a = 1; a < argc; a++)
            if (strcmp(argv[a], cases[i].name) == 0) selected = true;
        if (!selected) continue;
        int before = prw_test_failures;
        double t0 = prw_now();
        cases[i].fn();
        double dt = prw_now() - t0;
        bool ok = prw_test_failures == before;
        printf("%-4s %s (%.2f s)\n", ok ? "ok" : "FAIL", cases[i].name, dt);
        fflush(stdout);
        if (ok) passed++;
        else failed++;
    }
    printf("group wall time %.2f s\n", prw_now() - t_all);
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}

bool prw_test_light(void)
{
    const char *v = getenv("PRW_TEST_LIGHT");
    if (v && *v) return strcmp(v, "0") != 0;
#ifdef PRW_SANITIZE_BUILD
    return true;
#else
    return false;
#endif
}

int prw_test_scale(int n, int div)
{
    if (!prw_test_light() || div <= 1) return n;
    return n / div > 1 ? n / div : 1;
}

const char *prw_test_tmpdir(void)
{
    static char dir[512];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "prw-test-tmp-%ld", (long)getpid());
        mkdir(dir, 0755);
    }
    return dir;
}

char *prw_test_path(const char *name)
{
    static char buf[8][1024];
    static int k = 0;
    char *p = buf[k++ % 8];
    snprintf(p, sizeof buf[0], "%s/%s", prw_test_tmpdir(), name);
    return p;
}

void prw_test_write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return;
    CHECK(fwrite(data, 1, n, f) == n);
    fclose(f);
}

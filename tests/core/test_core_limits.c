/* test_core_limits — core helpers for untrusted inputs and outputs: the memory budget and its
 * parser, bounded file reads, output writability checks (nothing left behind). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "prw_test.h"

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    if (!d) return -1;
    for (struct dirent *de; (de = readdir(d));)
        if (strcmp(de->d_name, ".") && strcmp(de->d_name, "..")) n++;
    closedir(d);
    return n;
}

static void test_mem_parse(void)
{
    prw_error e;
    uint64_t v = 0;
    CHECK(prw_mem_parse("512M", &v, &e) && v == 512ull << 20);
    CHECK(prw_mem_parse("4G", &v, &e) && v == 4ull << 30);
    CHECK(prw_mem_parse("1.5GiB", &v, &e) && v == 3ull << 29);
    CHECK(prw_mem_parse("2TB", &v, &e) && v == 2ull << 40);
    CHECK(prw_mem_parse("1048576", &v, &e) && v == 1ull << 20);
    const char *bad[] = {"", "-1G", "12Q", "0", "1K", "G", "nan", "1e30", "4 G"};
    for (size_t i = 0; i < PRW_ARRAY_LEN(bad); i++)
        CHECK_MSG(!prw_mem_parse(bad[i], &v, &e) && strstr(e.msg, "--max-memory"), "'%s' accepted", bad[i]);
    char b[32];
    prw_mem_format(3ull << 29, b, sizeof b);
    CHECK(strcmp(b, "1.50 GiB") == 0);
    prw_mem_format(12, b, sizeof b);
    CHECK(strcmp(b, "12 B") == 0);
}

static void test_mem_budget(void)
{
    prw_error e;
    prw_mem_set_budget(0);
    uint64_t avail = prw_mem_budget();
    CHECK(avail > (16ull << 20)); /* a machine that runs the suite has more than 16 MiB free */
    CHECK(strcmp(prw_mem_budget_source(), "available memory") == 0);
    prw_mem_set_budget(100ull << 20);
    CHECK(prw_mem_budget() == 100ull << 20);
    CHECK(prw_mem_check(100ull << 20, "x", "y", &e));
    CHECK(!prw_mem_check((100ull << 20) + 1, "file.exr", "reading the image", &e));
    CHECK_MSG(strcmp(e.msg, "file.exr: reading the image needs 100.00 MiB, more than the memory budget of 100.00 MiB "
                            "(set by --max-memory)") == 0,
              "%s", e.msg);
    CHECK(!prw_mem_check(prw_mul_sat(UINT64_MAX / 2, 3), "f", "w", &e) && strstr(e.msg, "more than 16 EiB"));
    CHECK(prw_mul_sat(1ull << 32, 1ull << 32) == UINT64_MAX && prw_mul_sat(3, 4) == 12);
    CHECK(prw_add_sat(UINT64_MAX, 1) == UINT64_MAX && prw_add_sat(3, 4) == 7);
    prw_mem_set_budget(0);
}

static void test_read_bounded(void)
{
    prw_error e;
    const char *p = prw_test_path("ten.txt");
    prw_test_write_file(p, "0123456789", 10);
    char *d = NULL;
    size_t n = 0;
    CHECK_OK(prw_read_file_bounded(p, 10, 1, "a test", &d, &n, &e), &e);
    CHECK(n == 10 && d[10] == '\0' && memcmp(d, "0123456789", 10) == 0);
    free(d);
    CHECK(!prw_read_file_bounded(p, 9, 1, "a test", &d, &n, &e) && !d);
    CHECK_MSG(strstr(e.msg, "ten.txt: file of 10 bytes exceeds the limit of 9 bytes for a test"), "%s", e.msg);
    prw_mem_set_budget(2ull << 20);
    CHECK(!prw_read_file_bounded(p, 0, 1ull << 20, "a JSON document", &d, &n, &e) && !d);
    CHECK_MSG(strstr(e.msg, "ten.txt: a JSON document of 10 bytes needs up to 1048576 times its size") &&
                  strstr(e.msg, "2.00 MiB"),
              "%s", e.msg);
    prw_mem_set_budget(0);
    CHECK(!prw_read_file_bounded(prw_test_tmpdir(), 0, 1, "x", &d, &n, &e) && strstr(e.msg, "is a directory"));
    CHECK(!prw_read_file_bounded(prw_test_path("none"), 0, 1, "x", &d, &n, &e) && strstr(e.msg, "cannot open"));
    /* a pipe has no size: judged by what it delivers */
    CHECK_OK(prw_read_file_bounded("/dev/null", 5, 1, "x", &d, &n, &e), &e);
    CHECK(n == 0);
    free(d);
    CHECK(!prw_read_file_bounded("/dev/zero", 1000, 1, "a test", &d, &n, &e) && strstr(e.msg, "more than the limit of 1000"));
}

static void test_writable(void)
{
    prw_error e;
    const char *dir = prw_test_path("wdir");
    mkdir(dir, 0755);
    int before = count_entries(dir);
    char p[1200];
    snprintf(p, sizeof p, "%s/out.exr", dir);
    CHECK_OK(prw_check_writable(p, false, &e), &e);
    CHECK(count_entries(dir) == before); /* the probe is gone */
    snprintf(p, sizeof p, "%s/missing/out.exr", dir);
    CHECK(!prw_check_writable(p, false, &e) && strstr(e.msg, "missing/out.exr: cannot write: directory"));
    CHECK_OK(prw_check_writable(p, true, &e), &e); /* the command would create missing/ */
    CHECK(count_entries(dir) == before);
    /* a regular file where a directory must be */
    char f[1200];
    snprintf(f, sizeof f, "%s/file", dir);
    prw_test_write_file(f, "x", 1);
    snprintf(p, sizeof p, "%s/file/out.exr", dir);
    CHECK(!prw_check_writable(p, false, &e) && strstr(e.msg, "cannot write"));
    CHECK(!prw_check_writable(p, true, &e) && strstr(e.msg, "not a directory"));
    snprintf(p, sizeof p, "%s/file/a/b/out.exr", dir);
    CHECK(!prw_check_writable(p, true, &e) && strstr(e.msg, "not a directory"));
    CHECK(!prw_check_writable(dir, false, &e) && strstr(e.msg, "is a directory"));
    CHECK_OK(prw_check_writable(f, false, &e), &e); /* replacing an existing file is fine */
    CHECK(!prw_check_writable_dir(f, true, &e) && strstr(e.msg, "not a directory"));
    before = count_entries(dir);
    snprintf(p, sizeof p, "%s/new/sub", dir);
    CHECK_OK(prw_check_writable_dir(p, true, &e), &e);
    CHECK(count_entries(dir) == before); /* nothing created */
    CHECK_OK(prw_check_writable_dir(dir, false, &e), &e);
    CHECK(count_entries(dir) == before);
    snprintf(p, sizeof p, "%s/file/sub", dir);
    CHECK(!prw_check_writable_dir(p, true, &e) && strstr(e.msg, "not a directory"));
    snprintf(p, sizeof p, "%s/absent", dir);
    CHECK(!prw_check_writable_dir(p, false, &e) && strstr(e.msg, "cannot write"));
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"mem_parse", test_mem_parse},
        {"mem_budget", test_mem_budget},
        {"read_bounded", test_read_bounded},
        {"writable", test_writable},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

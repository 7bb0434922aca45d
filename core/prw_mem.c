/* prw_mem.c — the memory budget (prw_core.h): --max-memory, else the memory available now. */
#define _POSIX_C_SOURCE 200809L
#include "prw_core.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static uint64_t g_budget = 0; /* 0: not set */

void prw_mem_set_budget(uint64_t bytes) { g_budget = bytes; }

const char *prw_mem_budget_source(void) { return g_budget ? "--max-memory" : "available memory"; }

/* A "<key>: <n> kB" line of /proc/meminfo, in bytes; 0 when absent. */
static uint64_t meminfo(const char *key)
{
    FILE *f = fopen("/proc/meminfo", "r");
    if (!f) return 0;
    char line[256];
    uint64_t v = 0;
    size_t n = strlen(key);
    while (fgets(line, sizeof line, f))
        if (strncmp(line, key, n) == 0 && line[n] == ':') {
            unsigned long long kb = 0;
            if (sscanf(line + n + 1, "%llu", &kb) == 1) v = prw_mul_sat(kb, 1024);
            break;
        }
    fclose(f);
    return v;
}

/* One unsigned number from a small file ("max" or unreadable: 0). */
static uint64_t file_number(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    unsigned long long v = 0;
    if (fscanf(f, "%llu", &v) != 1) v = 0;
    fclose(f);
    return v;
}

/* Room left under the cgroup v2 limit of this process; UINT64_MAX when there is none. */
static uint64_t cgroup_room(void)
{
    FILE *f = fopen("/proc/self/cgroup", "r");
    if (!f) return UINT64_MAX;
    char line[1024], rel[900] = "";
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "0::", 3) == 0) {
            size_t len = strcspn(line + 3, "\n");
            if (len >= sizeof rel) len = sizeof rel - 1;
            memcpy(rel, line + 3, len);
            rel[len] = '\0';
            break;
        }
    fclose(f);
    char path[1100];
    snprintf(path, sizeof path, "/sys/fs/cgroup%s/memory.max", strcmp(rel, "/") == 0 ? "" : rel);
    uint64_t max = file_number(path);
    if (!max) return UINT64_MAX;
    snprintf(path, sizeof path, "/sys/fs/cgroup%s/memory.current", strcmp(rel, "/") == 0 ? "" : rel);
    uint64_t cur = file_number(path);
    return max > cur ? max - cur : 0;
}

uint64_t prw_mem_budget(void)
{
    if (g_budget) return g_budget;
    /* the files are read at most every 0.25 s: image allocations ask often */
    static _Thread_local double t_last = -1;
    static _Thread_local uint64_t last = 0;
    double now = prw_now();
    if (t_last >= 0 && now - t_last < 0.25) return last;
    uint64_t avail = meminfo("MemAvailable");
    if (!avail) {
        long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        avail = pages > 0 && page > 0 ? prw_mul_sat((uint64_t)pages, (uint64_t)page) : UINT64_MAX;
    }
    uint64_t room = cgroup_room();
    last = avail < room ? avail : room;
    t_last = now;
    return last;
}

bool prw_mem_parse(const char *s, uint64_t *out, prw_error *e)
{
    char *end = NULL;
    errno = 0;
    double v = s && *s != '-' ? strtod(s, &end) : NAN;
    double mult = 1;
    if (end && end != s) {
        const char *u = end;
        switch (*u) {
        case 'k': case 'K': mult = 1024.0, u++; break;
        case 'm': case 'M': mult = 1024.0 * 1024, u++; break;
        case 'g': case 'G': mult = 1024.0 * 1024 * 1024, u++; break;
        case 't': case 'T': mult = 1024.0 * 1024 * 1024 * 1024, u++; break;
        default: break;
        }
        if (mult > 1 && strcmp(u, "iB") == 0) u += 2;
        else if (strcmp(u, "B") == 0) u += 1;
        end = (char *)u;
    }
    double b = v * mult;
    if (errno || !end || end == s || *end != '\0' || !isfinite(b) || b < 1024 * 1024 || b > 9.0e18)
        return prw_fail(e, "--max-memory '%s': expected a byte count of at least 1M, e.g. 512M, 4G, 1.5GiB", s ? s : "");
    *out = (uint64_t)b;
    return true;
}

void prw_mem_format(uint64_t bytes, char *buf, size_t cap)
{
    static const char *const units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    if (bytes == UINT64_MAX) {
        snprintf(buf, cap, "more than 16 EiB");
        return;
    }
    double v = (double)bytes;
    int u = 0;
    while (v >= 1024 && u < 6) v /= 1024, u++;
    if (u == 0) snprintf(buf, cap, "%llu B", (unsigned long long)bytes);
    else snprintf(buf, cap, "%.2f %s", v, units[u]);
}

bool prw_mem_check(uint64_t bytes, const char *who, const char *what, prw_error *e)
{
    uint64_t budget = prw_mem_budget();
    if (bytes <= budget) return true;
    char need[32], have[32];
    prw_mem_format(bytes, need, sizeof need);
    prw_mem_format(budget, have, sizeof have);
    return prw_fail(e, "%s: %s needs %s, more than the memory budget of %s (%s)", who, what, need, have,
                    g_budget ? "set by --max-memory" : "available memory; see --max-memory");
}

uint64_t prw_mul_sat(uint64_t a, uint64_t b)
{
    uint64_t r;
    return __builtin_mul_overflow(a, b, &r) ? UINT64_MAX : r;
}

uint64_t prw_add_sat(uint64_t a, uint64_t b)
{
    uint64_t r;
    return __builtin_add_overflow(a, b, &r) ? UINT64_MAX : r;
}

/* What the reader fuzz targets share: the contract on a failure (one line that starts with the
 * name the reader was given) and a scratch file for readers that take a path. */
#ifndef PRW_FUZZ_COMMON_H
#define PRW_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "prw_core.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static inline void fuzz_die(const char *target, const char *what, const char *msg)
{
    fprintf(stderr, "%s: contract violated: %s: %s\n", target, what, msg);
    abort();
}

/* A failure names the input first and is one clean line (no control characters). */
static inline void fuzz_check_error(const char *target, const prw_error *e, const char *name)
{
    if (strncmp(e->msg, name, strlen(name)) != 0) fuzz_die(target, "message does not start with the input's name", e->msg);
    for (const char *p = e->msg; *p; p++)
        if ((unsigned char)*p < 0x20) fuzz_die(target, "control character in the message", e->msg);
}

static char fuzz_dir[512];
static char fuzz_names[4][64];

static void fuzz_cleanup(void)
{
    char p[sizeof fuzz_dir + sizeof fuzz_names[0] + 2];
    for (int i = 0; i < 4; i++)
        if (fuzz_names[i][0]) {
            int n = snprintf(p, sizeof p, "%s/%s", fuzz_dir, fuzz_names[i]);
            if (n > 0 && (size_t)n < sizeof p) unlink(p);
        }
    rmdir(fuzz_dir);
}

/* A directory of this process under $TMPDIR (or /tmp), made once and removed at exit; buf
 * receives "<dir>/<name>" (at most 4 names). */
static inline const char *fuzz_scratch(const char *name, char *buf, size_t cap)
{
    char *dir = fuzz_dir;
    for (int i = 0; i < 4; i++) {
        if (strcmp(fuzz_names[i], name) == 0) break;
        if (!fuzz_names[i][0]) {
            snprintf(fuzz_names[i], sizeof fuzz_names[i], "%s", name);
            break;
        }
    }
    if (!dir[0]) {
        const char *t = getenv("TMPDIR");
        snprintf(fuzz_dir, sizeof fuzz_dir, "%s/prw-fuzz-XXXXXX", t && t[0] ? t : "/tmp");
        if (!mkdtemp(fuzz_dir)) {
            perror("mkdtemp");
            abort();
        }
        atexit(fuzz_cleanup);
    }
    snprintf(buf, cap, "%s/%s", dir, name);
    return buf;
}

/* Writes data to path (replacing it). */
static inline void fuzz_write(const char *path, const uint8_t *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        perror(path);
        abort();
    }
}

#endif

/* env_corpus_gen <dir> — writes the seed corpus of fuzz_env_file: valid entries of a few sizes
 * built from synthetic maps, and damaged copies (truncated, bad checksum). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_env_file.h"

static int put(const char *dir, const char *name, const uint8_t *b, size_t n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    prw_error e;
    if (!prw_write_file_atomic(path, b, n, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: env_corpus_gen <dir>\n");
        return 2;
    }
    int bad = 0;
    const prw_env_params ps[] = {{1, 1, 1, 2}, {2, 2, 4, 3}, {4, 3, 8, 2}};
    float map[8 * 4 * 3];
    for (int k = 0; k < 8 * 4 * 3; k++) map[k] = (float)(k % 7) * 0.5f;
    for (int i = 0; i < 3; i++) {
        prw_env_data d;
        prw_error e;
        uint8_t *b;
        size_t n;
        if (!prw_env_data_build(map, 8, 4, 1.5, 0.25 * i, 42 + i, &ps[i], &d, &e) || !prw_env_encode(&d, &b, &n, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 1;
        }
        char name[64];
        snprintf(name, sizeof name, "valid_%d.env", i);
        bad |= put(argv[1], name, b, n);
        snprintf(name, sizeof name, "truncated_%d.env", i);
        bad |= put(argv[1], name, b, n / 2);
        b[n - 1] ^= 0xff;
        snprintf(name, sizeof name, "checksum_%d.env", i);
        bad |= put(argv[1], name, b, n);
        free(b);
        prw_env_data_free(&d);
    }
    return bad;
}

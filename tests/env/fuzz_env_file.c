/* fuzz_env_file — libFuzzer target for the environment cache entry reader (prw_env_decode): a
 * failure is one line starting with the name; an entry that reads has finite values and encodes
 * back to the same bytes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_env_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void die(const char *what, const char *msg)
{
    fprintf(stderr, "fuzz_env_file: contract violated: %s: %s\n", what, msg);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static bool init = false;
    if (!init) {
        prw_mem_set_budget((uint64_t)256 << 20);
        init = true;
    }
    prw_error e = {{0}};
    prw_env_data d;
    if (!prw_env_decode(data, size, "in.env", &d, &e)) {
        if (strncmp(e.msg, "in.env: ", 8) != 0) die("message does not start with the name", e.msg);
        for (const char *p = e.msg; *p; p++)
            if ((unsigned char)*p < 0x20) die("control character in the message", e.msg);
        return 0;
    }
    uint8_t *buf = NULL;
    size_t n = 0;
    if (!prw_env_encode(&d, &buf, &n, &e)) die("re-encode", e.msg);
    if (n != size || memcmp(buf, data, n) != 0) die("re-encode", "bytes differ");
    free(buf);
    prw_env_data_free(&d);
    return 0;
}

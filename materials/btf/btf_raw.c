/* btf_raw.c — the raw dump of a BTF container (prw_btf.h: prw_btf_write_raw / prw_btf_read_raw). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf.h"

#define RAW_MAGIC "PRWBTFR1"

bool prw_btf_write_raw(const char *path, const prw_btf *b, prw_error *e)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "wb");
    if (!f) return prw_fail(e, "%s: cannot create", tmp);
    uint32_t hdr[4] = {b->width, b->height, b->views, b->lights};
    size_t n = (size_t)b->width * b->height * b->views * b->lights * 3;
    bool ok = fwrite(RAW_MAGIC, 1, 8, f) == 8 && fwrite(hdr, 4, 4, f) == 4 &&
              fwrite(b->view_dirs, 4, 2 * (size_t)b->views, f) == 2 * (size_t)b->views &&
              fwrite(b->light_dirs, 4, 2 * (size_t)b->lights, f) == 2 * (size_t)b->lights && fwrite(b->rgb, 4, n, f) == n;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0) {
        remove(tmp);
        return prw_fail(e, "%s: write failed", path);
    }
    return true;
}

bool prw_btf_read_raw(const char *path, prw_btf *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open", path);
    char magic[8];
    uint32_t h[4];
    bool ok = fread(magic, 1, 8, f) == 8 && memcmp(magic, RAW_MAGIC, 8) == 0 && fread(h, 4, 4, f) == 4;
    if (!ok) {
        fclose(f);
        return prw_fail(e, "%s: byte 0 (header): not a raw BTF dump (%s and four sizes)", path, RAW_MAGIC);
    }
    if (!h[0] || !h[1] || !h[2] || !h[3] || h[0] > 65536 || h[1] > 65536 || h[2] > 65536 || h[3] > 65536) {
        fclose(f);
        return prw_fail(e, "%s: byte 8 (size): %u x %u texels, %u views, %u lights", path, h[0], h[1], h[2], h[3]);
    }
    uint64_t n = prw_mul_sat(prw_mul_sat((uint64_t)h[0] * h[1], (uint64_t)h[2] * h[3]), 3);
    uint64_t want = prw_add_sat(24 + 8 * ((uint64_t)h[2] + h[3]), prw_mul_sat(n, 4));
    long long have = (fseek(f, 0, SEEK_END) == 0) ? (long long)ftell(f) : -1;
    if (have < 0 || (uint64_t)have != want) {
        fclose(f);
        return prw_fail(e, "%s: %lld bytes where the header asks for %llu", path, have, (unsigned long long)want);
    }
    fseek(f, 24, SEEK_SET);
    if (!prw_btf_create(h[0], h[1], h[2], h[3], out, e)) {
        fclose(f);
        return false;
    }
    ok = fread(out->view_dirs, 4, 2 * (size_t)h[2], f) == 2 * (size_t)h[2] &&
         fread(out->light_dirs, 4, 2 * (size_t)h[3], f) == 2 * (size_t)h[3] && fread(out->rgb, 4, (size_t)n, f) == n;
    fclose(f);
    for (uint64_t i = 0; ok && i < n; i++) ok = isfinite(out->rgb[i]);
    for (uint64_t i = 0; ok && i < 2 * (uint64_t)h[2]; i++) ok = isfinite(out->view_dirs[i]);
    for (uint64_t i = 0; ok && i < 2 * (uint64_t)h[3]; i++) ok = isfinite(out->light_dirs[i]);
    if (!ok) {
        prw_btf_free(out);
        return prw_fail(e, "%s: short read or a value that is not finite", path);
    }
    return true;
}

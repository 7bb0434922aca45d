/* btf.c — the BTF container, the Bonn direction set, decoding the Bonn binaries and reading image
 * sets (prw_btf.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "prw_btf.h"

#define DEG (3.14159265358979323846 / 180.0)

bool prw_btf_create(uint32_t width, uint32_t height, uint32_t views, uint32_t lights, prw_btf *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (!width || !height || !views || !lights)
        return prw_fail(e, "btf: %u x %u texels, %u views, %u lights: none may be 0", width, height, views, lights);
    uint64_t n = prw_mul_sat(prw_mul_sat(prw_mul_sat(width, height), prw_mul_sat(views, lights)), 3);
    uint64_t bytes = prw_add_sat(prw_mul_sat(n, sizeof(float)), prw_mul_sat(2ull * ((uint64_t)views + lights), sizeof(float)));
    char what[128];
    snprintf(what, sizeof what, "%u x %u texels x %u x %u directions", width, height, views, lights);
    if (!prw_mem_check(bytes, "btf", what, e)) return false;
    out->width = width, out->height = height, out->views = views, out->lights = lights;
    out->view_dirs = prw_calloc(2 * (size_t)views, sizeof(float));
    out->light_dirs = prw_calloc(2 * (size_t)lights, sizeof(float));
    out->rgb = prw_calloc((size_t)n, sizeof(float));
    return true;
}

void prw_btf_free(prw_btf *b)
{
    if (!b) return;
    free(b->view_dirs);
    free(b->light_dirs);
    free(b->rgb);
    memset(b, 0, sizeof *b);
}

void prw_btf_dir_vector(float theta, float phi, double out[3])
{
    double t = theta, p = phi;
    out[0] = sin(t) * cos(p), out[1] = sin(t) * sin(p), out[2] = cos(t);
}

void prw_btf_dirs_ubo81(float *dirs)
{
    static const int count[6] = {1, 6, 12, 18, 20, 24};
    int k = 0;
    for (int ring = 0; ring < 6; ring++)
        for (int i = 0; i < count[ring]; i++, k++) {
            dirs[2 * k] = (float)(15.0 * ring * DEG);
            dirs[2 * k + 1] = (float)(360.0 / count[ring] * i * DEG);
        }
}

bool prw_btf_from_ubo(const prw_btf_ubo *u, prw_btf *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (u->channels != 3) return prw_fail(e, "btf: %u channels; only RGB BTFs are decoded", u->channels);
    if (!prw_btf_create(u->width, u->height, u->views, u->lights, out, e)) return false;
    memcpy(out->view_dirs, u->view_dirs, 2 * sizeof(float) * u->views);
    memcpy(out->light_dirs, u->light_dirs, 2 * sizeof(float) * u->lights);
    for (uint32_t v = 0; v < u->views; v++)
        for (uint32_t l = 0; l < u->lights; l++)
            for (uint32_t y = 0; y < u->height; y++)
                for (uint32_t x = 0; x < u->width; x++) {
                    double rgb[3];
                    if (!prw_btf_ubo_rgb(u, v, l, x, y, rgb, e)) {
                        prw_btf_free(out);
                        return false;
                    }
                    float *d = out->rgb + prw_btf_at(out, v, l, x, y);
                    for (int c = 0; c < 3; c++) {
                        /* a value beyond float (a decoding blow-up) would put Inf into every renderer */
                        if (!(fabs(rgb[c]) <= 3.0e38)) {
                            prw_btf_free(out);
                            return prw_fail(e, "btf: view %u light %u texel (%u, %u): value %g is not a finite float", v,
                                            l, x, y, rgb[c]);
                        }
                        d[c] = (float)rgb[c];
                    }
                }
    return true;
}

/* The image of one direction pair: "<dir>/<name>.<ext>" or "<dir>/tv<T>_pv<P>/<name>.<ext>". */
static bool find_image(const char *dir, int tl, int pl, int tv, int pv, const char *const *exts, int n, char *path,
                       size_t cap)
{
    for (int sub = 0; sub < 2; sub++)
        for (int i = 0; i < n; i++) {
            int k = sub ? snprintf(path, cap, "%s/tv%03d_pv%03d/tl%03d_pl%03d_tv%03d_pv%03d.%s", dir, tv, pv, tl, pl, tv, pv,
                                   exts[i])
                        : snprintf(path, cap, "%s/tl%03d_pl%03d_tv%03d_pv%03d.%s", dir, tl, pl, tv, pv, exts[i]);
            if (k > 0 && (size_t)k < cap && access(path, R_OK) == 0) return true;
        }
    /* not found: path receives "tl..._pv....(ext|ext) in the folder or its tv..._pv.../" for the message */
    size_t k = (size_t)snprintf(path, cap, "tl%03d_pl%03d_tv%03d_pv%03d.(", tl, pl, tv, pv);
    for (int i = 0; i < n && k < cap; i++) k += (size_t)snprintf(path + k, cap - k, "%s%s", i ? "|" : "", exts[i]);
    if (k < cap) snprintf(path + k, cap - k, ") in the folder or its tv%03d_pv%03d/", tv, pv);
    return false;
}

bool prw_btf_read_image_set(const char *dir, const char *const *exts, int n, prw_btf_image_loader load, void *user,
                            prw_btf *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    float dirs[2 * PRW_BTF_UBO81];
    prw_btf_dirs_ubo81(dirs);
    int deg[PRW_BTF_UBO81][2];
    for (uint32_t i = 0; i < PRW_BTF_UBO81; i++) {
        deg[i][0] = (int)lround(dirs[2 * i] / DEG);
        deg[i][1] = (int)lround(dirs[2 * i + 1] / DEG);
    }
    char path[4096];
    for (uint32_t v = 0; v < PRW_BTF_UBO81; v++)
        for (uint32_t l = 0; l < PRW_BTF_UBO81; l++) {
            if (!find_image(dir, deg[l][0], deg[l][1], deg[v][0], deg[v][1], exts, n, path, sizeof path)) {
                prw_btf_free(out);
                return prw_fail(e, "%s: image set: no %s (view %u, light %u of the 81 x 81 Bonn directions)", dir,
                                path, v, l);
            }
            uint32_t w = 0, h = 0;
            float *img = NULL;
            if (!load(user, path, &w, &h, &img, e)) {
                prw_btf_free(out);
                return false;
            }
            if (!out->rgb) {
                if (!prw_btf_create(w, h, PRW_BTF_UBO81, PRW_BTF_UBO81, out, e)) {
                    free(img);
                    return prw_fail_wrap(e, "%s: image set", dir);
                }
                memcpy(out->view_dirs, dirs, sizeof dirs);
                memcpy(out->light_dirs, dirs, sizeof dirs);
            } else if (w != out->width || h != out->height) {
                uint32_t w0 = out->width, h0 = out->height;
                free(img);
                prw_btf_free(out);
                return prw_fail(e, "%s: %u x %u pixels, the set's first image has %u x %u", path, w, h, w0, h0);
            }
            memcpy(out->rgb + prw_btf_at(out, v, l, 0, 0), img, sizeof(float) * 3 * (size_t)w * h);
            free(img);
        }
    return true;
}

#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "prw_bake_scene.h"
#include "prw_demo.h"

prw_global_opts g_prw_opts;

bool prw_app_load_scene(const char *path, prw_scene **out, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    bool ok = (!path || strcmp(path, "demo") == 0) ? prw_demo_build(s, prw_v3(0, 0, 0), e)
                                                  : prw_scene_load_manifest(s, path, e);
    if (ok) prw_scene_update(s);
    if (!ok) {
        prw_scene_destroy(s);
        return false;
    }
    *out = s;
    return true;
}

static void bake_progress(void *user, const char *line)
{
    (void)user;
    prw_log(PRW_LOG_INFO, "%s", line);
    fflush(stderr);
}

bool prw_app_bake_scene(prw_scene *s, prw_error *e) { return prw_bake_scene(s, bake_progress, NULL, e); }

bool prw_app_create_gpu(bool present, prw_gpu **out, prw_error *e)
{
    prw_gpu_desc d = {
        .device_index = -1,
        .validation = g_prw_opts.validation,
        .present = present,
    };
    if (g_prw_opts.device) {
        char *end;
        long idx = strtol(g_prw_opts.device, &end, 10);
        if (*end == '\0' && end != g_prw_opts.device) d.device_index = (int)idx;
        else d.device_name = g_prw_opts.device;
    }
    return prw_gpu_create(&d, out, e);
}

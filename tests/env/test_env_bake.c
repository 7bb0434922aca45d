/* prw_env_bake: the scene's environment (gi-room-sky.exr through its manifest) baked through the
 * "env" cache: a miss builds, a hit reads the same bytes, the knob and the rotation change the key;
 * the SH of the bake equals the SH of the decoded map times its scale; a uniform environment. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "prw_cache.h"
#include "prw_env_bake.h"
#include "prw_image.h"
#include "prw_test.h"

static void test_scene_bake(void)
{
    setenv("PRW_CACHE_DIR", prw_test_path("cache"), 1);
    prw_error e;
    prw_cache_clear("env", &(prw_cache_clear_report){0}, &e);
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_load_manifest(s, PRW_SOURCE_DIR "/assets/scenes/gi-room-sky.json", &e), &e);
    CHECK(s->environment.present && s->environment.file[0]);
    prw_env_data a, b;
    bool hit = true;
    char warn[2048];
    CHECK_OK(prw_env_bake(&s->environment, 16, &a, &hit, warn, sizeof warn, &e), &e);
    CHECK(!hit);
    CHECK_MSG(!warn[0], "%s", warn);
    CHECK(a.height == 16 && a.levels == PRW_ENV_DEFAULT_LEVELS && a.source_hash == s->environment.file_hash);
    CHECK_OK(prw_env_bake(&s->environment, 16, &b, &hit, warn, sizeof warn, &e), &e);
    CHECK(hit);
    CHECK(memcmp(a.maps, b.maps, (size_t)a.levels * 16 * 32 * 3 * sizeof(float)) == 0);
    prw_env_data_free(&b);
    /* the SH is the decoded map's times the scale */
    prw_image img = {0};
    CHECK_OK(prw_exr_read(s->environment.file, NULL, &img, &e), &e);
    float *rgb = prw_malloc((size_t)img.width * img.height * 3 * sizeof(float));
    for (size_t k = 0; k < (size_t)img.width * img.height; k++)
        for (int c = 0; c < 3; c++) rgb[3 * k + c] = img.rgba[4 * k + c];
    float sh[9][3];
    CHECK_OK(prw_env_sh_project(rgb, (uint32_t)img.width, (uint32_t)img.height, sh, &e), &e);
    for (int i = 0; i < 9; i++)
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(a.sh[i][c], sh[i][c] * s->environment.scale, 1e-5 * (fabs(sh[0][c]) + 1e-6));
    free(rgb);
    prw_image_free(&img);
    /* another envmap_size, another rotation: another entry */
    CHECK_OK(prw_env_bake(&s->environment, 8, &b, &hit, warn, sizeof warn, &e), &e);
    CHECK(!hit && b.height == 8);
    prw_env_data_free(&b);
    prw_environment r = s->environment;
    r.rotation += 0.5;
    CHECK_OK(prw_env_bake(&r, 16, &b, &hit, warn, sizeof warn, &e), &e);
    CHECK(!hit && b.rotation == r.rotation);
    prw_env_data_free(&b);
    prw_env_data_free(&a);
    /* a missing file: one error naming it */
    snprintf(r.file, sizeof r.file, "%s", prw_test_path("missing.exr"));
    CHECK(!prw_env_bake(&r, 16, &b, &hit, warn, sizeof warn, &e));
    CHECK(strstr(e.msg, "missing.exr") != NULL);
    r.present = false;
    CHECK(!prw_env_bake(&r, 16, &b, &hit, warn, sizeof warn, &e));
    prw_scene_destroy(s);
}

static void test_uniform(void)
{
    setenv("PRW_CACHE_DIR", prw_test_path("cache"), 1);
    prw_environment env;
    memset(&env, 0, sizeof env);
    env.present = true;
    env.uniform[0] = 100, env.uniform[1] = 200, env.uniform[2] = 50;
    prw_env_data d;
    bool hit;
    prw_error e;
    CHECK_OK(prw_env_bake(&env, 8, &d, &hit, NULL, 0, &e), &e);
    double n[3] = {0.6, 0.0, 0.8};
    float E[3];
    prw_env_sh_irradiance(d.sh, n, E);
    CHECK_NEAR(E[1], 200 * 3.14159265358979, 200 * 3.14159265358979 * 1e-4);
    for (size_t k = 0; k < (size_t)d.levels * 8 * 16; k++) CHECK(d.maps[3 * k + 2] == 50.0f);
    prw_env_data_free(&d);
}

static const prw_test_case cases[] = {{"scene_bake", test_scene_bake}, {"uniform", test_uniform}};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0])); }

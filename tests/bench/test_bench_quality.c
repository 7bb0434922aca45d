/* prw_quality: presets as points of the knob space, config and sweep parsing, knobs -> render desc. */
#include <stdlib.h>
#include <string.h>

#include "prw_quality.h"
#include "prw_test.h"

static void t_presets(void)
{
    prw_error e = {{0}};
    prw_quality lo, me, hi, ul;
    CHECK_OK(prw_quality_preset("low", &lo, &e), &e);
    CHECK_OK(prw_quality_preset("medium", &me, &e), &e);
    CHECK_OK(prw_quality_preset("high", &hi, &e), &e);
    CHECK_OK(prw_quality_preset("ultra", &ul, &e), &e);
    CHECK(lo.msaa == 1 && ul.msaa == 4);
    CHECK(lo.shadow_size < me.shadow_size && me.shadow_size < hi.shadow_size && hi.shadow_size < ul.shadow_size);
    prw_quality d = prw_quality_default();
    CHECK(memcmp(&d, &hi, sizeof d) == 0);
    CHECK(d.extra_gpu_work == 0);
    CHECK(!prw_quality_preset("extreme", &lo, &e));
    CHECK(strstr(e.msg, "preset 'extreme'") && strstr(e.msg, "low, medium, high, ultra"));
    /* every preset's knobs are in range */
    uint32_t n;
    const prw_knob_info *k = prw_quality_knobs(&n);
    const prw_quality *all[4] = {&lo, &me, &hi, &ul};
    for (int p = 0; p < 4; p++)
        for (uint32_t i = 0; i < n; i++) {
            double v = prw_quality_get(all[p], &k[i]);
            CHECK_MSG(v >= k[i].min && v <= k[i].max, "preset %d knob %s = %g", p, k[i].name, v);
        }
}

static void t_config(void)
{
    prw_error e = {{0}};
    prw_quality base = prw_quality_default(), q;
    CHECK_OK(prw_quality_parse_config("msaa=1", &base, &q, &e), &e);
    CHECK(q.msaa == 1 && q.shadow_size == base.shadow_size);
    CHECK_OK(prw_quality_parse_config("low;shadow_size=2048", &base, &q, &e), &e);
    CHECK(q.msaa == 1 && q.shadow_size == 2048);
    CHECK_OK(prw_quality_parse_config("msaa=1,shadow_size=512,extra_gpu_work=0.2", &base, &q, &e), &e);
    CHECK(q.msaa == 1 && q.shadow_size == 512 && q.extra_gpu_work == 0.2);
    CHECK(!prw_quality_parse_config("msaa=2", &base, &q, &e) && strstr(e.msg, "msaa"));
    CHECK(!prw_quality_parse_config("shadow_size=9999999", &base, &q, &e) && strstr(e.msg, "out of range"));
    CHECK(!prw_quality_parse_config("bogus=1", &base, &q, &e) && strstr(e.msg, "unknown knob 'bogus'"));
    CHECK(!prw_quality_parse_config("msaa=abc", &base, &q, &e) && strstr(e.msg, "expected a number"));
    CHECK(!prw_quality_parse_config("msaa=1;high", &base, &q, &e) && strstr(e.msg, "preset name must come first"));
    CHECK(!prw_quality_parse_config("", &base, &q, &e));
    /* format -> parse round trip */
    char buf[1024];
    q = base;
    q.ssdo_radius = 0.1;
    q.extra_gpu_work = 0.25;
    prw_quality_format(&q, buf, sizeof buf);
    prw_quality back;
    CHECK_OK(prw_quality_parse_config(buf, &base, &back, &e), &e);
    CHECK(memcmp(&q, &back, sizeof q) == 0);
    CHECK(strstr(buf, "extra_gpu_work=0.25"));
    prw_quality_format(&base, buf, sizeof buf);
    CHECK(!strstr(buf, "extra_gpu_work")); /* hidden knob only when set */
    prw_quality_format_diff(&q, &base, buf, sizeof buf);
    CHECK(strcmp(buf, "ssdo_radius=0.10000000000000001;extra_gpu_work=0.25") == 0);
}

static void t_sweep(void)
{
    prw_error e = {{0}};
    prw_quality base = prw_quality_default(), *list = NULL;
    uint32_t n = 0;
    CHECK_OK(prw_quality_parse_sweep("msaa=1,4;shadow_size=512,1024,2048", &base, &list, &n, &e), &e);
    CHECK(n == 6);
    if (n == 6) {
        /* first knob slowest */
        const uint32_t msaa[6] = {1, 1, 1, 4, 4, 4}, sh[6] = {512, 1024, 2048, 512, 1024, 2048};
        for (int i = 0; i < 6; i++) CHECK(list[i].msaa == msaa[i] && list[i].shadow_size == sh[i]);
        CHECK(list[0].ssdo_samples == base.ssdo_samples);
    }
    free(list);
    CHECK(!prw_quality_parse_sweep("msaa=1,3", &base, &list, &n, &e) && strstr(e.msg, "msaa"));
    CHECK(!prw_quality_parse_sweep("msaa", &base, &list, &n, &e) && strstr(e.msg, "knob=v1,v2"));
    CHECK(!prw_quality_parse_sweep("msaa=1;msaa=4", &base, &list, &n, &e) && strstr(e.msg, "twice"));
    CHECK(!prw_quality_parse_sweep("nope=1,2", &base, &list, &n, &e) && strstr(e.msg, "unknown knob"));
    CHECK(!prw_quality_parse_sweep("", &base, &list, &n, &e));
    CHECK(list == NULL && n == 0);
}

/* The renderer takes the struct as it is: validation names the first knob out of range; the help says
 * which knobs have no effect yet (the renderer uses lod_pixel_tolerance now). */
static void t_validate(void)
{
    prw_error e = {{0}};
    prw_quality q = prw_quality_default();
    CHECK_OK(prw_quality_validate(&q, &e), &e);
    q.msaa = 1;
    q.shadow_size = 512;
    q.supersample = 2;
    q.extra_gpu_work = 0.2;
    CHECK_OK(prw_quality_validate(&q, &e), &e);
    q.msaa = 2;
    CHECK(!prw_quality_validate(&q, &e) && strstr(e.msg, "msaa"));
    q = prw_quality_default();
    q.lod_pixel_tolerance = 0;
    CHECK(!prw_quality_validate(&q, &e) && strstr(e.msg, "lod_pixel_tolerance"));
    q = prw_quality_default();
    q.ssdo_radius = 0.0 / 0.0;
    CHECK(!prw_quality_validate(&q, &e) && strstr(e.msg, "ssdo_radius"));
    char help[4096];
    prw_quality_describe(help, sizeof help);
    CHECK(strstr(help, "btf_clusters") && strstr(help, "no effect yet"));
    const char *lod = strstr(help, "lod_pixel_tolerance");
    CHECK(lod && (!strchr(lod, '\n') || !strstr(lod, "no effect yet") || strstr(lod, "no effect yet") > strchr(lod, '\n')));
    CHECK(!strstr(help, "extra_gpu_work"));
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"presets", t_presets}, {"config", t_config}, {"sweep", t_sweep}, {"validate", t_validate},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}

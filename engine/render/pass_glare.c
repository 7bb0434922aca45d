/* pass_glare — temporal glare (prw_glare.h) as a host stage of the graph: per view, the radiance image
 * is read back, convolved on the CPU with the eye's point-spread function (pupil from the adapted
 * luminance when adaptation runs, else from the image's log-average; PSF at the display's pixels per
 * degree) and uploaded as "hdr_glare", which the tone mapping then reads instead of "hdr".  So the
 * display outputs (signal, ldr) are glared and the scene radiance ("hdr") is not.  In the graph only
 * when the renderer is made with glare settings. */
#include <stdlib.h>
#include <string.h>

#include "prw_glare.h"
#include "prw_pass.h"
#include "tonemap_gpu.h"

static void setup(prw_setup *s)
{
    if (!prw_setup_env(s)->desc->glare) return prw_setup_skip(s, "temporal glare is off");
    prw_image_decl d = {.format = VK_FORMAT_R32G32B32A32_SFLOAT, .size = PRW_SIZE_VIEW};
    prw_setup_image(s, "hdr_glare", &d);
    prw_setup_use(s, "hdr", PRW_USE_TRANSFER_SRC);
    prw_setup_use(s, "hdr_glare", PRW_USE_TRANSFER_DST);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    for (uint32_t v = 0; v < c->frame->view_count; v++) {
        prw_image img = {0};
        float *psf = NULL;
        int radius = 0;
        prw_gpu_image *src = prw_graph_image(c->graph, "hdr", v), *dst = prw_graph_image(c->graph, "hdr_glare", v);
        bool ok = prw_image_alloc(&img, (int)src->width, (int)src->height, e) &&
                  prw_image_readback(env->gpu, src, img.rgba, e);
        double la;
        if (ok && !prw_tm_gpu_adaptation(env->tm, &la)) {
            prw_tm_stats st;
            prw_tm_stats_image(&img, &st);
            la = st.log_avg;
        }
        double pupil = ok ? prw_glare_pupil_mm(la) : 0;
        ok = ok && prw_glare_psf(env->desc->glare, pupil, &psf, &radius, e) && prw_glare_apply(&img, psf, radius, e) &&
             prw_image_upload(env->gpu, dst, 0, img.rgba, (size_t)img.width * (size_t)img.height * 16, e);
        free(psf);
        prw_image_free(&img);
        if (!ok) return prw_fail_wrap(e, "glare, view %u", v);
        c->frame->glare_pupil_mm = pupil;
        c->frame->glare_psf_radius = radius;
    }
    return true;
}

const prw_pass prw_pass_glare = {
    .name = "glare",
    .scope = PRW_SCOPE_FRAME,
    .queue = PRW_QUEUE_HOST,
    .setup = setup,
    .record = record,
};

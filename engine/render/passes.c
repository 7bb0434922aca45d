/* passes — the standard pass table: one line per pass, recorded in this order (graph.h). */
#include "prw_pass.h"

#ifdef PRW_HAVE_GLARE
extern const prw_pass prw_pass_glare;
#endif
extern const prw_pass prw_pass_shadow, prw_pass_base, prw_pass_base_multiview, prw_pass_mirror, prw_pass_mirror_glossy,
    prw_pass_mirror_add,
    prw_pass_reproject,
    prw_pass_downsample, prw_pass_floor, prw_pass_tm_stats, prw_pass_tonemap, prw_pass_compose, prw_pass_extra_work;

const prw_pass *const prw_passes_default[] = {
    &prw_pass_shadow,         /* shadow atlas, once per frame (pass_shadow.c) */
    &prw_pass_base,           /* emission + direct light per view (pass_base.c) */
    &prw_pass_base_multiview, /* the same for two views at once (pass_base_multiview.c) */
    &prw_pass_mirror,         /* planar mirror: the view reflected in the reflector's plane (pass_mirror.c) */
    &prw_pass_mirror_glossy,  /* glossy reflectors: that image convolved by the GGX lobe (pass_mirror.c) */
    &prw_pass_mirror_add,     /* + Fresnel x that image in the reflector's pixels (pass_mirror.c) */
    &prw_pass_reproject,      /* stereo_reuse=reproject: the right eye from the left (pass_reproject.c) */
    &prw_pass_downsample,     /* N x N supersampling box filter (pass_downsample.c) */
    &prw_pass_floor,          /* with timestamps: the base draws with a constant shader (pass_floor.c) */
#ifdef PRW_HAVE_GLARE
    &prw_pass_glare,          /* temporal glare on the display's copy, a host stage (pass_glare.c) */
#endif
    &prw_pass_tm_stats,       /* tone-mapping frame statistics (pass_tonemap.c) */
    &prw_pass_tonemap,        /* display-aware tone mapping per view (pass_tonemap.c) */
    &prw_pass_compose,        /* two views -> one HMD / side-by-side panel (pass_compose.c) */
    &prw_pass_extra_work,     /* test knob: extra GPU work (pass_extra_work.c) */
    NULL,
};

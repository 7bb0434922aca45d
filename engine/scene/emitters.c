/* emitters — how much light the scene's emissive surfaces give (prw_scene.h prw_scene_emitters). */
#include <math.h>

#include "prw_emissive.h"

static double srgb_decode(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

bool prw_material_emitted_rgb(const prw_scene *s, const prw_material *m, double rgb[3])
{
    double r = m->emission[0], g = m->emission[1], b = m->emission[2];
    int t = m->emissive_tex;
    if (t >= 0 && (uint32_t)t < s->texture_count && s->textures[t].rgba8) {
        const prw_texture *tx = &s->textures[t];
        size_t n = (size_t)tx->width * (size_t)tx->height;
        double lut[256], sr = 0, sg = 0, sb = 0;
        for (int i = 0; i < 256; i++) lut[i] = tx->srgb ? srgb_decode(i / 255.0) : i / 255.0;
        for (size_t i = 0; i < n; i++) {
            sr += lut[tx->rgba8[4 * i]];
            sg += lut[tx->rgba8[4 * i + 1]];
            sb += lut[tx->rgba8[4 * i + 2]];
        }
        if (n) r *= sr / (double)n, g *= sg / (double)n, b *= sb / (double)n;
    }
    rgb[0] = isfinite(r) && r > 0 ? r : 0.0;
    rgb[1] = isfinite(g) && g > 0 ? g : 0.0;
    rgb[2] = isfinite(b) && b > 0 ? b : 0.0;
    return rgb[0] > 0 || rgb[1] > 0 || rgb[2] > 0;
}

/* Rec.709 luminance of a material's emission times its emissive texture's mean (sRGB decoded). */
static double emitted_luminance(const prw_scene *s, const prw_material *m)
{
    double c[3];
    prw_material_emitted_rgb(s, m, c);
    double y = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    return isfinite(y) && y > 0 ? y : 0.0;
}

prw_emitters prw_scene_emitters(const prw_scene *s)
{
    prw_emitters out = {0};
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        const prw_node *n = &s->nodes[ni];
        if (n->mesh_group < 0 || (uint32_t)n->mesh_group >= s->group_count) continue;
        const prw_mesh_group *g = &s->groups[n->mesh_group];
        for (uint32_t k = g->first; k < g->first + g->count && k < s->mesh_count; k++) {
            const prw_mesh *m = &s->meshes[k];
            if (m->material < 0 || (uint32_t)m->material >= s->material_count) continue;
            const prw_material *mat = &s->materials[m->material];
            double lum = emitted_luminance(s, mat);
            if (lum <= 0) continue;
            double area = 0;
            for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
                prw_dvec3 p[3];
                for (int c = 0; c < 3; c++) {
                    const float *v = &m->positions[3 * (size_t)m->indices[t + c]];
                    p[c] = prw_dm4_point(n->world, prw_v3(v[0], v[1], v[2]));
                }
                area += 0.5 * prw_v3_len(prw_v3_cross(prw_v3_sub(p[1], p[0]), prw_v3_sub(p[2], p[0])));
            }
            /* a Lambertian emitter of luminance L and area A sends pi L A lumens to each side it emits from */
            double flux = PRW_PI * lum * area * (mat->double_sided ? 2.0 : 1.0);
            if (isfinite(flux)) out.mesh_flux_lm += flux;
            out.mesh_count++;
        }
    }
    for (uint32_t i = 0; i < s->nurbs_count; i++) {
        int mi = s->nurbs[i].material;
        if (mi >= 0 && (uint32_t)mi < s->material_count && emitted_luminance(s, &s->materials[mi]) > 0)
            out.nurbs_count++;
    }
    return out;
}

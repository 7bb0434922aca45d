/* IGES driver: reads the records, picks the drawable entities (subordinate switch, 144
 * references), converts them, applies units, and lists what was skipped. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_iges_internal.h"

/* Entities that are converted when something references them (or are drawn). */
static bool supported(int type)
{
    switch (type) {
    case 0: case 100: case 102: case 110: case 124: case 126: case 142: case 144: case 314:
    case 108: case 118: case 120: case 122: case 128:
        return true;
    default:
        return false;
    }
}

static void scale_surface(prw_trimmed_surface *t, double s)
{
    prw_dmat4 m = prw_dm4_identity();
    m.m[0] = m.m[5] = m.m[10] = s;
    prw_nurbs_surface_transform(&t->surface, &m);
    for (int l = 0; l < t->nloops; l++)
        for (int k = 0; k < t->loops[l].count; k++)
            if (t->loops[l].segs[k].model) prw_nurbs_curve_transform(t->loops[l].segs[k].model, &m);
}

bool prw_iges_parse(const char *data, size_t size, const char *name, prw_nurbs_model *out, prw_iges_info *info,
                    prw_error *e)
{
    prw_iges_info dummy;
    if (!info) info = &dummy;
    memset(info, 0, sizeof *info);
    prw_nurbs_model_init(out);
    iges_file f = {0};
    f.name = name;
    if (!iges_read_records(&f, data, size, e)) {
        iges_file_free(&f);
        return false;
    }
    info->entities = f.nde;
    info->metres_per_unit = f.unit_m / f.model_scale;
    iges_ctx x = {&f, e, 0, 4000000 + 64L * (long)size, 0};
    /* surfaces referenced by a 144 are never drawn on their own */
    for (int k = 0; k < f.nde; k++) {
        if (f.de[k].type != 144 || f.de[k].ntok < 1) continue;
        int s;
        prw_error ignore;
        if (iges_ptr(&f, &f.de[k], 1, false, &s, &ignore)) f.de[s].used_by_144 = true;
    }
    int skipped[10000] = {0};
    bool ok = true;
    for (int k = 0; k < f.nde && ok; k++) {
        iges_de *d = &f.de[k];
        if (!supported(d->type)) {
            skipped[d->type]++;
            info->skipped++;
            continue;
        }
        bool independent = d->subord == 0 || d->subord == 2;
        bool draw = independent && (d->type == 144 || (iges_is_surface_type(d->type) && !d->used_by_144));
        if (!draw) continue;
        prw_trimmed_surface *t = prw_nurbs_model_add(out);
        t->source = d->seq;
        ok = d->type == 144 ? iges_trimmed_surface(&x, k, t) : iges_plain_surface(&x, k, t);
        if (ok) ok = iges_colour(&x, d, t->colour, &t->has_colour);
        if (!ok) break;
        scale_surface(t, info->metres_per_unit);
        if (d->type == 144) info->trimmed++;
        else info->untrimmed++;
    }
    info->max_projection_distance = x.max_proj * info->metres_per_unit;
    if (ok && info->skipped) {
        size_t n = (size_t)snprintf(info->warning, sizeof info->warning, "%s: skipped %d unsupported entities:", name,
                                    info->skipped);
        bool first = true;
        for (int t = 0; t < 10000 && n < sizeof info->warning; t++) {
            if (!skipped[t]) continue;
            n += (size_t)snprintf(info->warning + n, sizeof info->warning - n, "%s %d x%d", first ? "" : ",", t, skipped[t]);
            first = false;
        }
    }
    iges_file_free(&f);
    if (!ok) prw_nurbs_model_free(out);
    return ok;
}

bool prw_iges_load(const char *path, prw_nurbs_model *out, prw_iges_info *info, prw_error *e)
{
    char *data;
    size_t size;
    if (!prw_read_file(path, &data, &size, e)) return false;
    bool ok = prw_iges_parse(data, size, path, out, info, e);
    free(data);
    return ok;
}

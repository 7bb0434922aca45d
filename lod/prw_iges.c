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
    case 0: case 100: case 102: case 104: case 110: case 112: case 124: case 126: case 142: case 144: case 314:
    case 108: case 114: case 118: case 120: case 122: case 128: case 140: case 141: case 143: case 190:
    case 186: case 502: case 504: case 508: case 510: case 514:
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

/* Marks entity `ptr` parameter i of d as used (never drawn on its own). */
static void mark(iges_file *f, const iges_de *d, int i)
{
    int s;
    prw_error ignore;
    if (i <= d->ntok && iges_ptr(f, d, i, false, &s, &ignore)) f->de[s].used_by_144 = true;
}

/* A face of a B-rep (510 used by a 514, 514 by a 186) to convert, with its orientation. */
typedef struct face_job {
    int k;     /* the 510 */
    bool flip; /* shell / solid orientation reverses the face */
} face_job;

typedef struct face_list {
    face_job *v;
    int n, cap;
} face_list;

static void add_face(face_list *l, int k, bool flip)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 64;
        l->v = prw_realloc(l->v, sizeof *l->v * (size_t)l->cap);
    }
    l->v[l->n++] = (face_job){k, flip};
}

/* The faces of shell k (514): per face its pointer and orientation flag (1 = the face's normal is
 * the surface's, 0 = opposite).  Malformed shells fail the file. */
static bool shell_faces(iges_file *f, int k, bool flip, face_list *out, prw_error *e)
{
    const iges_de *d = &f->de[k];
    if (d->type != 514) return iges_fail(f, d, 0, e, "a solid's shell must be a 514, not entity %d", d->type);
    int n;
    if (!iges_int(f, d, 1, 0, &n, e)) return false;
    if (n < 0 || n > 10000000) return iges_fail(f, d, 1, e, "%d faces", n);
    if (!iges_need(f, d, 1 + 2 * n, e)) return false;
    for (int i = 0; i < n; i++) {
        int fk, of;
        if (!iges_ptr(f, d, 2 + 2 * i, false, &fk, e) || !iges_int(f, d, 3 + 2 * i, 1, &of, e)) return false;
        if (f->de[fk].type != 510) return iges_fail(f, d, 2 + 2 * i, e, "shell face must be a 510, not entity %d", f->de[fk].type);
        if (of != 0 && of != 1) return iges_fail(f, d, 3 + 2 * i, e, "face orientation flag %d is not 0 or 1", of);
        add_face(out, fk, flip != (of == 0));
    }
    return true;
}

/* 186: the outer shell and the void shells with their orientation flags. */
static bool solid_faces(iges_file *f, int k, face_list *out, prw_error *e)
{
    const iges_de *d = &f->de[k];
    int sh, sof, nv;
    if (!iges_need(f, d, 3, e) || !iges_ptr(f, d, 1, false, &sh, e) || !iges_int(f, d, 2, 1, &sof, e) ||
        !iges_int(f, d, 3, 0, &nv, e))
        return false;
    if (nv < 0 || nv > 1000000) return iges_fail(f, d, 3, e, "%d void shells", nv);
    if (!iges_need(f, d, 3 + 2 * nv, e)) return false;
    if (!shell_faces(f, sh, sof == 0, out, e)) return false;
    for (int i = 0; i < nv; i++) {
        int vk, vof;
        if (!iges_ptr(f, d, 4 + 2 * i, false, &vk, e) || !iges_int(f, d, 5 + 2 * i, 1, &vof, e) ||
            !shell_faces(f, vk, vof == 0, out, e))
            return false;
    }
    return true;
}

/* Appends "type xN" for every non-zero count. */
static size_t list_counts(char *buf, size_t cap, size_t n, const int *counts)
{
    bool first = true;
    for (int t = 0; t < 10000 && n < cap; t++) {
        if (!counts[t]) continue;
        n += (size_t)snprintf(buf + n, cap - n, "%s %d x%d", first ? "" : ",", t, counts[t]);
        first = false;
    }
    return n < cap ? n : cap - 1;
}

long prw_iges_default_work(size_t size) { return 4000000 + 64L * (long)(size > (1u << 30) ? (1u << 30) : size); }

bool prw_iges_parse(const char *data, size_t size, const char *name, prw_nurbs_model *out, prw_iges_info *info,
                    prw_error *e)
{
    return prw_iges_parse_limited(data, size, name, prw_iges_default_work(size), out, info, e);
}

bool prw_iges_parse_limited(const char *data, size_t size, const char *name, long work, prw_nurbs_model *out,
                            prw_iges_info *info, prw_error *e)
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
    iges_ctx x = {&f, e, 0, work, 0, 0};
    /* surfaces referenced by a 144 / 143 / 510, faces by a shell and shells by a solid are never
     * drawn on their own */
    for (int k = 0; k < f.nde; k++) {
        const iges_de *d = &f.de[k];
        if ((d->type == 144 || d->type == 510) && d->ntok >= 1) mark(&f, d, 1);
        if (d->type == 143 && d->ntok >= 2) mark(&f, d, 2);
        if (d->type == 186 && d->ntok >= 1) mark(&f, d, 1);
        if (d->type == 186 && d->ntok >= 3) {
            int nv;
            prw_error ignore;
            if (iges_int(&f, d, 3, 0, &nv, &ignore))
                for (int i = 0; i < nv && 4 + 2 * i <= d->ntok; i++) mark(&f, d, 4 + 2 * i);
        }
        if (d->type == 514 && d->ntok >= 1) {
            int n;
            prw_error ignore;
            if (iges_int(&f, d, 1, 0, &n, &ignore))
                for (int i = 0; i < n && 2 + 2 * i <= d->ntok; i++) mark(&f, d, 2 + 2 * i);
        }
        if (d->type == 308 && d->ntok >= 3) { /* depth, name, N, N members */
            int n, s;
            prw_error ignore;
            if (iges_int(&f, d, 3, 0, &n, &ignore))
                for (int i = 0; i < n && 4 + i <= d->ntok; i++)
                    if (iges_ptr(&f, d, 4 + i, false, &s, &ignore)) f.de[s].in_subfigure = true;
        }
    }
    int *skipped = prw_calloc(10000, sizeof(int)), *needs = prw_calloc(10000, sizeof(int));
    face_list faces = {0};
    bool ok = true;
    for (int k = 0; k < f.nde && ok; k++) {
        iges_de *d = &f.de[k];
        bool independent = d->subord == 0 || d->subord == 2;
        if (!supported(d->type)) {
            /* points and directions a 190 plane reads are parts of it, not unsupported entities */
            if ((d->type == 116 || d->type == 123) && !independent) continue;
            skipped[d->type]++;
            info->skipped++;
            continue;
        }
        if (d->type == 190 && independent && !d->used_by_144) { /* a free plane has no extent to draw */
            skipped[d->type]++;
            info->skipped++;
            continue;
        }
        /* a B-rep face flagged physically dependent that no shell (and no subfigure) uses is drawn
         * as the free face it is (OpenCASCADE 6.x writes single faces so) */
        bool orphan_face = d->type == 510 && !d->used_by_144 && !d->in_subfigure;
        if ((!independent && !orphan_face) || d->used_by_144) continue;
        /* what to draw: trimmed (144) and bounded (143) surfaces, B-rep faces, plain surfaces */
        faces.n = 0;
        int kind; /* 0: 144, 1: 143, 2: B-rep faces, 3: plain surface */
        if (d->type == 144) kind = 0;
        else if (d->type == 143) kind = 1;
        else if (d->type == 186) kind = 2, ok = solid_faces(&f, k, &faces, e);
        else if (d->type == 514) kind = 2, ok = shell_faces(&f, k, false, &faces, e);
        else if (d->type == 510) kind = 2, add_face(&faces, k, false);
        else if (iges_is_surface_type(d->type)) kind = 3;
        else continue;
        int jobs = kind == 2 ? faces.n : 1;
        for (int j = 0; ok && j < jobs; j++) {
            int fk = kind == 2 ? faces.v[j].k : k;
            iges_de *fd = &f.de[fk];
            prw_trimmed_surface *t = prw_nurbs_model_add(out);
            t->source = fd->seq;
            x.unsupported = 0;
            x.depth = 0;
            bool fok = kind == 0 ? iges_trimmed_surface(&x, fk, t)
                       : kind == 1 ? iges_bounded_surface(&x, fk, t)
                       : kind == 2 ? iges_brep_face(&x, fk, faces.v[j].flip, t)
                                   : iges_plain_surface(&x, fk, t);
            if (!fok && x.unsupported > 0 && x.unsupported < 10000) {
                /* a face that needs an entity type this reader lacks: left out, counted */
                needs[x.unsupported]++;
                info->faces_skipped++;
                prw_nurbs_model_pop(out);
                continue;
            }
            ok = fok && iges_colour(&x, kind == 2 && fd->colour == 0 ? d : fd, t->colour, &t->has_colour);
            if (ok && kind == 2 && fd != d) { /* the solid's / shell's own transformation */
                prw_dmat4 own;
                ok = iges_own_xform(&x, d, &own);
                if (ok) {
                    prw_nurbs_surface_transform(&t->surface, &own);
                    for (int l = 0; l < t->nloops; l++)
                        for (int s = 0; s < t->loops[l].count; s++)
                            if (t->loops[l].segs[s].model) prw_nurbs_curve_transform(t->loops[l].segs[s].model, &own);
                }
            }
            if (!ok) break;
            scale_surface(t, info->metres_per_unit);
            if (kind == 3 && t->natural_outer) info->untrimmed++;
            else info->trimmed++;
        }
    }
    free(faces.v);
    info->max_projection_distance = x.max_proj * info->metres_per_unit;
    if (ok && (info->skipped || info->faces_skipped || f.note[0])) {
        size_t n = (size_t)snprintf(info->warning, sizeof info->warning, "%s:", name);
        if (f.note[0])
            n += (size_t)snprintf(info->warning + n, sizeof info->warning - n, " %s%s", f.note,
                                  info->skipped || info->faces_skipped ? ";" : "");
        if (info->skipped) {
            n += (size_t)snprintf(info->warning + n, sizeof info->warning - n, " skipped %d unsupported entities:",
                                  info->skipped);
            n = list_counts(info->warning, sizeof info->warning, n, skipped);
        }
        if (info->faces_skipped && n < sizeof info->warning) {
            n += (size_t)snprintf(info->warning + n, sizeof info->warning - n, "%s%d faces left out, they need",
                                  info->skipped ? "; " : " ", info->faces_skipped);
            n = list_counts(info->warning, sizeof info->warning, n < sizeof info->warning ? n : sizeof info->warning - 1,
                            needs);
        }
    }
    free(skipped);
    free(needs);
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

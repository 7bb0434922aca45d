/* Hand-made IGES test models (see iges_models.h). */
#include "iges_models.h"

#include "iges_writer.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEP 1 /* physically dependent */

static const char *BILINEAR_100 =
    "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,"
    "0.,0.,0.,100.,0.,0.,0.,100.,0.,100.,100.,0.,0.,1.,0.,1.";

char *iges_model_sphere_rev(size_t *len)
{
    igw w;
    igw_init(&w);
    int col = igw_add(&w, 314, 0, 0, 0, 0, "30.,60.,90.,4Hblue");
    int axis = igw_add(&w, 110, 0, DEP, 0, 0, "0.,-1000.,0.,0.,1000.,0.");
    int gen = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,0.,-1000.,0.,1000.");
    igw_add(&w, 120, 0, 0, 0, -col, "%d,%d,0.,6.283185307179586", axis, gen);
    char *s = igw_finish(&w, len);
    igw_free(&w);
    return s;
}

char *iges_model_sphere_zone(double t0, double t1, double th0, double th1, size_t *len)
{
    igw w;
    igw_init(&w);
    int axis = igw_add(&w, 110, 0, DEP, 0, 0, "0.,-1000.,0.,0.,1000.,0.");
    int gen = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,0.,-1000.,0.,1000.");
    int rev = igw_add(&w, 120, 0, DEP, 0, 0, "%d,%d,0.,6.283185307179586", axis, gen);
    double c[5][2] = {{t0, th0}, {t1, th0}, {t1, th1}, {t0, th1}, {t0, th0}};
    int l[4];
    for (int i = 0; i < 4; i++)
        l[i] = igw_add(&w, 110, 0, DEP, 0, 0, "%.17g,%.17g,0.,%.17g,%.17g,0.", c[i][0], c[i][1], c[i + 1][0], c[i + 1][1]);
    int b = igw_add(&w, 102, 0, DEP, 0, 0, "4,%d,%d,%d,%d", l[0], l[1], l[2], l[3]);
    int cos_ = igw_add(&w, 142, 0, DEP, 0, 0, "1,%d,%d,0,1", rev, b);
    igw_add(&w, 144, 0, 0, 0, 0, "%d,1,0,%d", rev, cos_);
    char *r = igw_finish(&w, len);
    igw_free(&w);
    return r;
}

char *iges_model_trimmed_plate(size_t *len)
{
    igw w;
    igw_init(&w);
    int xf = igw_add(&w, 124, 0, 0, 0, 0, "1.,0.,0.,10.,0.,1.,0.,0.,0.,0.,1.,0.");
    int plate = igw_add(&w, 128, 0, DEP, 0, 0, "%s", BILINEAR_100);
    /* outer boundary along the domain edges: (u, v) and model-space 102s of 110s */
    int b[4], c[4];
    double uv[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
    for (int i = 0; i < 4; i++)
        b[i] = igw_add(&w, 110, 0, DEP, 0, 0, "%g,%g,0.,%g,%g,0.", uv[i][0], uv[i][1], uv[i + 1][0], uv[i + 1][1]);
    for (int i = 0; i < 4; i++)
        c[i] = igw_add(&w, 110, 0, DEP, 0, 0, "%g,%g,0.,%g,%g,0.", 100 * uv[i][0], 100 * uv[i][1], 100 * uv[i + 1][0],
                       100 * uv[i + 1][1]);
    int bo = igw_add(&w, 102, 0, DEP, 0, 0, "4,%d,%d,%d,%d", b[0], b[1], b[2], b[3]);
    int co = igw_add(&w, 102, 0, DEP, 0, 0, "4,%d,%d,%d,%d", c[0], c[1], c[2], c[3]);
    int outer = igw_add(&w, 142, 0, DEP, 0, 0, "1,%d,%d,%d,1", plate, bo, co);
    /* hole 1: (u, v) circle + model circle */
    int hb = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.3,0.5,0.45,0.5,0.45,0.5");
    int hc = igw_add(&w, 100, 0, DEP, 0, 0, "0.,30.,50.,45.,50.,45.,50.");
    int h1 = igw_add(&w, 142, 0, DEP, 0, 0, "1,%d,%d,%d,1", plate, hb, hc);
    /* hole 2: model space only -> projected */
    int mc = igw_add(&w, 100, 0, DEP, 0, 0, "0.,70.,50.,80.,50.,80.,50.");
    int h2 = igw_add(&w, 142, 0, DEP, 0, 0, "1,%d,0,%d,2", plate, mc);
    igw_add(&w, 144, 0, 0, xf, 4, "%d,1,2,%d,%d,%d", plate, outer, h1, h2);
    char *s = igw_finish(&w, len);
    igw_free(&w);
    return s;
}

char *iges_model_all_entities(size_t *len)
{
    igw w;
    igw_init(&w);
    w.unit_flag = 6;
    w.unit = "M";
    int bound = igw_add(&w, 100, 0, DEP, 0, 0, "5.,0.,0.,20.,0.,20.,0.");
    igw_add(&w, 108, 1, 0, 0, 0, "0.,0.,1.,5.,%d,0.,0.,5.,10.", bound);
    int l1 = igw_add(&w, 110, 0, DEP, 0, 0, "-10.,0.,0.,10.,0.,0.");
    int a1 = igw_add(&w, 100, 0, DEP, 0, 0, "3.,0.,0.,10.,0.,-10.,0.");
    igw_add(&w, 118, 1, 0, 0, 0, "%d,%d,0,0", l1, a1);
    int dir = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,4.,0.,0.,4.");
    igw_add(&w, 122, 0, 0, 0, 0, "%d,4.,0.,30.", dir);
    int rot = igw_add(&w, 124, 0, 0, 0, 0, "0.,-1.,0.,1.,1.,0.,0.,2.,0.,0.,1.,3.");
    igw_add(&w, 128, 0, 0, rot, 0, "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,"
                                   "0.,0.,0.,1.,0.,0.,0.,1.,0.,1.,1.,0.,0.,1.,0.,1.");
    igw_add(&w, 126, 0, 0, 0, 0, "1,1,0,0,1,0,0.,0.,1.,1.,1.,1.,0.,0.,0.,1.,1.,1.,0.,1.");
    int s143 = igw_add(&w, 128, 0, DEP, 0, 0, "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,"
                                              "0.,0.,0.,1.,0.,0.,0.,1.,0.,1.,1.,0.,0.,1.,0.,1.");
    igw_add(&w, 143, 0, 0, 0, 0, "0,%d,0", s143); /* no boundary: the whole (dependent) 128 */
    igw_add(&w, 116, 0, 0, 0, 0, "0.,0.,0.");
    igw_add(&w, 123, 0, 0, 0, 0, "0.,0.,1.");
    igw_add(&w, 212, 0, 0, 0, 0, "0");
    igw_add(&w, 406, 15, 0, 0, 0, "1,4Hname");
    igw_add(&w, 410, 0, 0, 0, 0, "0");
    char *s = igw_finish(&w, len);
    igw_free(&w);
    return s;
}

char *iges_model_units(int unit_flag, const char *unit, double scale, int subord, int used_by_144, size_t *len)
{
    igw w;
    igw_init(&w);
    w.unit_flag = unit_flag;
    w.unit = unit;
    w.scale = scale;
    int s = igw_add(&w, 128, 0, subord, 0, 0, "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,"
                                               "0.,0.,0.,1.,0.,0.,0.,1.,0.,1.,1.,0.,0.,1.,0.,1.");
    if (used_by_144) igw_add(&w, 144, 0, 0, 0, 0, "%d,0,0,0", s);
    char *r = igw_finish(&w, len);
    igw_free(&w);
    return r;
}

/* ---- B-rep solids (MSBO 186) ---- */

/* A small B-rep builder: vertices, edges (curve DE, start / end vertex: the curve runs from start
 * to end), faces (surface DE, orientation flag, one loop as a vertex cycle with the edge between
 * each consecutive pair), written as 502, 504, 508, 510, 514 (form 1, closed) and 186. */
typedef struct brep {
    igw *w;
    double vx[64][3];
    int nv;
    int ecurve[64], ea[64], eb[64], ne;
    struct {
        int surf, of, n, v[8];
        int e[8]; /* edge per step (-1: find by vertices) */
        int o[8]; /* orientation per step: 1 along the curve, 0 against, -1 from the vertices */
    } f[16];
    int nf;
    bool orphan; /* faces only: no 514 / 186 (physically dependent 510s nobody uses) */
} brep;

static int bv(brep *b, double x, double y, double z)
{
    b->vx[b->nv][0] = x, b->vx[b->nv][1] = y, b->vx[b->nv][2] = z;
    return b->nv++;
}

static int be(brep *b, int curve, int a, int c)
{
    b->ecurve[b->ne] = curve, b->ea[b->ne] = a, b->eb[b->ne] = c;
    return b->ne++;
}

/* Face with a loop through vertices v[0..n-1] (back to v[0]); e[k] (or -1) is the edge from v[k]
 * to v[k+1]; -1 picks the edge joining the two vertices. */
static void bf(brep *b, int surf, int of, int n, const int *v, const int *e, const int *o)
{
    b->f[b->nf].surf = surf, b->f[b->nf].of = of, b->f[b->nf].n = n;
    for (int k = 0; k < n; k++) b->f[b->nf].v[k] = v[k], b->f[b->nf].e[k] = e ? e[k] : -1, b->f[b->nf].o[k] = o ? o[k] : -1;
    b->nf++;
}

static char *brep_finish(brep *b, size_t *len)
{
    igw *w = b->w;
    char buf[8192];
    int n = snprintf(buf, sizeof buf, "%d", b->nv);
    for (int i = 0; i < b->nv; i++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",%.17g,%.17g,%.17g", b->vx[i][0], b->vx[i][1], b->vx[i][2]);
    int vl = igw_add(w, 502, 1, DEP, 0, 0, "%s", buf);
    n = snprintf(buf, sizeof buf, "%d", b->ne);
    for (int i = 0; i < b->ne; i++)
        n += snprintf(buf + n, sizeof buf - (size_t)n, ",%d,%d,%d,%d,%d", b->ecurve[i], vl, b->ea[i] + 1, vl, b->eb[i] + 1);
    int el = igw_add(w, 504, 1, DEP, 0, 0, "%s", buf);
    int face[16];
    for (int fi = 0; fi < b->nf; fi++) {
        n = snprintf(buf, sizeof buf, "%d", b->f[fi].n);
        for (int k = 0; k < b->f[fi].n; k++) {
            int a = b->f[fi].v[k], c = b->f[fi].v[(k + 1) % b->f[fi].n], ed = b->f[fi].e[k];
            if (ed < 0)
                for (int i = 0; i < b->ne; i++)
                    if ((b->ea[i] == a && b->eb[i] == c) || (b->ea[i] == c && b->eb[i] == a)) ed = i;
            int of = b->f[fi].o[k] >= 0 ? b->f[fi].o[k] : b->ea[ed] == a && b->eb[ed] == c;
            n += snprintf(buf + n, sizeof buf - (size_t)n, ",0,%d,%d,%d,0", el, ed + 1, of);
        }
        int loop = igw_add(w, 508, 1, DEP, 0, 0, "%s", buf);
        face[fi] = igw_add(w, 510, 1, DEP, 0, 0, "%d,1,1,%d", b->f[fi].surf, loop);
    }
    n = snprintf(buf, sizeof buf, "%d", b->nf);
    for (int fi = 0; fi < b->nf; fi++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",%d,%d", face[fi], b->f[fi].of);
    if (!b->orphan) {
        int shell = igw_add(w, 514, 1, DEP, 0, 0, "%s", buf);
        igw_add(w, 186, 0, 0, 0, 0, "%d,1,0", shell);
    }
    char *s = igw_finish(w, len);
    igw_free(w);
    return s;
}

static int line(igw *w, const double *a, const double *c)
{
    return igw_add(w, 110, 0, DEP, 0, 0, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", a[0], a[1], a[2], c[0], c[1], c[2]);
}

/* Bilinear 128 plane through p00, p10, p01, p11 (normal (p10 - p00) x (p01 - p00)). */
static int plane128(igw *w, const double *p00, const double *p10, const double *p01, const double *p11)
{
    return igw_add(w, 128, 0, DEP, 0, 0,
                   "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                   "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0.,1.,0.,1.",
                   p00[0], p00[1], p00[2], p10[0], p10[1], p10[2], p01[0], p01[1], p01[2], p11[0], p11[1], p11[2]);
}

/* The box's face planes as 128 or (plane190) as 190 through p00 with normal (p10 - p00) x (p01 - p00). */
static bool plane190;
static int box_plane(igw *w, const double *p00, const double *p10, const double *p01, const double *p11)
{
    if (!plane190) return plane128(w, p00, p10, p01, p11);
    double a[3], c[3];
    for (int k = 0; k < 3; k++) a[k] = p10[k] - p00[k], c[k] = p01[k] - p00[k];
    int pt = igw_add(w, 116, 0, DEP, 0, 0, "%.17g,%.17g,%.17g", p00[0], p00[1], p00[2]);
    int nr = igw_add(w, 123, 0, DEP, 0, 0, "%.17g,%.17g,%.17g", a[1] * c[2] - a[2] * c[1], a[2] * c[0] - a[0] * c[2],
                     a[0] * c[1] - a[1] * c[0]);
    return igw_add(w, 190, 0, DEP, 0, 0, "%d,%d", pt, nr);
}

char *iges_model_brep_box_variant(bool faces_only, bool planes_190, size_t *len)
{
    static igw w;
    igw_init(&w);
    static brep b;
    memset(&b, 0, sizeof b);
    b.w = &w;
    b.orphan = faces_only;
    plane190 = planes_190;
    const double X = 100, Y = 60, Z = 40, m = 10; /* mm; faces' planes extend m beyond the face */
    int v[8];
    for (int i = 0; i < 8; i++) v[i] = bv(&b, (i & 1) * X, ((i >> 1) & 1) * Y, ((i >> 2) & 1) * Z);
    static const int E[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (int i = 0; i < 12; i++) be(&b, line(&w, b.vx[E[i][0]], b.vx[E[i][1]]), v[E[i][0]], v[E[i][1]]);
    /* faces: planes whose normal points outward (of 1), except the bottom, written inward (of 0) */
    double p[4][3];
#define P4(a, b_, c, d) memcpy(p[0], a, sizeof p[0]), memcpy(p[1], b_, sizeof p[0]), memcpy(p[2], c, sizeof p[0]), memcpy(p[3], d, sizeof p[0])
    {
        double a[3] = {-m, -m, 0}, c[3] = {X + m, -m, 0}, d[3] = {-m, Y + m, 0}, e[3] = {X + m, Y + m, 0};
        P4(a, c, d, e); /* normal +z: inward for the bottom */
        int c4[4] = {v[0], v[1], v[3], v[2]};
        bf(&b, box_plane(&w, p[0], p[1], p[2], p[3]), 0, 4, c4, NULL, NULL);
    }
    {
        double a[3] = {-m, -m, Z}, c[3] = {X + m, -m, Z}, d[3] = {-m, Y + m, Z}, e[3] = {X + m, Y + m, Z};
        P4(a, c, d, e);
        int c4[4] = {v[4], v[5], v[7], v[6]};
        bf(&b, box_plane(&w, p[0], p[1], p[2], p[3]), 1, 4, c4, NULL, NULL);
    }
    {
        double a[3] = {-m, 0, -m}, c[3] = {-m, 0, Z + m}, d[3] = {X + m, 0, -m}, e[3] = {X + m, 0, Z + m}; /* -y */
        P4(a, d, c, e);
        int c4[4] = {v[0], v[1], v[5], v[4]};
        bf(&b, box_plane(&w, p[0], p[1], p[2], p[3]), 1, 4, c4, NULL, NULL);
    }
    {
        double a[3] = {-m, Y, -m}, c[3] = {X + m, Y, -m}, d[3] = {-m, Y, Z + m}, e[3] = {X + m, Y, Z + m}; /* +y */
        P4(a, d, c, e);
        int c4[4] = {v[2], v[3], v[7], v[6]};
        bf(&b, box_plane(&w, p[0], p[1], p[2], p[3]), 1, 4, c4, NULL, NULL);
    }
    {
        double a[3] = {0, -m, -m}, c[3] = {0, Y + m, -m}, d[3] = {0, -m, Z + m}, e[3] = {0, Y + m, Z + m}; /* -x */
        P4(a, d, c, e);
        int c4[4] = {v[0], v[2], v[6], v[4]};
        bf(&b, box_plane(&w, p[0], p[1], p[2], p[3]), 1, 4, c4, NULL, NULL);
    }
    {
        double a[3] = {X, -m, -m}, c[3] = {X, Y + m, -m}, d[3] = {X, -m, Z + m}, e[3] = {X, Y + m, Z + m}; /* +x */
        P4(a, c, d, e);
        int c4[4] = {v[1], v[3], v[7], v[5]};
        bf(&b, box_plane(&w, p[0], p[1], p[2], p[3]), 1, 4, c4, NULL, NULL);
    }
#undef P4
    return brep_finish(&b, len);
}

char *iges_model_brep_box(size_t *len) { return iges_model_brep_box_variant(false, false, len); }

char *iges_model_brep_cylinder(size_t *len)
{
    static igw w;
    igw_init(&w);
    static brep b;
    memset(&b, 0, sizeof b);
    b.w = &w;
    const double R = 30, H = 80;
    /* the lateral surface in two halves (as CATIA writes it): seams at +x and -x */
    int v0 = bv(&b, R, 0, 0), v1 = bv(&b, R, 0, H), v2 = bv(&b, -R, 0, 0), v3 = bv(&b, -R, 0, H);
    int bot0 = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,%g,0.,%g,0.", R, -R), bot1 = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,%g,0.,%g,0.", -R, R);
    int top0 = igw_add(&w, 100, 0, DEP, 0, 0, "%g,0.,0.,%g,0.,%g,0.", H, R, -R), top1 = igw_add(&w, 100, 0, DEP, 0, 0, "%g,0.,0.,%g,0.,%g,0.", H, -R, R);
    int eb0 = be(&b, bot0, v0, v2), eb1 = be(&b, bot1, v2, v0), et0 = be(&b, top0, v1, v3), et1 = be(&b, top1, v3, v1);
    int es0 = be(&b, line(&w, b.vx[v0], b.vx[v1]), v0, v1), es1 = be(&b, line(&w, b.vx[v2], b.vx[v3]), v2, v3);
    int axis = igw_add(&w, 110, 0, DEP, 0, 0, "0.,0.,0.,0.,0.,1.");
    int gen = igw_add(&w, 110, 0, DEP, 0, 0, "%g,0.,0.,%g,0.,%g", R, R, H);
    /* normals inward (u up the generatrix, v around): face flag 0 */
    int rev0 = igw_add(&w, 120, 0, DEP, 0, 0, "%d,%d,0.,3.141592653589793", axis, gen);
    int rev1 = igw_add(&w, 120, 0, DEP, 0, 0, "%d,%d,3.141592653589793,6.283185307179586", axis, gen);
    int ptop = igw_add(&w, 108, 0, DEP, 0, 0, "0.,0.,1.,%g,0,0.,0.,%g,%g", H, H, R);
    int pbot = igw_add(&w, 108, 0, DEP, 0, 0, "0.,0.,1.,0.,0,0.,0.,0.,%g", R); /* normal +z: inward, of 0 */
    int l0v[4] = {v0, v2, v3, v1}, l0e[4] = {eb0, es1, et0, es0};
    bf(&b, rev0, 0, 4, l0v, l0e, NULL);
    int l1v[4] = {v2, v0, v1, v3}, l1e[4] = {eb1, es0, et1, es1};
    bf(&b, rev1, 0, 4, l1v, l1e, NULL);
    int tv[2] = {v1, v3}, te[2] = {et0, et1};
    bf(&b, ptop, 1, 2, tv, te, NULL);
    int bvv[2] = {v0, v2}, bee[2] = {eb0, eb1};
    bf(&b, pbot, 0, 2, bvv, bee, NULL);
    return brep_finish(&b, len);
}

char *iges_model_plane190_trimmed(size_t *len)
{
    static igw w;
    igw_init(&w);
    /* a 100 x 60 mm rectangle at z = 5 trimming a 190 plane (144 / 142, model-space curve only) */
    int pt = igw_add(&w, 116, 0, DEP, 0, 0, "0.,0.,5.");
    int nr = igw_add(&w, 123, 0, DEP, 0, 0, "0.,0.,1.");
    int pl = igw_add(&w, 190, 0, DEP, 0, 0, "%d,%d", pt, nr);
    const double c[5][2] = {{10, 20}, {110, 20}, {110, 80}, {10, 80}, {10, 20}};
    int e[4];
    for (int k = 0; k < 4; k++)
        e[k] = igw_add(&w, 110, 0, DEP, 0, 0, "%g,%g,5.,%g,%g,5.", c[k][0], c[k][1], c[k + 1][0], c[k + 1][1]);
    int cc = igw_add(&w, 102, 0, DEP, 0, 0, "4,%d,%d,%d,%d", e[0], e[1], e[2], e[3]);
    int cos = igw_add(&w, 142, 0, DEP, 0, 0, "0,%d,0,%d,2", pl, cc);
    igw_add(&w, 144, 0, 0, 0, 0, "%d,1,0,%d", pl, cos);
    /* and a free plane of its own, which has no extent to draw */
    int pt2 = igw_add(&w, 116, 0, DEP, 0, 0, "0.,0.,0.");
    int nr2 = igw_add(&w, 123, 0, DEP, 0, 0, "0.,1.,0.");
    igw_add(&w, 190, 0, 0, 0, 0, "%d,%d", pt2, nr2);
    char *t = igw_finish(&w, len);
    igw_free(&w);
    return t;
}

char *iges_model_bounded_band(bool same_way, size_t *len)
{
    static igw w;
    igw_init(&w);
    const double R = 30, H = 80;
    int axis = igw_add(&w, 110, 0, DEP, 0, 0, "0.,0.,0.,0.,0.,1.");
    int gen = igw_add(&w, 110, 0, DEP, 0, 0, "%g,0.,0.,%g,0.,%g", R, R, H);
    int rev = igw_add(&w, 120, 0, DEP, 0, 0, "%d,%d,0.,6.283185307179586", axis, gen);
    /* the two circles start at the same angle (+x); the top one runs the other way unless same_way */
    int bot = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,%g,0.,%g,0.", R, R);
    int top = igw_add(&w, 100, 0, DEP, 0, 0, "%g,0.,0.,%g,0.,%g,0.", H, R, R);
    int b0 = igw_add(&w, 141, 0, DEP, 0, 0, "0,1,%d,1,%d,1,0", rev, bot);
    int b1 = igw_add(&w, 141, 0, DEP, 0, 0, "0,1,%d,1,%d,%d,0", rev, top, same_way ? 1 : 2);
    igw_add(&w, 143, 0, 0, 0, 0, "0,%d,2,%d,%d", rev, b0, b1);
    char *s = igw_finish(&w, len);
    igw_free(&w);
    return s;
}

/* Cubic Bézier helpers for the free-form solid. */
static void bern3(double t, double *B)
{
    double s = 1 - t;
    B[0] = s * s * s, B[1] = 3 * t * s * s, B[2] = 3 * t * t * s, B[3] = t * t * t;
}

/* The part [a, b] of the cubic with control points q (4 x 3), by de Casteljau splits. */
static void bez_part(const double q[4][3], double a, double b, double out[4][3])
{
    double r[4][3], l[4][3];
    /* left part [0, b] */
    memcpy(r, q, sizeof r);
    for (int k = 0; k < 4; k++) {
        memcpy(l[k], r[0], sizeof l[k]);
        for (int i = 0; i < 3 - k; i++)
            for (int c = 0; c < 3; c++) r[i][c] = (1 - b) * r[i][c] + b * r[i + 1][c];
    }
    /* l holds [0, b]; its right part from a / b */
    double t = a / b;
    memcpy(r, l, sizeof r);
    double right[4][3];
    for (int k = 0; k < 4; k++) {
        memcpy(right[3 - k], r[3 - k], sizeof right[0]);
        for (int i = 0; i < 3 - k; i++)
            for (int c = 0; c < 3; c++) r[i][c] = (1 - t) * r[i][c] + t * r[i + 1][c];
    }
    memcpy(out, right, sizeof right);
}

static int curve126(igw *w, const double q[4][3])
{
    return igw_add(w, 126, 0, DEP, 0, 0,
                   "3,3,0,0,1,0,0.,0.,0.,0.,1.,1.,1.,1.,1.,1.,1.,1.,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                   "%.17g,%.17g,%.17g,%.17g,0.,1.,0.,0.,1.",
                   q[0][0], q[0][1], q[0][2], q[1][0], q[1][1], q[1][2], q[2][0], q[2][1], q[2][2], q[3][0], q[3][1], q[3][2]);
}

char *iges_model_brep_freeform(size_t *len)
{
    static igw w;
    igw_init(&w);
    static brep b;
    memset(&b, 0, sizeof b);
    b.w = &w;
    /* top: one bicubic Bézier patch over x in [-60, 60], y in [-45, 45] (x, y linear in u, v), z a
     * bump around 40; the solid is its part over [-40, 40] x [-30, 30] (u, v in [1/6, 5/6]) down to
     * z = 0 */
    static const double bump[4][4] = {{0, 1, 1, 0}, {1, 4, -2, 1}, {1, 3, 2, 1}, {0, 1, 1, 0}};
    double P[4][4][3]; /* [i][j] */
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) P[i][j][0] = -60 + 40.0 * i, P[i][j][1] = -45 + 30.0 * j, P[i][j][2] = 40 + 6 * bump[i][j];
    char buf[4096];
    int n = snprintf(buf, sizeof buf, "3,3,3,3,0,0,1,0,0,0.,0.,0.,0.,1.,1.,1.,1.,0.,0.,0.,0.,1.,1.,1.,1.");
    for (int k = 0; k < 16; k++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",1.");
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",%.17g,%.17g,%.17g", P[i][j][0], P[i][j][1], P[i][j][2]);
    snprintf(buf + n, sizeof buf - (size_t)n, ",0.,1.,0.,1.");
    int top = igw_add(&w, 128, 0, DEP, 0, 0, "%s", buf);
    const double lo = 1.0 / 6, hi = 5.0 / 6;
    /* isocurves u = lo, hi (running in v) and v = lo, hi (running in u), cut to [lo, hi] */
    double iso[4][4][3], cut[4][4][3];
    for (int s = 0; s < 2; s++) {
        double B[4];
        bern3(s ? hi : lo, B);
        for (int k = 0; k < 4; k++)
            for (int c = 0; c < 3; c++) {
                iso[s][k][c] = iso[2 + s][k][c] = 0;
                for (int m = 0; m < 4; m++) {
                    iso[s][k][c] += B[m] * P[m][k][c];     /* u fixed: control point k along v */
                    iso[2 + s][k][c] += B[m] * P[k][m][c]; /* v fixed: control point k along u */
                }
            }
    }
    for (int s = 0; s < 4; s++) bez_part(iso[s], lo, hi, cut[s]);
    /* corners: c[i][j] at (u, v) = (i ? hi : lo, j ? hi : lo) */
    int c[2][2], f[2][2];
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            const double *q = cut[i][j ? 3 : 0]; /* curve u = i along v: start at v = lo, end at hi */
            c[i][j] = bv(&b, q[0], q[1], q[2]);
            f[i][j] = bv(&b, q[0], q[1], 0);
        }
    int top_e[4]; /* u = lo, u = hi (c[i][0] -> c[i][1]); v = lo, v = hi (c[0][j] -> c[1][j]) */
    for (int i = 0; i < 2; i++) top_e[i] = be(&b, curve126(&w, cut[i]), c[i][0], c[i][1]);
    for (int j = 0; j < 2; j++) top_e[2 + j] = be(&b, curve126(&w, cut[2 + j]), c[0][j], c[1][j]);
    int bot_c[4];
    int bot_e[4];
    for (int i = 0; i < 2; i++) {
        bot_c[i] = line(&w, b.vx[f[i][0]], b.vx[f[i][1]]);
        bot_e[i] = be(&b, bot_c[i], f[i][0], f[i][1]);
    }
    for (int j = 0; j < 2; j++) {
        bot_c[2 + j] = line(&w, b.vx[f[0][j]], b.vx[f[1][j]]);
        bot_e[2 + j] = be(&b, bot_c[2 + j], f[0][j], f[1][j]);
    }
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) be(&b, line(&w, b.vx[f[i][j]], b.vx[c[i][j]]), f[i][j], c[i][j]);
    /* top (normal +z, of 1) */
    int tv[4] = {c[0][0], c[1][0], c[1][1], c[0][1]}, tev[4] = {top_e[2], top_e[1], top_e[3], top_e[0]};
    bf(&b, top, 1, 4, tv, tev, NULL);
    /* bottom: a plane larger than the face, normal -z */
    double a0[3] = {-50, -40, 0}, a1[3] = {-50, 40, 0}, a2[3] = {50, -40, 0}, a3[3] = {50, 40, 0};
    int bot = plane128(&w, a0, a1, a2, a3);
    int bvv[4] = {f[0][0], f[1][0], f[1][1], f[0][1]}, bev[4] = {bot_e[2], bot_e[1], bot_e[3], bot_e[0]};
    bf(&b, bot, 1, 4, bvv, bev, NULL);
    /* sides: ruled (118) from the bottom line to the top curve; x = -40 and y = +30 come out inward */
    int cu[4][2] = {{bot_c[0], top_e[0]}, {bot_c[1], top_e[1]}, {bot_c[2], top_e[2]}, {bot_c[3], top_e[3]}};
    int ofs[4] = {0, 1, 1, 0};
    for (int s = 0; s < 4; s++) {
        int rs = igw_add(&w, 118, 1, DEP, 0, 0, "%d,%d,0,0", cu[s][0], b.ecurve[cu[s][1]]);
        int i = s < 2 ? s : 0, j = s < 2 ? 0 : s - 2;
        int sv[4];
        if (s < 2) sv[0] = f[i][0], sv[1] = f[i][1], sv[2] = c[i][1], sv[3] = c[i][0];
        else sv[0] = f[0][j], sv[1] = f[1][j], sv[2] = c[1][j], sv[3] = c[0][j];
        bf(&b, rs, ofs[s], 4, sv, NULL, NULL);
    }
    return brep_finish(&b, len);
}

char *iges_model_spike_loop(double e, size_t *len)
{
    static igw w;
    igw_init(&w);
    const double p00[3] = {-10, -10, 0}, p10[3] = {20, -10, 0}, p01[3] = {-10, 20, 0}, p11[3] = {20, 20, 0};
    int pl = plane128(&w, p00, p10, p01, p11);
    const double a[3] = {10, 0, 0}, o[3] = {0, 0, 0}, c[3] = {4, 10, 0}, d[3] = {10, 10, 0};
    int l0 = line(&w, a, o);
    /* (0, 0) back along y = 0 to (4, 0), zig-zagging +-e across the line, then up to (4, 10) */
    enum { NZ = 10 };
    double z[NZ][2] = {{0, 0}, {0.5, e}, {1, -e}, {1.5, e}, {2, -e}, {2.5, e}, {3, -e}, {3.5, e}, {4, 0}, {4, 10}};
    char buf[2048];
    int n = snprintf(buf, sizeof buf, "%d,1,1,0,1,0,0.,0.", NZ - 1);
    for (int k = 1; k < NZ - 1; k++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",%d.", k);
    n += snprintf(buf + n, sizeof buf - (size_t)n, ",%d.,%d.", NZ - 1, NZ - 1);
    for (int k = 0; k < NZ; k++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",1.");
    for (int k = 0; k < NZ; k++) n += snprintf(buf + n, sizeof buf - (size_t)n, ",%.17g,%.17g,0.", z[k][0], z[k][1]);
    snprintf(buf + n, sizeof buf - (size_t)n, ",0.,%d.,0.,0.,1.", NZ - 1);
    int l1 = igw_add(&w, 126, 0, DEP, 0, 0, "%s", buf);
    int l2 = line(&w, c, d), l3 = line(&w, d, a);
    int b = igw_add(&w, 141, 0, DEP, 0, 0, "0,1,%d,4,%d,1,0,%d,1,0,%d,1,0,%d,1,0", pl, l0, l1, l2, l3);
    igw_add(&w, 143, 0, 0, 0, 0, "0,%d,1,%d", pl, b);
    char *s = igw_finish(&w, len);
    igw_free(&w);
    return s;
}

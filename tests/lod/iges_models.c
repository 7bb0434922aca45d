/* Hand-made IGES test models (see iges_models.h). */
#include "iges_models.h"

#include "iges_writer.h"

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

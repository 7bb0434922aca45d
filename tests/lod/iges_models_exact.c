/* Test models for the exactly converted entities 104, 114 and 140 (see iges_models.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "iges_models.h"
#include "iges_writer.h"

#define DEP 1 /* physically dependent */

const double iges_model_spline114_z[4][4] = {{0, 0, 1, 0}, {0.5, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0.25}};

/* A 100 x 100 mm bilinear plane patch (128) at offset (ox, oy), physically dependent. */
static int plane128(igw *w, double ox, double oy)
{
    return igw_add(w, 128, 0, DEP, 0, 0,
                   "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,"
                   "%.17g,%.17g,0.,%.17g,%.17g,0.,%.17g,%.17g,0.,%.17g,%.17g,0.,0.,1.,0.,1.",
                   ox, oy, ox + 100, oy, ox, oy + 100, ox + 100, oy + 100);
}

/* A trimmed face (144) of `surf` bounded by the model-space curve `curve` (142, projected). */
static void face(igw *w, int surf, int curve)
{
    int b = igw_add(w, 142, 0, DEP, 0, 0, "0,%d,0,%d,2", surf, curve);
    igw_add(w, 144, 0, 0, 0, 0, "%d,1,0,%d", surf, b);
}

static char *finish(igw *w, size_t *len)
{
    char *s = igw_finish(w, len);
    igw_free(w);
    return s;
}

char *iges_model_conics(size_t *len)
{
    igw w;
    igw_init(&w);
    const double cx = 50, cy = 40, a = 30, b = 15, ph = 3.14159265358979323846 / 6, c = cos(ph), s = sin(ph);
    double A = c * c / (a * a) + s * s / (b * b), B = 2 * c * s * (1 / (a * a) - 1 / (b * b)), C = s * s / (a * a) + c * c / (b * b);
    double D = -2 * A * cx - B * cy, E = -B * cx - 2 * C * cy, F = A * cx * cx + B * cx * cy + C * cy * cy - 1;
    double sx = cx + a * c, sy = cy + a * s;
    int el = igw_add(&w, 104, 1, DEP, 0, 0, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0.,%.17g,%.17g,%.17g,%.17g", A, B, C, D, E,
                     F, sx, sy, sx, sy);
    face(&w, plane128(&w, 0, 0), el);
    const double x0 = 40, y0 = 10 * sqrt(x0 * x0 / 400 - 1);
    int hy = igw_add(&w, 104, 2, DEP, 0, 0, "1.,0.,-4.,0.,0.,-400.,0.,%.17g,%.17g,%.17g,%.17g", x0, -y0, x0, y0);
    int hl = igw_add(&w, 110, 0, DEP, 0, 0, "%.17g,%.17g,0.,%.17g,%.17g,0.", x0, y0, x0, -y0);
    face(&w, plane128(&w, 0, -50), igw_add(&w, 102, 0, DEP, 0, 0, "2,%d,%d", hy, hl));
    int pa = igw_add(&w, 104, 3, DEP, 0, 0, "0.,0.,1.,-20.,0.,0.,0.,20.,-20.,20.,20.");
    int pl = igw_add(&w, 110, 0, DEP, 0, 0, "20.,20.,0.,20.,-20.,0.");
    face(&w, plane128(&w, -10, -50), igw_add(&w, 102, 0, DEP, 0, 0, "2,%d,%d", pa, pl));
    return finish(&w, len);
}

static double binom(int n, int k) { return k == 0 || k == n ? 1 : n == 3 ? 3 : 2; }

char *iges_model_spline114(size_t *len)
{
    const double TU[3] = {0, 1, 2.5}, TV[3] = {-1, 0.5, 1};
    const int M = 2, N = 2;
    char *buf = malloc(60000);
    int n = sprintf(buf, "3,1,%d,%d", M, N);
    for (int i = 0; i <= M; i++) n += sprintf(buf + n, ",%.17g", TU[i]);
    for (int j = 0; j <= N; j++) n += sprintf(buf + n, ",%.17g", TV[j]);
    for (int i = 0; i < M; i++) {
        for (int j = 0; j < N; j++) {
            double cx[16] = {0}, cy[16] = {0}, cz[16] = {0};
            cx[0] = TU[i], cx[1] = 1; /* X = u */
            cy[0] = TV[j], cy[4] = 1; /* Y = v */
            /* u^k v^l = (U + s)^k (V + t)^l expanded; coefficient of s^p t^q at p + 4 q */
            for (int k = 0; k < 4; k++)
                for (int l = 0; l < 4; l++)
                    for (int p = 0; p <= k; p++)
                        for (int q = 0; q <= l; q++)
                            cz[p + 4 * q] += iges_model_spline114_z[k][l] * binom(k, p) * pow(TU[i], k - p) * binom(l, q) *
                                             pow(TV[j], l - q);
            for (int q = 0; q < 16; q++) n += sprintf(buf + n, ",%.17g", cx[q]);
            for (int q = 0; q < 16; q++) n += sprintf(buf + n, ",%.17g", cy[q]);
            for (int q = 0; q < 16; q++) n += sprintf(buf + n, ",%.17g", cz[q]);
        }
        for (int q = 0; q < 48; q++) n += sprintf(buf + n, ",0."); /* the unused patch N + 1 */
    }
    for (int q = 0; q < 48 * (N + 1); q++) n += sprintf(buf + n, ",0."); /* the unused row M + 1 */
    igw w;
    igw_init(&w);
    w.unit_flag = 6, w.unit = "M";
    igw_add(&w, 114, 0, 0, 0, 0, "%s", buf);
    free(buf);
    return finish(&w, len);
}

char *iges_model_offsets(size_t *len)
{
    igw w;
    igw_init(&w);
    w.unit_flag = 6, w.unit = "M";
    int pln = igw_add(&w, 108, 0, DEP, 0, 0, "0.,0.,1.,0.,0,0.,0.,0.,0.");
    int off = igw_add(&w, 140, 0, DEP, 0, 0, "0.,0.,1.,0.25,%d", pln);
    int sq[4];
    const double q[5][2] = {{0, 0}, {2, 0}, {2, 1}, {0, 1}, {0, 0}};
    for (int i = 0; i < 4; i++)
        sq[i] = igw_add(&w, 110, 0, DEP, 0, 0, "%g,%g,0.25,%g,%g,0.25", q[i][0], q[i][1], q[i + 1][0], q[i + 1][1]);
    face(&w, off, igw_add(&w, 102, 0, DEP, 0, 0, "4,%d,%d,%d,%d", sq[0], sq[1], sq[2], sq[3]));
    int ax = igw_add(&w, 110, 0, DEP, 0, 0, "0.,0.,0.,0.,0.,1.");
    int gl = igw_add(&w, 110, 0, DEP, 0, 0, "1.,0.,0.,1.,0.,3.");
    int cyl = igw_add(&w, 120, 0, DEP, 0, 0, "%d,%d,0.,6.283185307179586", ax, gl);
    igw_add(&w, 140, 0, 0, 0, 0, "-1.,0.,0.,0.25,%d", cyl);
    int ay = igw_add(&w, 110, 0, DEP, 0, 0, "0.,-1.,0.,0.,1.,0.");
    int arc = igw_add(&w, 100, 0, DEP, 0, 0, "0.,0.,0.,0.,-2.,0.,2.");
    int sph = igw_add(&w, 120, 0, DEP, 0, 0, "%d,%d,0.,6.283185307179586", ay, arc);
    igw_add(&w, 140, 0, 0, 0, 0, "1.,0.,0.,-0.5,%d", sph);
    igw_add(&w, 140, 0, 0, 0, 0, "0.,0.,1.,1.,%d", plane128(&w, 0, 0));
    return finish(&w, len);
}

/* gen_ggx_fit — writes materials/prw_ggx_fit.h, the GGX albedo functions of the shared material
 * header prw_brdf.h (multiple-scattering compensation after Kulla & Conty 2017, "Revisiting
 * Physically Based Shading at Imageworks", and the reciprocal diffuse-specular coupling).
 *
 *   cc -O2 -std=c17 materials/tools/gen_ggx_fit.c -lm -o gen_ggx_fit
 *   ./gen_ggx_fit > materials/prw_ggx_fit.h        (~30 s; prints its accuracy on stderr)
 * (or build the CMake target prw_gen_ggx_fit and run build/materials/prw_gen_ggx_fit).
 *
 * Quantities, for perceptual roughness r (alpha = max(r^2, 0.002) as prw_alpha_from_roughness):
 *   Ec(mu, r) = 1 - E(mu, alpha),  E the directional albedo of the single-scattering GGX lobe
 *               D * G2 / (4 mu_o mu_i) with F = 1 (height-correlated Smith G2, Heitz 2014);
 *   Ed(mu, r) = the same albedo with the exact unpolarised Fresnel reflectance of a dielectric of
 *               relative IOR 1.5 (F0 = 0.04) evaluated at the microfacet (wo . wm);
 *   Ec_avg, Ed_avg = 2 int X(mu) mu dmu of the FITTED functions (so the compensation and coupling
 *               lobes integrate to what the model promises, up to the 1-D fit);
 *   F_avg = 2 int F_dielectric(mu) mu dmu.
 * Representation: not a table (a large constant array costs lavapipe 40-100 s of LLVM compile time
 * per shader) but straight-line code: tensor Chebyshev interpolants at 16 x 16 Chebyshev-Gauss nodes
 * (see the fit section below), evaluated in float with the same operations in C and GLSL.
 *
 * Integration method (double precision): over the visible normals (see albedo() below), with
 * composite Gauss-Legendre quadrature, 96 panels x 8 nodes in the disk radius and 96 panels x 8
 * nodes in its angle, i.e. 589 824 integrand evaluations per node (checked against an independent
 * quadrature over the half vector in tests/materials/test_brdf_model.c).  The averages use 64 x 8
 * Gauss-Legendre nodes in sqrt(mu) over the fitted function; F_avg 64 x 8 nodes.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NF 16 /* Chebyshev terms per axis */
#define PANELS 96
#define PI 3.14159265358979323846

static double gl_x[8], gl_w[8]; /* Gauss-Legendre nodes/weights on [-1, 1] */

/* Nodes as roots of P_8 by Newton iteration from the Chebyshev guess (Abramowitz & Stegun 25.4.29). */
static void gauss_legendre_init(void)
{
    const int n = 8;
    for (int i = 0; i < n; i++) {
        double x = cos(PI * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = x;
            for (int k = 2; k <= n; k++) {
                double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = n * (x * p1 - p0) / (x * x - 1);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16) break;
        }
        gl_x[i] = x;
        gl_w[i] = 2 / ((1 - x * x) * dp * dp);
    }
}

static double fresnel_dielectric(double c, double eta)
{
    double g2 = eta * eta - 1 + c * c;
    if (g2 < 0) return 1;
    double g = sqrt(g2), a = (g - c) / (g + c), b = (c * (g + c) - 1) / (c * (g - c) + 1);
    return 0.5 * a * a * (1 + b * b);
}

static double lambda_ggx(double mu, double alpha)
{
    double t2 = (1 - mu * mu) / (mu * mu);
    return 0.5 * (sqrt(1 + alpha * alpha * t2) - 1);
}

/* Albedo of the GGX lobe at cos(theta_o) = mu; fresnel: 0 for F = 1, 1 for the dielectric.
 * Over the distribution of visible normals D_wo(wm) = G1(wo) D(wm) (wo.wm) / mu_o (Heitz 2014), the
 * albedo is E = int D_wo(wm) F(wo.wm) G2(wo, wi) / G1(wo) dwm, wi = reflect(wo, wm), wi.z > 0: a
 * bounded integrand.  The visible normals are parameterised as in Heitz 2018 ("Sampling the GGX
 * Distribution of Visible Normals"): a uniform point (r, phi) on the unit disk, warped and lifted
 * onto the hemisphere seen from the stretched view direction, then unstretched; the map is
 * measure-preserving, so E = 1/pi int_0^1 int_0^{2 pi} F G2 / G1(wo) r dphi dr. */
static double albedo(double mu, double alpha, int fresnel)
{
    double so = sqrt(1 - mu * mu), lo = lambda_ggx(mu, alpha), sum = 0;
    double vh[3] = {alpha * so, 0, mu};
    double vl = sqrt(vh[0] * vh[0] + vh[2] * vh[2]);
    vh[0] /= vl, vh[2] /= vl;
    /* T1 = (0, 1, 0) (vh has no y component), T2 = vh x T1 = (-vh.z, 0, vh.x) */
    double warp = 0.5 * (1 + vh[2]);
    for (int pr = 0; pr < PANELS; pr++)
        for (int ir = 0; ir < 8; ir++) {
            double r = (pr + 0.5 + 0.5 * gl_x[ir]) / PANELS, wr = 0.5 * gl_w[ir] / PANELS;
            for (int pp = 0; pp < PANELS; pp++)
                for (int ip = 0; ip < 8; ip++) {
                    double ph = 2 * PI * (pp + 0.5 + 0.5 * gl_x[ip]) / PANELS, wp = PI * gl_w[ip] / PANELS;
                    double t1 = r * cos(ph), t2 = r * sin(ph);
                    t2 = (1 - warp) * sqrt(1 - t1 * t1) + warp * t2;
                    double tz = sqrt(fmax(0.0, 1 - t1 * t1 - t2 * t2));
                    double n[3] = {-t2 * vh[2] + tz * vh[0], t1, t2 * vh[0] + tz * vh[2]};
                    double m[3] = {alpha * n[0], alpha * n[1], fmax(0.0, n[2])};
                    double ml = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
                    if (!(ml > 0)) continue;
                    for (int k = 0; k < 3; k++) m[k] /= ml;
                    double om = so * m[0] + mu * m[2];
                    double wiz = 2 * om * m[2] - mu;
                    if (om <= 0 || wiz <= 0) continue;
                    double g2_over_g1 = (1 + lo) / (1 + lo + lambda_ggx(wiz, alpha));
                    double f = fresnel ? fresnel_dielectric(om, 1.5) : 1.0;
                    sum += wr * wp * r * g2_over_g1 * f;
                }
        }
    return sum / PI;
}

/* ---- the fit ----
 * Coordinates: t = sqrt(mu) clamped to [T_MIN, 1] (mu < 0.01, i.e. within 0.6 degrees of grazing,
 * uses the value at mu = 0.01), s = sqrt(alpha) = max(r, sqrt(0.002)) (removes the kink of the
 * alpha clamp), each mapped to [-1, 1].  Fitted quantity: y = log(value + EPS), interpolated at
 * NF x NF Chebyshev-Gauss nodes (coefficients by the discrete cosine transform; Trefethen,
 * "Approximation Theory and Approximation Practice", ch. 3), so value = exp(y) - EPS >= -EPS. */
#define T_MIN 0.1
#define EPS 1e-3
static const double S_MIN = 0.044721359549995794; /* sqrt(0.002) */

static double map_t(double mu) { double t = sqrt(mu < 0 ? 0 : mu > 1 ? 1 : mu); t = t < T_MIN ? T_MIN : t; return 2 * (t - T_MIN) / (1 - T_MIN) - 1; }
static double map_s(double r) { r = r < 0 ? 0 : r > 1 ? 1 : r; double s = r < S_MIN ? S_MIN : r; return 2 * (s - S_MIN) / (1 - S_MIN) - 1; }
static double node(int k) { return cos(PI * (k + 0.5) / NF); } /* in [-1, 1] */

static void cheb(double x, double t[NF])
{
    t[0] = 1, t[1] = x;
    for (int k = 2; k < NF; k++) t[k] = 2 * x * t[k - 1] - t[k - 2];
}

/* The offset of the log (constant; a roughness-dependent offset rang more). */
static double eps_of_v(double v)
{
    double s = S_MIN + (1 - S_MIN) * 0.5 * (v + 1), s4 = s * s * s * s;
    (void)s4;
    return EPS;
}

static double eval2(const double c[NF][NF], double u, double v)
{
    double a[NF], b[NF], s = 0;
    cheb(u, a), cheb(v, b);
    for (int j = 0; j < NF; j++) {
        double row = 0;
        for (int i = 0; i < NF; i++) row += c[j][i] * a[i];
        s += b[j] * row;
    }
    return exp(s) - eps_of_v(v);
}

/* The averages are fitted as log(value + EPS_AVG): they must be accurate relative to themselves
 * even where tiny (the compensation lobe divides by Ec_avg). */
#define EPS_AVG 1e-6
static double eval1(const double c[NF], double v)
{
    double b[NF], s = 0;
    cheb(v, b);
    for (int j = 0; j < NF; j++) s += c[j] * b[j];
    return exp(s) - EPS_AVG;
}

static void fit2(double g[NF][NF], double c[NF][NF])
{
    for (int j = 0; j < NF; j++)
        for (int i = 0; i < NF; i++) {
            double s = 0;
            for (int l = 0; l < NF; l++)
                for (int k = 0; k < NF; k++) s += g[l][k] * cos(PI * i * (k + 0.5) / NF) * cos(PI * j * (l + 0.5) / NF);
            c[j][i] = s * (i ? 2.0 : 1.0) * (j ? 2.0 : 1.0) / (NF * NF);
        }
}

static void fit1(const double g[NF], double c[NF])
{
    for (int j = 0; j < NF; j++) {
        double s = 0;
        for (int l = 0; l < NF; l++) s += g[l] * cos(PI * j * (l + 0.5) / NF);
        c[j] = s * (j ? 2.0 : 1.0) / NF;
    }
}

/* 2 int_0^1 f(mu) mu dmu = 4 int_0^1 f(t^2) t^3 dt of the fitted function (with its clamp at T_MIN). */
static double cosine_average(const double c[NF][NF], double v)
{
    double s = 0;
    for (int p = 0; p < 64; p++)
        for (int q = 0; q < 8; q++) {
            double t = (p + 0.5 + 0.5 * gl_x[q]) / 64;
            s += 0.5 * gl_w[q] / 64 * eval2(c, map_t(t * t), v) * t * t * t;
        }
    return 4 * s;
}

/* float literal readable by C and GLSL: 9 significant digits, a '.' or exponent, suffix f */
static const char *lit(double v)
{
    static char buf[8][48];
    static int k;
    char *b = buf[k++ & 7];
    snprintf(b, 40, "%.9g", (double)(float)v);
    if (!strpbrk(b, ".e")) strcat(b, ".0");
    strcat(b, "f");
    return b;
}

static void emit_cheb(const char *var, const char *x)
{
    printf("    float %s0 = 1.0f, %s1 = %s;\n", var, var, x);
    for (int k = 2; k < NF; k++) printf("    float %s%d = 2.0f * %s * %s%d - %s%d;\n", var, k, x, var, k - 1, var, k - 2);
}

/* The 2-D fit as row (roughness: the v basis contracted with the coefficients, d_i = sum_j c_ji b_j)
 * and evaluation at mu (y = sum_i d_i a_i): a shader shading several lights at one roughness computes the
 * row once.  name(mu, roughness) is the two composed (the same operations). */
static void emit2(const char *name, const char *doc, const double c[NF][NF])
{
    printf("/* %s: %s_row(roughness), then %s_at(row, mu) */\n", doc, name, name);
    printf("PRW_FN prw_ggx_row %s_row(float roughness)\n{\n    float v = prw_ggx_fit_v(roughness);\n", name);
    emit_cheb("b", "v");
    printf("    prw_ggx_row r;\n");
    for (int i = 0; i < NF; i++) {
        printf("    r.d%d = ", i);
        for (int j = 0; j < NF; j++) printf("%s%s * b%d%s", j ? " + " : "", lit(c[j][i]), j, j % 4 == 3 && j + 1 < NF ? "\n           " : "");
        printf(";\n");
    }
    printf("    return r;\n}\n\n");
    printf("PRW_FN float %s_at(prw_ggx_row r, float mu)\n{\n    float u = prw_ggx_fit_u(mu);\n", name);
    emit_cheb("a", "u");
    printf("    float y = ");
    for (int i = 0; i < NF; i++) printf("%sr.d%d * a%d%s", i ? " + " : "", i, i, i % 4 == 3 && i + 1 < NF ? "\n              " : "");
    printf(";\n    return PRW_B_MAX(prw_exp(y) - %s, 0.0f);\n}\n\n", lit(EPS));
    printf("PRW_FN float %s(float mu, float roughness) { return %s_at(%s_row(roughness), mu); }\n\n", name, name, name);
}

static void emit1(const char *name, const char *doc, const double c[NF])
{
    printf("/* %s */\nPRW_FN float %s(float roughness)\n{\n    float v = prw_ggx_fit_v(roughness);\n", doc, name);
    emit_cheb("b", "v");
    printf("    float y = ");
    for (int j = 0; j < NF; j++) printf("%s%s * b%d%s", j ? " + " : "", lit(c[j]), j, j % 4 == 3 && j + 1 < NF ? "\n              " : "");
    printf(";\n    return PRW_B_MAX(prw_exp(y) - %s, 0.0f);\n}\n\n", lit(EPS_AVG));
}

int main(void)
{
    gauss_legendre_init();
    static double g_ec[NF][NF], g_ed[NF][NF], c_ec[NF][NF], c_ed[NF][NF];
    double a_ec[NF], a_ed[NF], ca_ec[NF], ca_ed[NF];
    for (int l = 0; l < NF; l++) {
        double s = S_MIN + (1 - S_MIN) * 0.5 * (node(l) + 1), alpha = s * s;
        for (int k = 0; k < NF; k++) {
            double t = T_MIN + (1 - T_MIN) * 0.5 * (node(k) + 1), mu = t * t;
            g_ec[l][k] = log(1 - albedo(mu, alpha, 0) + eps_of_v(node(l)));
            g_ed[l][k] = log(albedo(mu, alpha, 1) + eps_of_v(node(l)));
        }
    }
    fit2(g_ec, c_ec);
    fit2(g_ed, c_ed);
    for (int l = 0; l < NF; l++) {
        a_ec[l] = log(cosine_average(c_ec, node(l)) + EPS_AVG);
        a_ed[l] = log(cosine_average(c_ed, node(l)) + EPS_AVG);
    }
    fit1(a_ec, ca_ec);
    fit1(a_ed, ca_ed);
    double favg = 0;
    for (int p = 0; p < 64; p++)
        for (int k = 0; k < 8; k++) {
            double mu = (p + 0.5 + 0.5 * gl_x[k]) / 64;
            favg += 0.5 * gl_w[k] / 64 * 2 * mu * fresnel_dielectric(mu, 1.5);
        }
    /* report the fit against direct integration between the nodes (stderr) */
    double we = 0, wd = 0, wa = 0;
    for (int j = 0; j < 12; j++)
        for (int i = 0; i < 12; i++) {
            double r = (j + 0.5) / 12, t = 0.1 + 0.9 * (i + 0.5) / 12, mu = t * t, alpha = r * r < 0.002 ? 0.002 : r * r;
            double e = albedo(mu, alpha, 0), ed = albedo(mu, alpha, 1);
            we = fmax(we, fabs((1 - eval2(c_ec, map_t(mu), map_s(r))) / e - 1));
            wd = fmax(wd, fabs(eval2(c_ed, map_t(mu), map_s(r)) / ed - 1));
        }
    for (int j = 0; j <= 40; j++) {
        double v = map_s(j / 40.0);
        double a1 = cosine_average(c_ec, v), a2 = cosine_average(c_ed, v);
        if (a1 > 1e-4) wa = fmax(wa, fabs(eval1(ca_ec, v) / a1 - 1));
        wa = fmax(wa, fabs(eval1(ca_ed, v) / a2 - 1));
    }
    fprintf(stderr, "fit vs direct integration (mu >= 0.01): E worst relative %.3g, Ed worst relative %.3g; "
                    "averages vs the average of the fit: worst relative %.3g (where > 1e-4)\n", we, wd, wa);

    printf("/* prw_ggx_fit.h — GENERATED by materials/tools/gen_ggx_fit.c; do not edit.\n"
           " * Regenerate: cc -O2 -std=c17 materials/tools/gen_ggx_fit.c -lm -o gen_ggx_fit &&\n"
           " *             ./gen_ggx_fit > materials/prw_ggx_fit.h\n"
           " * GGX albedos for prw_brdf.h as straight-line code (C17 and GLSL 4.50; included by prw_brdf.h after its\n"
           " * macros).  Tensor Chebyshev interpolants (%d x %d) of y = log(value + %g) in\n"
           " *   u = 2 (t - %g) / (1 - %g) - 1, t = max(sqrt(mu), %g);  v = 2 (s - sqrt(0.002)) / (1 - sqrt(0.002)) - 1,\n"
           " *   s = max(roughness, sqrt(0.002)) = sqrt(alpha);\n"
           " * evaluated in float with the same operations in C and GLSL (per roughness a row of %d coefficients, then\n"
           " * the mu basis).  Fit vs direct integration for\n"
           " * mu >= 0.01: E worst relative %.2g, Ed worst relative %.2g (see the generator for the method).\n"
           " * The averages are 1-D interpolants of the cosine-weighted average of the fitted 2-D function\n"
           " * (relative agreement %.2g where above 1e-4), so the compensation and coupling lobes integrate to what the model promises. */\n"
           "#ifndef PRW_GGX_FIT_H\n#define PRW_GGX_FIT_H\n\n", NF, NF, EPS, T_MIN, T_MIN, T_MIN, NF, we, wd, wa);
    printf("/* 2 int_0^1 F_dielectric(mu) mu dmu for IOR 1.5 */\n#define PRW_DIELECTRIC_F_AVG %s\n\n", lit(favg));
    printf("/* A 2-D fit with its roughness fixed: the coefficients of the mu basis (prw_ggx_*_row). */\n#ifdef GL_core_profile\nstruct prw_ggx_row {\n#else\ntypedef struct prw_ggx_row {\n#endif\n    float ");
    for (int i = 0; i < NF; i++) printf("%sd%d", i ? ", " : "", i);
    printf(";\n#ifdef GL_core_profile\n};\n#else\n} prw_ggx_row;\n#endif\n\n");
    printf("PRW_FN float prw_ggx_fit_u(float mu)\n{\n    float t = PRW_B_MAX(PRW_B_SQRT(prw_clamp01(mu)), %s);\n"
           "    return (t - %s) * %s - 1.0f;\n}\n\n", lit(T_MIN), lit(T_MIN), lit(2 / (1 - T_MIN)));
    printf("PRW_FN float prw_ggx_fit_v(float roughness)\n{\n    float s = PRW_B_MAX(prw_clamp01(roughness), %s);\n"
           "    return (s - %s) * %s - 1.0f;\n}\n\n", lit(S_MIN), lit(S_MIN), lit(2 / (1 - S_MIN)));
    emit2("prw_ggx_Ec", "1 - E(mu, alpha): the energy the single-scattering GGX lobe (F = 1) loses", c_ec);
    emit2("prw_ggx_Ed", "E_d(mu, alpha): albedo of the single-scattering GGX lobe with the exact dielectric Fresnel", c_ed);
    emit1("prw_ggx_Ec_avg", "2 int Ec(mu) mu dmu", ca_ec);
    emit1("prw_ggx_Ed_avg", "2 int Ed(mu) mu dmu", ca_ed);
    printf("#endif\n");
    return 0;
}

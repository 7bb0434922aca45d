/* The material model of materials/prw_brdf.h checked on its own (DESIGN §5): reciprocity, the
 * Lambert albedo, the fitted GGX albedos and the single-scattering lobe against an independent
 * double-precision quadrature (mat_testutil.h: D, G2 and Fresnel written from the formulas),
 * energy conservation of the full model on a grid, and the white furnace of a white metal. */
#include <stdio.h>
#include <stdlib.h>

#include "mat_testutil.h"
#include "prw_brdf.h"
#include "prw_bsdf.h"
#include "prw_test.h"

static void random_dir(mt_rng *r, double w[3], double min_cos)
{
    /* cos(theta) spread towards grazing: half the draws within [min_cos, 0.05] */
    double u = mt_rand(r);
    double c = u < 0.5 ? min_cos + (0.05 - min_cos) * mt_rand(r) : mt_rand(r);
    c = fmax(c, min_cos);
    double s = sqrt(fmax(0.0, 1 - c * c)), ph = 2 * MT_PI * mt_rand(r);
    w[0] = s * cos(ph), w[1] = s * sin(ph), w[2] = c;
}

static prw_bsdf random_material(mt_rng *r)
{
    prw_bsdf b = {0};
    for (int c = 0; c < 3; c++) b.base[c] = mt_rand(r);
    b.metallic = mt_rand(r) < 0.3 ? 1.0 : mt_rand(r) < 0.3 ? 0.0 : mt_rand(r);
    b.roughness = mt_rand(r) < 0.1 ? 0.0 : mt_rand(r);
    b.specular = mt_rand(r) < 0.2 ? 0.0 : mt_rand(r) < 0.5 ? 1.0 : mt_rand(r);
    return b;
}

/* f(wo, wi) = f(wi, wo): through the C API (vectors) and through the header's entry point with the
 * cosine arguments swapped. */
static void test_reciprocity(void)
{
    mt_rng r = {1};
    double worst = 0, worst_h = 0;
    int n = 200000, bad = 0;
    for (int k = 0; k < n; k++) {
        prw_bsdf b = random_material(&r);
        double wo[3], wi[3], f1[3], f2[3];
        random_dir(&r, wo, 1e-4);
        random_dir(&r, wi, 1e-4);
        prw_bsdf_eval(&b, wo, wi, f1);
        prw_bsdf_eval(&b, wi, wo, f2);
        for (int c = 0; c < 3; c++) {
            double rel = fabs(f1[c] - f2[c]) / fmax(fabs(f1[c]), 1e-30);
            if (f1[c] == 0 && f2[c] == 0) rel = 0;
            if (!(rel <= 1e-6)) bad++;
            if (rel > worst) worst = rel;
        }
        /* header directly: swap NoV and NoL (h and VoH are symmetric by definition) */
        float NoV = (float)wo[2], NoL = (float)wi[2];
        double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
        double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        float NoH = (float)(h[2] / hl), VoH = (float)((wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]) / hl);
        float a = prw_brdf_channel(NoV, NoL, NoH, VoH, (float)b.base[0], (float)b.metallic, (float)b.roughness,
                                   (float)b.specular);
        float c = prw_brdf_channel(NoL, NoV, NoH, VoH, (float)b.base[0], (float)b.metallic, (float)b.roughness,
                                   (float)b.specular);
        double rel = a == c ? 0 : fabs((double)a - c) / fmax(fabs((double)a), 1e-30);
        if (!(rel <= 1e-6)) bad++;
        if (rel > worst_h) worst_h = rel;
    }
    printf("reciprocity: %d configurations (cos down to 1e-4), worst relative %.3g (C API), %.3g (header, "
           "cosines swapped), %d beyond 1e-6\n",
           n, worst, worst_h, bad);
    CHECK(bad == 0);
}

/* int f cos dw over the hemisphere by 8-node GL, 32 panels in mu_i and in phi (full circle). */
static double albedo_cosgrid(const prw_bsdf *b, double mu_o, int channel)
{
    mt_gl g = mt_gl8();
    double wo[3] = {sqrt(1 - mu_o * mu_o), 0, mu_o}, sum = 0;
    const int P = 32;
    for (int pm = 0; pm < P; pm++)
        for (int im = 0; im < 8; im++) {
            double mu = (pm + 0.5 + 0.5 * g.x[im]) / P, wm = 0.5 * g.w[im] / P;
            double s = sqrt(1 - mu * mu);
            for (int pp = 0; pp < P; pp++)
                for (int ip = 0; ip < 8; ip++) {
                    double ph = 2 * MT_PI * (pp + 0.5 + 0.5 * g.x[ip]) / P, wp = MT_PI * g.w[ip] / P;
                    double wi[3] = {s * cos(ph), s * sin(ph), mu}, f[3];
                    prw_bsdf_eval(b, wo, wi, f);
                    sum += wm * wp * f[channel] * mu;
                }
        }
    return sum;
}

/* specular 0, metallic 0: pure Lambert, albedo = rho at every view angle, any roughness. */
static void test_lambert_albedo(void)
{
    double worst = 0;
    const double rhos[] = {0.1, 0.5, 0.9, 1.0}, mus[] = {0.02, 0.3, 0.7, 1.0}, rs[] = {0.0, 0.5, 1.0};
    for (int a = 0; a < 4; a++)
        for (int m = 0; m < 4; m++)
            for (int q = 0; q < 3; q++) {
                if (prw_test_light() && (a + m + q) % 3) continue; /* light mode: a third of the grid */
                prw_bsdf b = {.base = {rhos[a], rhos[a], rhos[a]}, .metallic = 0.0, .roughness = rs[q], .specular = 0.0};
                double al = albedo_cosgrid(&b, mus[m], 0), rel = fabs(al / rhos[a] - 1);
                if (rel > worst) worst = rel;
                CHECK_MSG(rel <= 0.005, "rho %g mu %g r %g: albedo %.6f", rhos[a], mus[m], rs[q], al);
            }
    printf("Lambert albedo: worst relative error %.3g (tolerance 0.5 %%)\n", worst);
}

static double header_E(double mu, double r) { return 1.0 - prw_ggx_Ec((float)mu, (float)r); }

/* The exact Fresnel term of the header against Snell + amplitude coefficients. */
static void test_fresnel_exact(void)
{
    double worst = 0;
    for (int k = 0; k <= 1000; k++) {
        double c = k / 1000.0, ref = mt_fresnel(c, 1.5), got = prw_F_dielectric((float)c);
        double rel = fabs(got - ref) / ref;
        if (rel > worst) worst = rel;
    }
    printf("exact dielectric Fresnel: worst relative error %.3g; F(1) = %.7f\n", worst, prw_F_dielectric(1.0f));
    CHECK(worst < 1e-5);
    CHECK_NEAR(prw_F_dielectric(1.0f), 0.04, 1e-7);
    CHECK_NEAR(prw_F_dielectric(0.0f), 1.0, 1e-6);
    /* the generated hemispherical average */
    mt_gl g = mt_gl8();
    double favg = 0;
    for (int p = 0; p < 64; p++)
        for (int i = 0; i < 8; i++) {
            double mu = (p + 0.5 + 0.5 * g.x[i]) / 64;
            favg += 0.5 * g.w[i] / 64 * 2 * mu * mt_fresnel(mu, 1.5);
        }
    printf("F_avg: header %.7f, quadrature %.7f\n", (double)PRW_DIELECTRIC_F_AVG, favg);
    CHECK_NEAR(PRW_DIELECTRIC_F_AVG, favg, 1e-6);
}

typedef struct ss_ctx {
    float r;
} ss_ctx;

/* The header's single-scattering term alone, with F = 1: D * V. */
static double header_ss(const double wo[3], const double wi[3], void *ctx)
{
    const ss_ctx *c = ctx;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    float alpha = prw_alpha_from_roughness(c->r);
    return (double)prw_D_ggx((float)(h[2] / hl), alpha) * prw_V_smith_ggx((float)wo[2], (float)wi[2], alpha);
}

/* GGX albedo with F = 1 (and with the exact dielectric Fresnel): the header's fitted albedos and the
 * header's D * V integrated, against the independent quadrature, on a grid in (sqrt(mu), r) that is
 * not the fit's node set.  The fit holds mu >= 0.01 (below, the value at 0.01 is used: reported). */
static void test_ggx_albedo(void)
{
    double worst_e = 0, worst_d = 0, worst_ss = 0, worst_graze = 0;
    int checked = 0;
    for (int j = 0; j <= 20; j++) {
        double r = j / 20.0, alpha = fmax(r * r, 0.002);
        for (int i = 0; i <= 18; i++) {
            double t = 0.1 + 0.9 * i / 18.0, mu = t * t;
            double ref = mt_ggx_albedo(mu, alpha, 0, 24), got = header_E(mu, r);
            double rel = fabs(got / ref - 1);
            worst_e = fmax(worst_e, rel);
            CHECK_MSG(rel <= 0.005, "E(mu %.4f, r %.3f): model %.6f quadrature %.6f", mu, r, got, ref);
            double refd = mt_ggx_albedo(mu, alpha, 1, 24), gotd = prw_ggx_Ed((float)mu, (float)r);
            double reld = fabs(gotd / refd - 1);
            worst_d = fmax(worst_d, reld);
            CHECK_MSG(reld <= 0.005, "Ed(mu %.4f, r %.3f): model %.6f quadrature %.6f", mu, r, gotd, refd);
            if (i % 3 == 0 && j % 2 == 0) {
                ss_ctx c = {(float)r};
                double ss = mt_integrate_halfvector(mu, alpha, 24, header_ss, &c);
                double rels = fabs(ss / ref - 1);
                worst_ss = fmax(worst_ss, rels);
                CHECK_MSG(rels <= 0.005, "int D V cos (mu %.4f, r %.3f): %.6f quadrature %.6f", mu, r, ss, ref);
            }
            checked++;
        }
        /* grazing, below the fit's range */
        double ref = mt_ggx_albedo(0.002, alpha, 0, 24);
        worst_graze = fmax(worst_graze, fabs(header_E(0.002, r) - ref));
    }
    printf("GGX albedo vs independent quadrature (%d points, mu >= 0.01): E worst relative %.3g, Ed worst %.3g, "
           "header D*V integrated worst %.3g; at mu = 0.002 (clamped to 0.01) |E error| up to %.3g\n",
           checked, worst_e, worst_d, worst_ss, worst_graze);
}

/* Albedo of the full model for one channel: the diffuse part as a 1-D integral over mu_i (it does
 * not depend on phi), the specular part over the half vector (resolves the GGX peak). */
typedef struct full_ctx {
    float base, metallic, r, s;
    float mo, ec_avg, ec_o; /* the fitted terms that do not depend on wi (prw_brdf_specular_terms) */
} full_ctx;

static double header_spec(const double wo[3], const double wi[3], void *ctx)
{
    const full_ctx *c = ctx;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    float VoH = (float)((wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]) / hl);
    /* prw_brdf_specular_channel with the wi-independent fits hoisted (the same float operations) */
    float NoV = (float)wo[2], NoL = (float)wi[2];
    if (NoL <= 0.0 || NoV <= 0.0) return 0.0;
    float mi = fminf(NoL, 1.0f);
    return prw_brdf_specular_terms(c->mo, mi, (float)(h[2] / hl), VoH, c->base, c->metallic, c->r, c->s, c->ec_avg,
                                   c->ec_o, prw_ggx_Ec(mi, c->r));
}

static double full_albedo(double mu, full_ctx c, int panels)
{
    mt_gl g = mt_gl8();
    double d = 0;
    for (int p = 0; p < 64; p++)
        for (int i = 0; i < 8; i++) {
            double mi = (p + 0.5 + 0.5 * g.x[i]) / 64;
            d += 0.5 * g.w[i] / 64 * 2 * MT_PI * mi *
                 prw_brdf_diffuse_channel((float)mu, (float)mi, c.base, c.metallic, c.r, c.s);
        }
    double alpha = prw_alpha_from_roughness(c.r);
    c.mo = fminf((float)mu, 1.0f), c.ec_avg = prw_ggx_Ec_avg(c.r), c.ec_o = prw_ggx_Ec(c.mo, c.r);
    return d + mt_integrate_halfvector(mu, alpha, panels, header_spec, &c);
}

/* full_albedo of n materials that share mu and roughness (every other field free), in one pass over the
 * nodes: the nodes, their directions and the fitted Ec(mi) do not depend on the material, so they are
 * formed once per node.  Each out[k] is bit-identical to full_albedo(mu, cs[k], panels): the same
 * float and double operations in the same order (mt_integrate_wm with upper_only, mt_times_cos and
 * header_spec, unrolled). */
static void full_albedo_multi(double mu, const full_ctx *cs, int n, int panels, double *out)
{
    enum { MAXN = 27 };
    if (n > MAXN) abort();
    mt_gl g = mt_gl8();
    full_ctx c[MAXN];
    double sum[MAXN];
    for (int k = 0; k < n; k++) {
        c[k] = cs[k];
        double d = 0;
        for (int p = 0; p < 64; p++)
            for (int i = 0; i < 8; i++) {
                double mi = (p + 0.5 + 0.5 * g.x[i]) / 64;
                d += 0.5 * g.w[i] / 64 * 2 * MT_PI * mi *
                     prw_brdf_diffuse_channel((float)mu, (float)mi, c[k].base, c[k].metallic, c[k].r, c[k].s);
            }
        out[k] = d;
        c[k].mo = fminf((float)mu, 1.0f), c[k].ec_avg = prw_ggx_Ec_avg(c[k].r), c[k].ec_o = prw_ggx_Ec(c[k].mo, c[k].r);
        sum[k] = 0;
    }
    float r = cs[0].r;
    double alpha = prw_alpha_from_roughness(r);
    double wo[3] = {sqrt(fmax(0.0, 1 - mu * mu)), 0, mu};
    double tc = atan(8 * alpha), vc = 2 / MT_PI * atan(8.0);
    for (int region = 0; region < 2; region++)
        for (int pa = 0; pa < panels; pa++)
            for (int ia = 0; ia < 8; ia++) {
                double t = (pa + 0.5 + 0.5 * g.x[ia]) / panels, w = 0.5 * g.w[ia] / panels, th, dth;
                if (region == 0) {
                    double v = t * vc, tv = tan(MT_PI * v / 2);
                    th = atan(alpha * tv);
                    dth = vc * alpha * (MT_PI / 2) * (1 + tv * tv) / (1 + alpha * alpha * tv * tv);
                } else {
                    th = tc + t * (MT_PI / 2 - tc);
                    dth = MT_PI / 2 - tc;
                }
                double st = sin(th), ct = cos(th);
                for (int pp = 0; pp < panels; pp++)
                    for (int ip = 0; ip < 8; ip++) {
                        double ph = MT_PI * (pp + 0.5 + 0.5 * g.x[ip]) / panels, wp = MT_PI * 0.5 * g.w[ip] / panels;
                        double m[3] = {st * cos(ph), st * sin(ph), ct};
                        double om = wo[0] * m[0] + wo[2] * m[2];
                        if (om <= 0) continue;
                        double wi[3] = {2 * om * m[0] - wo[0], 2 * om * m[1] - wo[1], 2 * om * m[2] - wo[2]};
                        if (wi[2] <= 0) continue;
                        double pre = w * dth * wp * st * 4 * om;
                        /* header_spec's material-independent part */
                        double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
                        double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
                        float VoH = (float)((wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]) / hl);
                        float NoV = (float)wo[2], NoL = (float)wi[2];
                        if (NoL <= 0.0 || NoV <= 0.0) {
                            for (int k = 0; k < n; k++) sum[k] += pre * (wi[2] * 0.0);
                            continue;
                        }
                        float mi = fminf(NoL, 1.0f), NoH = (float)(h[2] / hl), ec_i = prw_ggx_Ec(mi, r);
                        for (int k = 0; k < n; k++) {
                            double f = prw_brdf_specular_terms(c[k].mo, mi, NoH, VoH, c[k].base, c[k].metallic, c[k].r,
                                                               c[k].s, c[k].ec_avg, c[k].ec_o, ec_i);
                            sum[k] += pre * (wi[2] * f);
                        }
                    }
            }
    for (int k = 0; k < n; k++) out[k] = out[k] + 2 * sum[k];
}

/* Energy conservation: the albedo of the full model never exceeds 1 (up to the albedo fit), and a
 * white metal (base 1, metallic 1) is a white furnace: albedo = 1. */
static void test_energy(void)
{
    const double mus[] = {0.02, 0.1, 0.25, 0.5, 0.75, 1.0};
    const double rs[] = {0.0, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 1.0};
    const double vals[] = {0.0, 0.5, 1.0};
    double worst = 0, worst_cfg[5] = {0}, worst_wide = 0; /* worst_wide: mu >= 0.1 */
    int nconf = 0;
    for (int a = 0; a < 6; a++)
        for (int q = 0; q < 8; q++) {
            /* the (base, metallic, specular) configurations of this (mu, r), in one pass (full_albedo_multi) */
            full_ctx cs[27];
            int cfg[27][3], n = 0;
            for (int ib = 0; ib < 3; ib++)
                for (int im = 0; im < 3; im++)
                    for (int is = 0; is < 3; is++) {
                        if (prw_test_light() && (a + q + ib + im + is) % 3) continue; /* light: a third */
                        cs[n] = (full_ctx){.base = (float)vals[ib], .metallic = (float)vals[im], .r = (float)rs[q], .s = (float)vals[is]};
                        cfg[n][0] = ib, cfg[n][1] = im, cfg[n][2] = is, n++;
                    }
            double als[27];
            full_albedo_multi(mus[a], cs, n, 16, als);
            for (int k = 0; k < n; k++) {
                double al = als[k];
                nconf++;
                if (mus[a] >= 0.1) worst_wide = fmax(worst_wide, al);
                if (al > worst) {
                    worst = al;
                    double w[5] = {mus[a], rs[q], vals[cfg[k][0]], vals[cfg[k][1]], vals[cfg[k][2]]};
                    for (int j = 0; j < 5; j++) worst_cfg[j] = w[j];
                }
            }
        }
    printf("energy: max albedo of the full model over %d configurations %.5f (mu %g r %g base %g metallic %g "
           "specular %g); %.5f for mu >= 0.1\n",
           nconf, worst, worst_cfg[0], worst_cfg[1], worst_cfg[2], worst_cfg[3], worst_cfg[4], worst_wide);
    /* The model itself has no excess; what remains is (a) the albedo fit (mu < 0.01 clamped) and
     * (b) at alpha = 0.002 the float evaluation of D from a float n.h near 1 (1 - n.h^2 is quantised
     * to ~1e-7 against alpha^2 = 4e-6), which moves the integral of the peak by ~0.1 % (the same
     * integral in double converges to 0.99999).  Without the coupling a white dielectric reaches ~1.04. */
    CHECK(worst <= 1.005);
    CHECK(worst_wide <= 1.002);

    /* white furnace over a fine roughness grid */
    double lo = 2, hi = 0, lo_cfg[2] = {0}, hi_cfg[2] = {0}, lo_w = 2, hi_w = 0;
    for (int q = 0; q <= 20; q++)
        for (int a = 0; a < 6; a++) {
            full_ctx c = {.base = 1, .metallic = 1, .r = (float)(q / 20.0), .s = 1};
            double al = full_albedo(mus[a], c, 12);
            if (al < lo) lo = al, lo_cfg[0] = mus[a], lo_cfg[1] = q / 20.0;
            if (al > hi) hi = al, hi_cfg[0] = mus[a], hi_cfg[1] = q / 20.0;
            if (mus[a] >= 0.1) lo_w = fmin(lo_w, al), hi_w = fmax(hi_w, al);
        }
    printf("white furnace (base 1, metallic 1), r = 0 .. 1 step 0.05: albedo in [%.5f (mu %g r %g), %.5f (mu %g r "
           "%g)]; in [%.5f, %.5f] for mu >= 0.1\n",
           lo, lo_cfg[0], lo_cfg[1], hi, hi_cfg[0], hi_cfg[1], lo_w, hi_w);
    CHECK(lo >= 0.99 && hi <= 1.01);
    CHECK(lo_w >= 0.995 && hi_w <= 1.005);
    /* and without compensation it would not be: the single-scattering lobe alone at r = 1, mu = 0.5 */
    double ss = mt_ggx_albedo(0.5, 1.0, 0, 12);
    printf("  (single scattering alone at r = 1, mu = 0.5: %.4f)\n", ss);
}

/* Lambert with specular 0 is exactly rho / pi at every configuration (the coupling vanishes). */
static void test_lambert_exact(void)
{
    mt_rng r = {7};
    int bad = 0;
    for (int k = 0; k < 10000; k++) {
        float rho = (float)mt_rand(&r), a = (float)mt_rand(&r), b = (float)mt_rand(&r), ro = (float)mt_rand(&r);
        float f = prw_brdf_channel(a + 1e-4f, b + 1e-4f, 0.5f, 0.5f, rho, 0.0f, ro, 0.0f);
        if (fabs(f - rho / MT_PI) > 1e-6 * rho) bad++;
    }
    CHECK(bad == 0);
}

/* ---- clear coat (KHR_materials_clearcoat, prw_brdf.h "Clear coat") ---- */

/* A unit coat normal within ~40 degrees of +Z (a coat normal map's range), or +Z itself. */
static void random_coat_normal(mt_rng *r, double n[3])
{
    if (mt_rand(r) < 0.3) {
        n[0] = n[1] = 0, n[2] = 1;
        return;
    }
    double c = 0.75 + 0.25 * mt_rand(r), s = sqrt(1 - c * c), ph = 2 * MT_PI * mt_rand(r);
    n[0] = s * cos(ph), n[1] = s * sin(ph), n[2] = c;
}

static prw_bsdf random_coated(mt_rng *r)
{
    prw_bsdf b = random_material(r);
    b.clearcoat = mt_rand(r) < 0.3 ? 1.0 : mt_rand(r);
    b.clearcoat_roughness = mt_rand(r) < 0.2 ? 0.0 : mt_rand(r);
    random_coat_normal(r, b.coat_n);
    return b;
}

/* f(wo, wi) = f(wi, wo) with a coat (tilted coat normals included), through the C API and through the
 * header with both sets of cosines swapped; clearcoat 0 is the uncoated model bit for bit. */
static void test_coat_reciprocity(void)
{
    mt_rng r = {21};
    double worst = 0, worst_h = 0;
    int n = 50000, bad = 0, differ = 0;
    for (int k = 0; k < n; k++) {
        prw_bsdf b = random_coated(&r);
        double wo[3], wi[3], f1[3], f2[3];
        random_dir(&r, wo, 1e-4);
        random_dir(&r, wi, 1e-4);
        prw_bsdf_eval(&b, wo, wi, f1);
        prw_bsdf_eval(&b, wi, wo, f2);
        for (int c = 0; c < 3; c++) {
            double rel = f1[c] == 0 && f2[c] == 0 ? 0 : fabs(f1[c] - f2[c]) / fmax(fabs(f1[c]), 1e-30);
            if (!(rel <= 1e-6)) bad++;
            worst = fmax(worst, rel);
        }
        double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
        double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        for (int q = 0; q < 3; q++) h[q] /= hl;
        const double *nc = b.coat_n;
        float NoH = (float)h[2], VoH = (float)(wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]);
        float cv = (float)(nc[0] * wo[0] + nc[1] * wo[1] + nc[2] * wo[2]);
        float cl = (float)(nc[0] * wi[0] + nc[1] * wi[1] + nc[2] * wi[2]);
        float ch = (float)(nc[0] * h[0] + nc[1] * h[1] + nc[2] * h[2]);
        float a = prw_brdf_coated_channel((float)wo[2], (float)wi[2], NoH, VoH, cv, cl, ch, (float)b.base[1],
                                          (float)b.metallic, (float)b.roughness, (float)b.specular, (float)b.clearcoat,
                                          (float)b.clearcoat_roughness);
        float c = prw_brdf_coated_channel((float)wi[2], (float)wo[2], NoH, VoH, cl, cv, ch, (float)b.base[1],
                                          (float)b.metallic, (float)b.roughness, (float)b.specular, (float)b.clearcoat,
                                          (float)b.clearcoat_roughness);
        double rel = a == c ? 0 : fabs((double)a - c) / fmax(fabs((double)a), 1e-30);
        if (!(rel <= 1e-6)) bad++;
        worst_h = fmax(worst_h, rel);
        /* no coat: the plain model exactly */
        float p = prw_brdf_channel((float)wo[2], (float)wi[2], NoH, VoH, (float)b.base[1], (float)b.metallic,
                                   (float)b.roughness, (float)b.specular);
        float z = prw_brdf_coated_channel((float)wo[2], (float)wi[2], NoH, VoH, cv, cl, ch, (float)b.base[1],
                                          (float)b.metallic, (float)b.roughness, (float)b.specular, 0.0f,
                                          (float)b.clearcoat_roughness);
        if (p != z) differ++;
    }
    printf("coat reciprocity: %d configurations (coat normals up to 41 deg off), worst relative %.3g (C API), %.3g "
           "(header, cosines swapped), %d beyond 1e-6; clearcoat 0 differs from the uncoated model in %d\n",
           n, worst, worst_h, bad, differ);
    CHECK(bad == 0);
    CHECK(differ == 0);
}

/* Independent albedo of the coat in double: E_coat = E_ss(Fresnel) + F_ms (1 - E(F = 1)), with
 * F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) from the quadrature's own averages (Kulla & Conty). */
typedef struct indep_coat {
    double alpha, f_avg, e_avg, fms;
} indep_coat;

static double indep_e(const indep_coat *c, double mu, int panels)
{
    return mt_ggx_albedo(mu, c->alpha, 1, panels) + c->fms * (1 - mt_ggx_albedo(mu, c->alpha, 0, panels));
}

static indep_coat indep_coat_make(double r)
{
    indep_coat c = {.alpha = fmax(r * r, 0.002)};
    mt_gl g = mt_gl8();
    for (int p = 0; p < 4; p++)
        for (int i = 0; i < 8; i++) {
            double mu = (p + 0.5 + 0.5 * g.x[i]) / 4, w = 0.5 * g.w[i] / 4 * 2 * mu;
            c.f_avg += w * mt_fresnel(mu, 1.5);
            c.e_avg += w * mt_ggx_albedo(mu, c.alpha, 0, 12);
        }
    c.fms = c.f_avg * c.f_avg * c.e_avg / (1 - c.f_avg * (1 - c.e_avg));
    return c;
}

typedef struct eval_ctx {
    const prw_bsdf *b;
} eval_ctx;

static double model_f0(const double wo[3], const double wi[3], void *ctx)
{
    double f[3];
    prw_bsdf_eval(((const eval_ctx *)ctx)->b, wo, wi, f);
    return f[0];
}

/* A Lambertian base (rho, specular 0) under a coat of weight c: the model's albedo, integrated from
 * prw_bsdf_eval over the half vector (resolves the coat's peak), against the independent
 *   c E(mu_o) + (1 - c E(mu_o)) rho (1 - c 2 int E(mu) mu dmu). */
static void test_coat_albedo(void)
{
    const double rs[] = {0.0, 0.2, 0.5, 1.0}, mus[] = {0.1, 0.5, 1.0};
    const double cs[] = {1.0, 1.0, 0.5}, rhos[] = {0.0, 0.8, 0.8};
    double worst = 0, worst_e = 0;
    int checked = 0;
    mt_gl g = mt_gl8();
    for (int q = 0; q < 4; q++) {
        indep_coat ic = indep_coat_make(rs[q]);
        double eavg = 0;
        for (int p = 0; p < 2; p++)
            for (int i = 0; i < 8; i++) {
                double mu = (p + 0.5 + 0.5 * g.x[i]) / 2;
                eavg += 0.5 * g.w[i] / 2 * 2 * mu * indep_e(&ic, mu, 12);
            }
        for (int m = 0; m < 3; m++) {
            double e = indep_e(&ic, mus[m], 24);
            double got_e = prw_coat_albedo((float)mus[m], (float)rs[q]);
            worst_e = fmax(worst_e, fabs(got_e / e - 1));
            CHECK_MSG(fabs(got_e / e - 1) <= 0.005, "E_coat(mu %g, r %g): header %.6f quadrature %.6f", mus[m], rs[q],
                      got_e, e);
            for (int ci = 0; ci < 3; ci++) {
                    double c = cs[ci], rho = rhos[ci];
                    prw_bsdf b = {{rho, rho, rho}, 0.0, 1.0, 0.0, c, rs[q], {0, 0, 0}};
                    eval_ctx ec = {&b};
                    double a = mt_integrate_halfvector(mus[m], ic.alpha, 10, model_f0, &ec);
                    double want = c * e + (1 - c * e) * rho * (1 - c * eavg);
                    double rel = fabs(a / want - 1);
                    worst = fmax(worst, rel);
                    CHECK_MSG(rel <= 0.005, "coated albedo mu %g r_c %g c %g rho %g: model %.6f independent %.6f",
                              mus[m], rs[q], c, rho, a, want);
                    checked++;
                }
        }
    }
    printf("coat albedo vs independent double quadrature: E_coat worst relative %.3g; coated Lambert (%d cases: "
           "mu, r_c, weight, rho) worst relative %.3g (tolerance 0.5 %%)\n",
           worst_e, checked, worst);
}

/* prw_bsdf_eval / _eval_diffuse are the header's prw_brdf_coated_channel / _diffuse_channel per channel
 * to the bit (prw_bsdf.c evaluates the fits its own way: shared Chebyshev bases, per-thread roughness
 * rows), with the arguments prw_bsdf.c derives from the vectors.  Roughness values come from a pool of
 * 7 (more than the row cache holds, so rows are evicted and refilled) or are drawn; coat normals are
 * +Z (the bases of base and coat coincide) or tilted. */
static void test_header_bits(void)
{
    mt_rng r = {77};
    const double pool[7] = {0.0, 0.15, 0.3, sqrt(0.05), 0.5, 0.7, 1.0};
    int n = 40000, differ = 0, differ_d = 0;
    for (int k = 0; k < n; k++) {
        prw_bsdf b = random_coated(&r);
        if (mt_rand(&r) < 0.5) b.clearcoat = 0;
        if (mt_rand(&r) < 0.5) b.coat_n[0] = b.coat_n[1] = b.coat_n[2] = 0;
        if (mt_rand(&r) < 0.7) b.roughness = pool[(int)(7 * mt_rand(&r)) % 7];
        if (mt_rand(&r) < 0.7) b.clearcoat_roughness = pool[(int)(7 * mt_rand(&r)) % 7];
        double wo[3], wi[3], f[3], fd[3], nc[3] = {0, 0, 1};
        random_dir(&r, wo, 1e-4);
        random_dir(&r, wi, 1e-4);
        if (b.coat_n[0] != 0 || b.coat_n[1] != 0 || b.coat_n[2] != 0)
            for (int q = 0; q < 3; q++) nc[q] = b.coat_n[q];
        prw_bsdf_eval(&b, wo, wi, f);
        prw_bsdf_eval_diffuse(&b, wo, wi, fd);
        double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
        double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        for (int q = 0; q < 3; q++) h[q] /= hl;
        double oh = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2], ih = wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2];
        float NoH = (float)h[2], VoH = (float)(0.5 * (oh + ih));
        float cv = (float)(nc[0] * wo[0] + nc[1] * wo[1] + nc[2] * wo[2]);
        float cl = (float)(nc[0] * wi[0] + nc[1] * wi[1] + nc[2] * wi[2]);
        float ch = (float)(nc[0] * h[0] + nc[1] * h[1] + nc[2] * h[2]);
        for (int c = 0; c < 3; c++) {
            float a = prw_brdf_coated_channel((float)wo[2], (float)wi[2], NoH, VoH, cv, cl, ch, (float)b.base[c],
                                              (float)b.metallic, (float)b.roughness, (float)b.specular,
                                              (float)b.clearcoat, (float)b.clearcoat_roughness);
            float d = prw_brdf_coated_diffuse_channel((float)wo[2], (float)wi[2], cv, cl, (float)b.base[c],
                                                      (float)b.metallic, (float)b.roughness, (float)b.specular,
                                                      (float)b.clearcoat, (float)b.clearcoat_roughness);
            if ((float)f[c] != a || (double)(float)f[c] != f[c]) differ++;
            if ((float)fd[c] != d || (double)(float)fd[c] != fd[c]) differ_d++;
        }
    }
    printf("header bits: %d configurations x 3 channels: prw_bsdf_eval differs from prw_brdf_coated_channel in %d, "
           "prw_bsdf_eval_diffuse from prw_brdf_coated_diffuse_channel in %d\n",
           n, differ, differ_d);
    CHECK(differ == 0);
    CHECK(differ_d == 0);
}

/* The coated model never reflects more than it receives: max albedo over a grid (base white metal,
 * white dielectric, coat weights and roughnesses). */
static void test_coat_energy(void)
{
    const double mus[] = {0.05, 0.4, 1.0}, rs[] = {0.0, 0.3, 1.0}, rcs[] = {0.0, 0.3, 1.0};
    double worst = 0;
    for (int a = 0; a < 3; a++)
        for (int q = 0; q < 3; q++)
            for (int k = 0; k < 3; k++)
                for (int mm = 0; mm < 2; mm++) {
                    prw_bsdf b = {{1, 1, 1}, (double)mm, rs[q], 1.0, 1.0, rcs[k], {0, 0, 0}};
                    eval_ctx ec = {&b};
                    double alpha = fmin(fmax(rcs[k] * rcs[k], 0.002), fmax(rs[q] * rs[q], 0.002));
                    double al = mt_integrate_halfvector(mus[a], alpha, 8, model_f0, &ec);
                    worst = fmax(worst, al);
                }
    printf("coat energy: max albedo of the coated model over 54 configurations %.5f\n", worst);
    CHECK(worst <= 1.005);
}

static const prw_test_case cases[] = {
    {"coat_reciprocity", test_coat_reciprocity}, {"coat_albedo", test_coat_albedo}, {"coat_energy", test_coat_energy},
    {"reciprocity", test_reciprocity},   {"lambert_albedo", test_lambert_albedo},
    {"lambert_exact", test_lambert_exact}, {"fresnel_exact", test_fresnel_exact},
    {"ggx_albedo", test_ggx_albedo},     {"energy", test_energy},
    {"header_bits", test_header_bits},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0])); }

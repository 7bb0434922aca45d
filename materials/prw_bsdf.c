/* prw_bsdf — evaluation through prw_brdf.h and importance sampling for the CPU side (see prw_bsdf.h). */
#include "prw_bsdf.h"

#include <math.h>
#include <string.h>

#include "prw_brdf.h"

#define PI 3.14159265358979323846

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }
static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The alpha the sampler uses: the header's mapping, in double. */
static double alpha_of(const prw_bsdf *b)
{
    double r = clampd(b->roughness, 0, 1);
    return fmax(r * r, (double)PRW_MIN_ALPHA);
}

static bool has_coat(const prw_bsdf *b) { return b->clearcoat > 0; }

/* The coat normal (local frame): coat_n, or +Z when it is all zero. */
static void coat_normal(const prw_bsdf *b, double nc[3])
{
    if (b->coat_n[0] == 0 && b->coat_n[1] == 0 && b->coat_n[2] == 0) {
        nc[0] = nc[1] = 0, nc[2] = 1;
        return;
    }
    for (int k = 0; k < 3; k++) nc[k] = b->coat_n[k];
}

/* The rows travel in prw_bsdf_lobes as float[16] (prw_bsdf.h does not include the generated header). */
_Static_assert(sizeof(prw_ggx_row) == 16 * sizeof(float), "prw_ggx_row is 16 floats");

/* ---- the fitted albedos, as prw_ggx_fit.h evaluates them ----
 * prw_ggx_Ec_at / prw_ggx_Ed_at(row, mu) are a Chebyshev basis in u(mu) dotted with the row, then
 * max(prw_exp(y) - 0.001, 0).  The basis depends on mu only (prw_ggx_fit_u clamps mu to [0, 1] first), so
 * rows evaluated at the same clamped cosine share it here; the float operations are the header's in
 * the header's order, so the values are the same bits (test_brdf_model: eval against the header's
 * prw_brdf_coated_channel bit for bit). */
typedef struct fit_basis {
    float mu; /* prw_clamp01 of the cosine */
    float a[16];
} fit_basis;

/* prw_clamp01 without its two libm calls (fminf / fmaxf are calls in C without -ffinite-math-only): the
 * same value for every x, NaN included (0), except that -0 may come out as +0, which the basis does not
 * tell apart (it feeds sqrt, a max with 0.1 and ==). */
static float clamp01_inline(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

/* prw_ggx_fit_u's operations and constants (prw_ggx_fit.h), its maxima inline; test_brdf_model's
 * header_bits fails if the generated header changes them */
static void basis_at(float mu, fit_basis *b)
{
    b->mu = clamp01_inline(mu);
    float t = sqrtf(b->mu);
    t = t > 0.100000001f ? t : 0.100000001f;
    float u = (t - 0.100000001f) * 2.22222233f - 1.0f;
    b->a[0] = 1.0f, b->a[1] = u;
#pragma GCC unroll 16
    for (int k = 2; k < 16; k++) b->a[k] = 2.0f * u * b->a[k - 1] - b->a[k - 2];
}

/* The basis at mu: *have when it is the same clamped cosine, else computed into *mine. */
static const fit_basis *basis_or(const fit_basis *have, float mu, fit_basis *mine)
{
    if (have && have->mu == clamp01_inline(mu)) return have;
    basis_at(mu, mine);
    return mine;
}

/* max(prw_exp(y) - 0.001, 0) as prw_ggx_Ec_at / _Ed_at end (x - 0.001 is never -0: x > 0 ? x : 0 is fmaxf) */
static float fit_end(float y)
{
    float x = prw_exp(y) - 0.00100000005f;
    return x > 0.0f ? x : 0.0f;
}

static float fit_at(const float d[16], const fit_basis *b)
{
    float y = d[0] * b->a[0];
#pragma GCC unroll 16
    for (int k = 1; k < 16; k++) y += d[k] * b->a[k];
    return fit_end(y);
}

/* two rows at one basis: two independent sums (each in the header's order) */
static void fit_at2(const float d[16], const float e[16], const fit_basis *b, float *fd, float *fe)
{
    float y = d[0] * b->a[0], z = e[0] * b->a[0];
#pragma GCC unroll 16
    for (int k = 1; k < 16; k++) y += d[k] * b->a[k], z += e[k] * b->a[k];
    *fd = fit_end(y), *fe = fit_end(z);
}

/* The roughness-only fits (two rows and two averages), kept per thread for the last few roughness
 * values: a path tracer shades hit after hit with a scene's few materials, and the 16 x 16 row
 * evaluation per hit cost as much as the rest of the BSDF.  A pure function of r, so cached or not
 * the same bits. */
typedef struct rough_fits {
    float r;
    int valid;
    prw_ggx_row ec, ed;
    float ec_avg, ed_avg;
} rough_fits;

#define FITS_CACHE 4
static _Thread_local rough_fits fits_cache[FITS_CACHE];
static _Thread_local unsigned fits_next;

static const rough_fits *rough_fits_of(float r)
{
    for (int k = 0; k < FITS_CACHE; k++)
        if (fits_cache[k].valid && memcmp(&fits_cache[k].r, &r, sizeof r) == 0) return &fits_cache[k];
    rough_fits *f = &fits_cache[fits_next++ % FITS_CACHE];
    f->r = r, f->valid = 1;
    f->ec = prw_ggx_Ec_row(r), f->ed = prw_ggx_Ed_row(r);
    f->ec_avg = prw_ggx_Ec_avg(r), f->ed_avg = prw_ggx_Ed_avg(r);
    return f;
}

/* prw_coat_albedo of prw_brdf.h with the coat's rows and a basis at mu: the same float operations. */
static float coat_albedo_rows(const prw_bsdf_lobes *l, const fit_basis *b)
{
    float ed, ec;
    fit_at2(l->cd_row, l->cc_row, b, &ed, &ec);
    return ed + l->coat_fms * ec;
}

/* prw_coat_transmission */
static float coat_transmission_rows(const prw_bsdf_lobes *l, const fit_basis *b, float clearcoat)
{
    return 1.0 - prw_clamp01(clearcoat) * coat_albedo_rows(l, b);
}

/* The fits of prw_bsdf_lobes: everything eval needs that does not depend on wi, with the arguments
 * eval used to pass (so the same bits). */
static void fill_fits(const prw_bsdf *b, const double wo[3], prw_bsdf_lobes *l)
{
    l->fits = 1;
    /* Without a specular lobe every fitted albedo is multiplied by an exact zero (metallic, specular
     * and F_ms(0, .)), so eval's result is prw_lambert(base) to the bit and the fits are not needed
     * (zeros stand in for them); prw_bsdf_lobes_at then samples the cosine lobe alone. */
    l->lambert = b->metallic <= 0 && b->specular <= 0 && !has_coat(b);
    if (l->lambert) {
        memset(l->ec_row, 0, sizeof l->ec_row), memset(l->ed_row, 0, sizeof l->ed_row);
        l->ec_avg = l->ed_avg = l->ec_o = l->ed_o = 0;
        return;
    }
    float NoV = (float)wo[2], r = (float)b->roughness;
    float mo = fminf(NoV, 1.0f);
    const rough_fits *rf = rough_fits_of(r);
    memcpy(l->ec_row, &rf->ec, sizeof rf->ec);
    memcpy(l->ed_row, &rf->ed, sizeof rf->ed);
    l->ec_avg = rf->ec_avg, l->ed_avg = rf->ed_avg;
    fit_basis bo, bc;
    basis_at(mo, &bo);
    fit_at2(l->ec_row, l->ed_row, &bo, &l->ec_o, &l->ed_o);
    if (!has_coat(b)) return;
    double nc[3];
    coat_normal(b, nc);
    float NcV = (float)dot3(nc, wo), rc = (float)b->clearcoat_roughness;
    const rough_fits *cf = rough_fits_of(rc);
    memcpy(l->cc_row, &cf->ec, sizeof cf->ec);
    memcpy(l->cd_row, &cf->ed, sizeof cf->ed);
    l->cc_avg = cf->ec_avg;
    l->coat_fms = prw_F_ms(PRW_DIELECTRIC_F_AVG, l->cc_avg);
    /* coat_mo and NcV clamp to the same basis (prw_ggx_fit_u clamps) */
    const fit_basis *bv = basis_or(&bo, NcV, &bc);
    l->coat_a_o = coat_albedo_rows(l, bv);
    l->coat_t_o = 1.0 - prw_clamp01((float)b->clearcoat) * l->coat_a_o;
    l->coat_mo = PRW_B_MIN(NcV, 1.0);
    l->cc_o = fit_at(l->cc_row, bv);
}

/* prw_brdf_diffuse_terms (+ prw_brdf_specular_terms unless diffuse_only) of prw_brdf.h for the three
 * channels: what does not depend on the channel (the Fresnel-free lobes D V, the dielectric Fresnel,
 * the F_ms factors, the diffuse energy ratio) computed once, then per channel the header's remaining
 * operations in its order and precision (double where its double constants promote), so the same bits
 * (test_brdf_model's header_bits). */
static void base_terms(const float base[3], float metallic, float specular, float roughness, float mo, float mi,
                       float NoH, float VoH, float ec_avg, float ed_avg, float ec_o, float ec_i, float ed_o, float ed_i,
                       bool diffuse_only, float fb[3])
{
    float m = prw_clamp01(metallic);
    float s = prw_clamp01(specular);
    float fms = prw_F_ms(s * PRW_DIELECTRIC_F_AVG, ec_avg); /* = the specular lobe's fms_diel */
    float e_o = s * ed_o + fms * ec_o;
    float e_i = s * ed_i + fms * ec_i;
    float e_avg = s * ed_avg + fms * ec_avg;
    double ratio = (1.0 - e_o) * (1.0 - e_i) / (1.0 - e_avg);
    for (int k = 0; k < 3; k++) fb[k] = (1.0 - m) * prw_lambert(base[k]) * ratio;
    if (diffuse_only) return;
    float alpha = prw_alpha_from_roughness(roughness);
    float c = prw_clamp01(VoH);
    float dv = prw_D_ggx(prw_clamp01(NoH), alpha) * prw_V_smith_ggx(mo, mi, alpha);
    float ms = prw_ggx_ms_terms(ec_avg, ec_o, ec_i);
    float f_diel = s * prw_F_dielectric(c);
    float diel = dv * f_diel + ms * fms;
    for (int k = 0; k < 3; k++) {
        float f_metal = prw_F_schlick(base[k], c);
        float fms_metal = prw_F_ms(base[k] + (1.0 - base[k]) * (1.0 / 21.0), ec_avg);
        float metal = dv * f_metal + ms * fms_metal;
        float spec = (1.0 - m) * diel + m * metal;
        fb[k] += spec;
    }
}

static void eval(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3],
                 bool diffuse_only, double f[3])
{
    f[0] = f[1] = f[2] = 0;
    if (wo[2] <= 0 || wi[2] <= 0 || !l->fits) return;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    double hl = sqrt(dot3(h, h));
    if (!(hl > 0)) return;
    for (int k = 0; k < 3; k++) h[k] /= hl;
    /* VoH = (wo.h) = (wi.h) mathematically; the symmetric form keeps f(wo, wi) = f(wi, wo) bit-exact
     * in double before the float boundary. */
    float NoV = (float)wo[2], NoL = (float)wi[2], NoH = (float)h[2];
    if (l->lambert) {
        if (NoL > 0.0 && NoV > 0.0)
            for (int c = 0; c < 3; c++) f[c] = prw_lambert((float)b->base[c]);
        return;
    }
    float VoH = (float)(0.5 * (dot3(wo, h) + dot3(wi, h)));
    float base[3] = {(float)b->base[0], (float)b->base[1], (float)b->base[2]};
    float m = (float)b->metallic, r = (float)b->roughness, sp = (float)b->specular;
    /* prw_brdf_channel / prw_brdf_diffuse_channel per channel, with the fitted albedos (which do not
     * depend on the channel) evaluated once, those at wo once per shading point: the same float
     * operations, so the same bits. */
    float fb[3] = {0, 0, 0};
    fit_basis bi, bc;
    const fit_basis *have = NULL; /* the basis at mi, when computed */
    if (NoL > 0.0 && NoV > 0.0) {
        float mo = fminf(NoV, 1.0f), mi = fminf(NoL, 1.0f);
        float ec_avg = l->ec_avg, ed_avg = l->ed_avg, ec_o = l->ec_o, ed_o = l->ed_o;
        basis_at(mi, &bi), have = &bi;
        float ec_i, ed_i;
        fit_at2(l->ec_row, l->ed_row, &bi, &ec_i, &ed_i);
        base_terms(base, m, sp, r, mo, mi, NoH, VoH, ec_avg, ed_avg, ec_o, ec_i, ed_o, ed_i, diffuse_only, fb);
    }
    float cc = (float)b->clearcoat, c = prw_clamp01(cc);
    if (!has_coat(b) || c <= 0.0) {
        for (int k = 0; k < 3; k++) f[k] = fb[k];
        return;
    }
    /* prw_brdf_coated_channel / prw_brdf_coated_diffuse_channel: the coat's transmission and lobe do not
     * depend on the channel either */
    double nc[3];
    coat_normal(b, nc);
    float NcV = (float)dot3(nc, wo), NcL = (float)dot3(nc, wi), NcH = (float)dot3(nc, h);
    float rc = (float)b->clearcoat_roughness;
    /* the basis at NcL: the base's when the coat normal gives the same cosine (coat_n = n) */
    const fit_basis *bl = basis_or(have, NcL, &bc);
    float t = l->coat_t_o * coat_transmission_rows(l, bl, cc);
    float lobe = 0.0f;
    if (!diffuse_only && NcL > 0.0 && NcV > 0.0) { /* prw_brdf_coat_lobe; mi > 0 clamps to bl's cosine */
        float mi = PRW_B_MIN(NcL, 1.0);
        lobe = prw_brdf_coat_terms(l->coat_mo, mi, NcH, VoH, rc, l->cc_avg, l->cc_o, fit_at(l->cc_row, bl));
    }
    for (int k = 0; k < 3; k++) f[k] = diffuse_only ? t * fb[k] : c * lobe + t * fb[k];
}

void prw_bsdf_eval_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3], double f[3])
{
    eval(b, l, wo, wi, false, f);
}

void prw_bsdf_eval_diffuse_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3],
                              double f[3])
{
    eval(b, l, wo, wi, true, f);
}

void prw_bsdf_eval(const prw_bsdf *b, const double wo[3], const double wi[3], double f[3])
{
    prw_bsdf_lobes l = prw_bsdf_lobes_at(b, wo);
    eval(b, &l, wo, wi, false, f);
}

void prw_bsdf_eval_diffuse(const prw_bsdf *b, const double wo[3], const double wi[3], double f[3])
{
    prw_bsdf_lobes l = prw_bsdf_lobes_at(b, wo);
    eval(b, &l, wo, wi, true, f);
}

/* ---- lobes ---- */

void prw_sample_cosine(const double u[2], double wi[3])
{
    /* Malley's method: uniform on the unit disk (polar map r = sqrt(u0)), lifted to the hemisphere. */
    double r = sqrt(u[0]), ph = 2 * PI * u[1];
    wi[0] = r * cos(ph);
    wi[1] = r * sin(ph);
    wi[2] = sqrt(fmax(0.0, 1 - u[0]));
}

double prw_pdf_cosine(const double wi[3]) { return wi[2] > 0 ? wi[2] / PI : 0; }

void prw_sample_ggx_vndf(const double wo[3], double alpha, const double u[2], double wm[3])
{
    /* Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4): stretch the view
     * direction to the alpha = 1 configuration, sample the projected area of the hemisphere as seen
     * from it (a disk whose far half is squashed by (1 + cos theta)/2), unproject onto the
     * hemisphere and unstretch the normal. */
    double vh[3] = {alpha * wo[0], alpha * wo[1], wo[2]};
    double vl = sqrt(dot3(vh, vh));
    for (int k = 0; k < 3; k++) vh[k] /= vl;
    double len2 = vh[0] * vh[0] + vh[1] * vh[1];
    double t1[3] = {1, 0, 0};
    if (len2 > 0) {
        double il = 1 / sqrt(len2);
        t1[0] = -vh[1] * il, t1[1] = vh[0] * il, t1[2] = 0;
    }
    double t2[3] = {vh[1] * t1[2] - vh[2] * t1[1], vh[2] * t1[0] - vh[0] * t1[2], vh[0] * t1[1] - vh[1] * t1[0]};
    double r = sqrt(u[0]), ph = 2 * PI * u[1];
    double p1 = r * cos(ph), p2 = r * sin(ph);
    double s = 0.5 * (1 + vh[2]);
    p2 = (1 - s) * sqrt(fmax(0.0, 1 - p1 * p1)) + s * p2;
    double pz = sqrt(fmax(0.0, 1 - p1 * p1 - p2 * p2));
    double nh[3];
    for (int k = 0; k < 3; k++) nh[k] = p1 * t1[k] + p2 * t2[k] + pz * vh[k];
    wm[0] = alpha * nh[0], wm[1] = alpha * nh[1], wm[2] = fmax(1e-12, nh[2]);
    double ml = sqrt(dot3(wm, wm));
    for (int k = 0; k < 3; k++) wm[k] /= ml;
}

/* Smith masking G1 for GGX: 1 / (1 + Lambda), Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2 (Heitz 2014). */
static double smith_g1(const double w[3], double alpha)
{
    double z2 = w[2] * w[2];
    if (!(z2 > 0)) return 0;
    double t2 = fmax(0.0, 1 - z2) / z2;
    return 2 / (1 + sqrt(1 + alpha * alpha * t2));
}

static double ggx_D(double cos_m, double alpha)
{
    if (cos_m <= 0) return 0;
    double a2 = alpha * alpha, c2 = cos_m * cos_m;
    double d = c2 * (a2 - 1) + 1;
    return a2 / (PI * d * d);
}

double prw_pdf_ggx_reflect(const double wo[3], const double wi[3], double alpha)
{
    if (wo[2] <= 0) return 0;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    double hl = sqrt(dot3(h, h));
    if (!(hl > 0)) return 0;
    for (int k = 0; k < 3; k++) h[k] /= hl;
    double oh = dot3(wo, h);
    if (oh <= 0 || h[2] <= 0) return 0;
    /* D_v(wm) = G1(wo) max(0, wo.wm) D(wm) / cos(theta_o); dwi = 4 (wo.wm) dwm. */
    return smith_g1(wo, alpha) * ggx_D(h[2], alpha) / (4 * wo[2]);
}

/* ---- mixture ---- */

/* Probability of choosing the GGX lobe: specular albedo / (specular + diffuse-like albedo), both
 * estimated per channel from the fitted albedos at mu_o and averaged over RGB.  The multiple-scattering lobe
 * is cosine-like and counted with the diffuse lobe (it is sampled through the cosine lobe). */
static double spec_probability(const prw_bsdf *b, const prw_bsdf_lobes *l, double mu_o, double *albedo)
{
    /* the fits at mo = mu_o (in (0, 1]: fill_fits' argument) and the clamped roughness (every fit clamps it) */
    float mo = (float)clampd(mu_o, 0, 1);
    double m = clampd(b->metallic, 0, 1), s = clampd(b->specular, 0, 1);
    float ecf = l->ec_o;
    double ec = ecf, e = 1 - ecf, ec_avg = l->ec_avg; /* 1 - ecf in float */
    double ed = l->ed_o;
    double fms_d = prw_F_ms((float)(s * PRW_DIELECTRIC_F_AVG), (float)ec_avg);
    double e_ds = s * ed + fms_d * ec;
    double spec = 0, diff = 0;
    for (int c = 0; c < 3; c++) {
        double base = clampd(b->base[c], 0, 1);
        double fm = prw_F_schlick((float)base, (float)mo);
        double fms_m = prw_F_ms((float)(base + (1 - base) / 21), (float)ec_avg);
        spec += (1 - m) * s * ed + m * fm * e;
        diff += (1 - m) * (base * (1 - e_ds) + fms_d * ec) + m * fms_m * ec;
    }
    if (albedo) *albedo = (spec + diff) / 3;
    if (!(spec + diff > 0)) return 0.5;
    return clampd(spec / (spec + diff), 0.05, 0.95);
}

/* ---- the coat lobe: GGX visible normals in the coat normal's frame ---- */

typedef struct coat_frame {
    double t[3], b[3], n[3];
} coat_frame;

static coat_frame make_coat_frame(const prw_bsdf *b)
{
    coat_frame f;
    coat_normal(b, f.n);
    prw_frame_from_normal(f.n, f.t, f.b);
    return f;
}

static void to_coat(const coat_frame *f, const double w[3], double out[3])
{
    out[0] = dot3(w, f->t), out[1] = dot3(w, f->b), out[2] = dot3(w, f->n);
}

static double coat_alpha(const prw_bsdf *b)
{
    double r = clampd(b->clearcoat_roughness, 0, 1);
    return fmax(r * r, (double)PRW_MIN_ALPHA);
}

/* Probability of the coat lobe: c E_coat(mu_c) against the base's estimated albedo under the coat;
 * 0 without a coat or when wo is below the coat's horizon. */
static double coat_probability(const prw_bsdf *b, const prw_bsdf_lobes *l, const coat_frame *f, const double wo[3],
                               double base_albedo)
{
    double mu = dot3(wo, f->n), c = clampd(b->clearcoat, 0, 1);
    if (!(mu > 0) || !(c > 0)) return 0;
    /* prw_coat_albedo((float)mu, rc) = the fits' coat_a_o: mu is NcV (the same product), the fits clamp
     * rc as clampd does */
    double w = c * l->coat_a_o;
    double wb = (1 - w) * base_albedo;
    if (!(w + wb > 0)) return 0.5;
    return clampd(w / (w + wb), 0.05, 0.95);
}

static double base_pdf(const prw_bsdf *b, double ps, const double wo[3], const double wi[3])
{
    if (ps == 0) return prw_pdf_cosine(wi);
    return ps * prw_pdf_ggx_reflect(wo, wi, alpha_of(b)) + (1 - ps) * prw_pdf_cosine(wi);
}

prw_bsdf_lobes prw_bsdf_lobes_at(const prw_bsdf *b, const double wo[3])
{
    prw_bsdf_lobes l = {.ps = 0, .pc = 0, .fits = 0};
    if (wo[2] <= 0) return l;
    fill_fits(b, wo, &l);
    if (l.lambert) return l; /* the cosine lobe alone (ps = pc = 0) */
    double albedo;
    l.ps = spec_probability(b, &l, wo[2], &albedo);
    if (has_coat(b)) {
        coat_frame f = make_coat_frame(b);
        l.pc = coat_probability(b, &l, &f, wo, albedo);
    }
    return l;
}

double prw_bsdf_pdf_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double wi[3])
{
    if (wo[2] <= 0 || wi[2] <= 0) return 0;
    if (!has_coat(b)) return base_pdf(b, l->ps, wo, wi);
    double pc = l->pc, pcoat = 0;
    if (pc > 0) {
        coat_frame f = make_coat_frame(b);
        double wo_c[3], wi_c[3];
        to_coat(&f, wo, wo_c);
        to_coat(&f, wi, wi_c);
        pcoat = prw_pdf_ggx_reflect(wo_c, wi_c, coat_alpha(b));
    }
    return pc * pcoat + (1 - pc) * base_pdf(b, l->ps, wo, wi);
}

double prw_bsdf_pdf(const prw_bsdf *b, const double wo[3], const double wi[3])
{
    prw_bsdf_lobes l = prw_bsdf_lobes_at(b, wo);
    return prw_bsdf_pdf_at(b, &l, wo, wi);
}

bool prw_bsdf_sample_at(const prw_bsdf *b, const prw_bsdf_lobes *l, const double wo[3], const double u[3],
                        double wi[3], double *pdf)
{
    *pdf = 0;
    if (wo[2] <= 0) return false;
    double u0 = u[0];
    if (has_coat(b)) {
        /* the coat lobe first (u0 < pc), else u0 is rescaled to [0, 1) for the base's lobe choice */
        double pc = l->pc;
        if (u0 < pc) {
            coat_frame f = make_coat_frame(b);
            double wo_c[3], wm[3];
            to_coat(&f, wo, wo_c);
            prw_sample_ggx_vndf(wo_c, coat_alpha(b), u + 1, wm);
            double om = dot3(wo_c, wm), wi_c[3];
            for (int k = 0; k < 3; k++) wi_c[k] = 2 * om * wm[k] - wo_c[k];
            for (int k = 0; k < 3; k++) wi[k] = f.t[k] * wi_c[0] + f.b[k] * wi_c[1] + f.n[k] * wi_c[2];
            double len = sqrt(dot3(wi, wi));
            for (int k = 0; k < 3; k++) wi[k] /= len;
            if (wi[2] <= 0) return false;
            *pdf = prw_bsdf_pdf_at(b, l, wo, wi);
            return *pdf > 0;
        }
        u0 = (u0 - pc) / (1 - pc);
    }
    if (u0 < l->ps) {
        double wm[3];
        prw_sample_ggx_vndf(wo, alpha_of(b), u + 1, wm);
        double om = dot3(wo, wm);
        for (int k = 0; k < 3; k++) wi[k] = 2 * om * wm[k] - wo[k];
        double len = sqrt(dot3(wi, wi));
        for (int k = 0; k < 3; k++) wi[k] /= len;
    } else {
        prw_sample_cosine(u + 1, wi);
    }
    if (wi[2] <= 0) return false;
    *pdf = prw_bsdf_pdf_at(b, l, wo, wi);
    return *pdf > 0;
}

bool prw_bsdf_sample(const prw_bsdf *b, const double wo[3], const double u[3], double wi[3], double *pdf)
{
    prw_bsdf_lobes l = prw_bsdf_lobes_at(b, wo);
    return prw_bsdf_sample_at(b, &l, wo, u, wi, pdf);
}

void prw_frame_from_normal(const double n[3], double t[3], double b[3])
{
    /* Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), listing 3. */
    double sign = copysign(1.0, n[2]);
    double a = -1 / (sign + n[2]);
    double c = n[0] * n[1] * a;
    t[0] = 1 + sign * n[0] * n[0] * a, t[1] = sign * c, t[2] = -sign * n[0];
    b[0] = c, b[1] = sign + n[1] * n[1] * a, b[2] = -n[1];
}

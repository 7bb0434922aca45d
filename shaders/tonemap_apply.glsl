// The per-pixel tone map of the global operators (tonemap_apply.comp, tonemap_fused.comp): operator ->
// gamut mapping -> inverse display model of one HDR pixel; L: its sanitised luminance (the statistics'
// Y); flags: F_BELOW / F_ABOVE / F_GAMUT.  The float mirror of prw_tm_pixel (tonemap_ops.c).
vec3 tm_pixel(vec3 raw, out float L, inout uint flags)
{
    int op = tm_mode_op();
    float exposure = P.range.x, lmin = P.range.y, lmax = P.range.z, dl = P.range.w;
    float white_cd = P.enc.w;
    vec3 c = vec3(san(raw.r), san(raw.g), san(raw.b));
    L = lum3(c);
    vec3 r;
    float ry;
    if (op == OP_EXPOSURE) {
        vec3 x = P.op1.x * exposure * c;
        if (max(x.r, max(x.g, x.b)) > 1.0) flags |= F_ABOVE;
        r = min(x, vec3(1.0));
        ry = lum3(r);
    } else if (op == OP_REINHARD) {
        float lavg = max(tm_log_avg(), LOG_DELTA);
        float scale = P.op1.y / lavg;
        float w = P.op1.z > 0.0 ? P.op1.z : WHITE_HEADROOM * scale * st.final_stats.y;
        float w2 = max(w * w, 1e-12);
        float ls = scale * L;
        float ld = ls / (1.0 + ls) * (1.0 + ls / w2);
        if (ld > 1.0) {
            flags |= F_ABOVE;
            ld = 1.0;
        }
        float k = L > 0.0 ? ld / L : 0.0;
        r = c * k;
        ry = ld;
    } else if (op == OP_LOCAL || op == OP_SELECTIVE) {
        // the global curve of the selective framework, Ld = L / (1 + L)
        float ls = P.op1.y / max(tm_log_avg(), LOG_DELTA) * L;
        ry = ls / (1.0 + ls);
        r = c * (L > 0.0 ? ry / L : 0.0);
    } else if (op == OP_NEUTRAL) {
        r = pbr_neutral(P.op1.x * exposure * c);
        ry = lum3(r);
    } else {
        if (op == OP_ADAPTIVE) {
            float lp = white_cd * exposure * L;
            float knee = P.op1.w;
            if (knee > 0.0 && lp < knee) {
                ry = (knee - lmin) / dl * pow(lp / knee, P.op2.x);
            } else {
                // shoulder constants from the frame statistics (prw_tm_derive)
                float U = log(max(WHITE_HEADROOM * exposure * st.final_stats.y, 1e-30));
                float V = log(lmax / white_cd);
                bool on = V > 0.0 && U > V * (1.0 + 1e-6);
                if (lp <= white_cd || !on) {
                    ry = (min(lp, lmax) - lmin) / dl;
                } else {
                    float lam = P.op2.y;
                    float m = lam * V / U, a = 1.0 - m;
                    float b = (a * U / ((1.0 - lam) * V) - 1.0) / U;
                    float u = log(lp / white_cd);
                    float v = min(a * u / (1.0 + b * u) + m * u, V);
                    ry = (white_cd * exp(v) - lmin) / dl;
                }
            }
        } else {
            if (L < lmin) flags |= F_BELOW;
            if (L > lmax) flags |= F_ABOVE;
            ry = (clamp(L, lmin, lmax) - lmin) / dl;
        }
        float yt = lmin + ry * dl;
        r = L > 0.0 ? ry + yt / dl * (c / L - 1.0) : vec3(ry);
    }
    return tm_finish(r, ry, flags);
}

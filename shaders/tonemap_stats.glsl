// Tone-mapping statistics, stage 1 (pass_tonemap.c "tm_stats"), shared by tonemap_stats.comp and,
// with TM_CLASSIFY, tonemap_classify.comp (selective): one workgroup of 16 x 16 invocations per
// 64 x 64 region of one view: each invocation sums 16 pixels, the sum of ln(delta + Y) (Reinhard et
// al. 2002, eq. 1, delta guards against log 0), the largest Y and the pixel count, into its own
// partial slot (256 per workgroup).  Input sanitised
// like tonemap_ops.c: NaN and negative -> 0, above 1e12 cd/m^2 (and +Inf) -> 1e12.
// TM_CLASSIFY: the same ln(delta + Y) of the region and a 1-pixel clamp-to-edge halo stay in shared
// memory, and the 3 x 3 Sobel of log10(delta + Y) = ln(delta + Y) / ln 10 gives each 16 x 16 block's
// largest gradient |(Gx, Gy)| / 8 (log10 units per pixel), stored for tonemap_compact.comp, which
// marks the tiles (mirror of prw_tm_classify, tonemap_ops.c).  The classification costs one more
// barrier and the halo's logs, not a pass of its own over the image.
const int REG = 64;
#ifdef TM_CLASSIFY
const int SIDE = REG + 2;
shared float s_lg[SIDE * SIDE];
shared uint s_bg[16]; // largest gradient per block of the region (non-negative float bits)
#endif

void main()
{
    uint t = gl_LocalInvocationIndex;
    ivec2 org = ivec2(gl_WorkGroupID.xy) * REG, lp = ivec2(gl_LocalInvocationID.xy);
    ivec2 size = ivec2(int(pc.width), int(pc.height));
    float s = 0.0, m = 0.0, n = 0.0;
#ifdef TM_CLASSIFY
    if (t < 16u) s_bg[t] = 0u;
    for (int i = int(t); i < SIDE * SIDE; i += 256) {
        ivec2 q = org - 1 + ivec2(i % SIDE, i / SIDE);
        ivec2 qc = clamp(q, ivec2(0), size - 1);
        float y = lum3(san3(texelFetch(src, qc, 0).rgb));
        float l = log(LOG_DELTA + y);
        s_lg[i] = l;
        if (q == qc && all(greaterThanEqual(q, org)) && all(lessThan(q, org + REG))) {
            s += l;
            m = max(m, y);
            n += 1.0;
        }
    }
    barrier();
    // invocation (x, y) takes block (x / 4, y / 4) of the region, its pixels (x % 4 + 4 i, y % 4 + 4 j)
    ivec2 blk = lp / 4, sub = lp % 4;
    float g = 0.0;
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            ivec2 pp = blk * 16 + sub + 4 * ivec2(i, j);
            if (any(greaterThanEqual(org + pp, size))) continue;
            int c = (pp.y + 1) * SIDE + pp.x + 1;
            float a = s_lg[c - SIDE - 1], b = s_lg[c - SIDE], cc = s_lg[c - SIDE + 1];
            float d = s_lg[c - 1], f = s_lg[c + 1];
            float h = s_lg[c + SIDE - 1], ii = s_lg[c + SIDE], jj = s_lg[c + SIDE + 1];
            float gx = (cc + 2.0 * f + jj) - (a + 2.0 * d + h);
            float gy = (h + 2.0 * ii + jj) - (a + 2.0 * b + cc);
            g = max(g, gx * gx + gy * gy);
        }
    // |G| / 8 in log10 units: sqrt(g) / (8 ln 10)
    atomicMax(s_bg[blk.y * 4 + blk.x], floatBitsToUint(sqrt(g) * 0.054286810235402240));
#else
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            ivec2 q = org + lp + 16 * ivec2(i, j);
            if (any(greaterThanEqual(q, size))) continue;
            float y = lum3(san3(texelFetch(src, q, 0).rgb));
            s += log(LOG_DELTA + y);
            m = max(m, y);
            n += 1.0;
        }
#endif
    // one partial per invocation (16 pixels), summed by tonemap_reduce.comp: no shared-memory tree
    // (on lavapipe every barrier switches all of the workgroup's coroutines)
    st.partial[pc.base + (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + t] = vec4(s, m, n, 0.0);
#ifdef TM_CLASSIFY
    barrier(); // every block's atomicMax done
    if (t < 16u) {
        uvec2 b = gl_WorkGroupID.xy * 4u + uvec2(t % 4u, t / 4u);
        if (b.x < tm_blocks_x() && b.y < tm_blocks_y())
            tl.data[tm_bgrad_base() + b.y * tm_blocks_x() + b.x] = s_bg[t];
    }
#endif
}

/* cornell_gltf — see cornell_gltf.h. */
#include "cornell_gltf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { WHITE, RED, GREEN, LIGHT, MAT_COUNT };

/* Quads (4 corners in order, millimetres) with their material. */
typedef struct quad {
    int mat;
    double p[4][3];
} quad;

static const quad QUADS[] = {
    /* the light, flush with the ceiling, which has a hole for it (4 strips): no ceiling point meets
     * the light's edge at grazing distance (a light hung just below a whole ceiling makes a
     * singular, heavy-tailed corner there) */
    {LIGHT, {{343.0, 548.8, 227.0}, {343.0, 548.8, 332.0}, {213.0, 548.8, 332.0}, {213.0, 548.8, 227.0}}},
    {WHITE, {{552.8, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 559.2}, {549.6, 0.0, 559.2}}},             /* floor */
    {WHITE, {{556.0, 548.8, 0.0}, {556.0, 548.8, 227.0}, {0.0, 548.8, 227.0}, {0.0, 548.8, 0.0}}},     /* ceiling */
    {WHITE, {{556.0, 548.8, 332.0}, {556.0, 548.8, 559.2}, {0.0, 548.8, 559.2}, {0.0, 548.8, 332.0}}},
    {WHITE, {{556.0, 548.8, 227.0}, {556.0, 548.8, 332.0}, {343.0, 548.8, 332.0}, {343.0, 548.8, 227.0}}},
    {WHITE, {{213.0, 548.8, 227.0}, {213.0, 548.8, 332.0}, {0.0, 548.8, 332.0}, {0.0, 548.8, 227.0}}},
    {WHITE, {{549.6, 0.0, 559.2}, {0.0, 0.0, 559.2}, {0.0, 548.8, 559.2}, {556.0, 548.8, 559.2}}},     /* back */
    {GREEN, {{0.0, 0.0, 559.2}, {0.0, 0.0, 0.0}, {0.0, 548.8, 0.0}, {0.0, 548.8, 559.2}}},             /* right */
    {RED, {{552.8, 0.0, 0.0}, {549.6, 0.0, 559.2}, {556.0, 548.8, 559.2}, {556.0, 548.8, 0.0}}},       /* left */
    /* short block */
    {WHITE, {{130.0, 165.0, 65.0}, {82.0, 165.0, 225.0}, {240.0, 165.0, 272.0}, {290.0, 165.0, 114.0}}},
    {WHITE, {{290.0, 0.0, 114.0}, {290.0, 165.0, 114.0}, {240.0, 165.0, 272.0}, {240.0, 0.0, 272.0}}},
    {WHITE, {{130.0, 0.0, 65.0}, {130.0, 165.0, 65.0}, {290.0, 165.0, 114.0}, {290.0, 0.0, 114.0}}},
    {WHITE, {{82.0, 0.0, 225.0}, {82.0, 165.0, 225.0}, {130.0, 165.0, 65.0}, {130.0, 0.0, 65.0}}},
    {WHITE, {{240.0, 0.0, 272.0}, {240.0, 165.0, 272.0}, {82.0, 165.0, 225.0}, {82.0, 0.0, 225.0}}},
    /* tall block */
    {WHITE, {{423.0, 330.0, 247.0}, {265.0, 330.0, 296.0}, {314.0, 330.0, 456.0}, {472.0, 330.0, 406.0}}},
    {WHITE, {{423.0, 0.0, 247.0}, {423.0, 330.0, 247.0}, {472.0, 330.0, 406.0}, {472.0, 0.0, 406.0}}},
    {WHITE, {{472.0, 0.0, 406.0}, {472.0, 330.0, 406.0}, {314.0, 330.0, 456.0}, {314.0, 0.0, 456.0}}},
    {WHITE, {{314.0, 0.0, 456.0}, {314.0, 330.0, 456.0}, {265.0, 330.0, 296.0}, {265.0, 0.0, 296.0}}},
    {WHITE, {{265.0, 0.0, 296.0}, {265.0, 330.0, 296.0}, {423.0, 330.0, 247.0}, {423.0, 0.0, 247.0}}},
};
#define QUAD_COUNT (sizeof QUADS / sizeof QUADS[0])

bool cornell_write_gltf(const char *out, double emission, char *err, size_t cap)
{
    size_t n = strlen(out);
    if (n < 6 || strcmp(out + n - 5, ".gltf") != 0) {
        snprintf(err, cap, "%s: the output name must end in .gltf", out);
        return false;
    }
    char *bin = malloc(n + 1);
    memcpy(bin, out, n - 5);
    strcpy(bin + n - 5, ".bin");
    const char *bin_name = strrchr(bin, '/') ? strrchr(bin, '/') + 1 : bin;

    /* One primitive per material: flat-shaded quads (4 vertices, 2 triangles each). */
    float pos[QUAD_COUNT * 4][3], nrm[QUAD_COUNT * 4][3];
    unsigned short idx[QUAD_COUNT * 6];
    size_t vstart[MAT_COUNT], vcount[MAT_COUNT], istart[MAT_COUNT], icount[MAT_COUNT];
    float lo[MAT_COUNT][3], hi[MAT_COUNT][3];
    size_t nv = 0, ni = 0;
    for (int m = 0; m < MAT_COUNT; m++) {
        vstart[m] = nv, istart[m] = ni;
        for (int c = 0; c < 3; c++) lo[m][c] = 1e30f, hi[m][c] = -1e30f;
        for (size_t q = 0; q < QUAD_COUNT; q++) {
            if (QUADS[q].mat != m) continue;
            const double(*p)[3] = QUADS[q].p;
            double a[3], b[3], nn[3];
            for (int c = 0; c < 3; c++) a[c] = p[1][c] - p[0][c], b[c] = p[2][c] - p[0][c];
            nn[0] = a[1] * b[2] - a[2] * b[1], nn[1] = a[2] * b[0] - a[0] * b[2], nn[2] = a[0] * b[1] - a[1] * b[0];
            double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            size_t v0 = nv - vstart[m];
            for (int k = 0; k < 4; k++, nv++)
                for (int c = 0; c < 3; c++) {
                    pos[nv][c] = (float)(p[k][c] * 1e-3);
                    nrm[nv][c] = (float)(nn[c] / l);
                    lo[m][c] = fminf(lo[m][c], pos[nv][c]);
                    hi[m][c] = fmaxf(hi[m][c], pos[nv][c]);
                }
            const unsigned short t[6] = {0, 1, 2, 0, 2, 3};
            for (int k = 0; k < 6; k++) idx[ni++] = (unsigned short)(v0 + t[k]);
        }
        vcount[m] = nv - vstart[m], icount[m] = ni - istart[m];
    }
    size_t pos_bytes = nv * sizeof pos[0], idx_bytes = ni * sizeof idx[0];
    FILE *fb = fopen(bin, "wb");
    if (!fb || fwrite(pos, 1, pos_bytes, fb) != pos_bytes || fwrite(nrm, 1, pos_bytes, fb) != pos_bytes ||
        fwrite(idx, 1, idx_bytes, fb) != idx_bytes || fclose(fb) != 0) {
        if (fb) fclose(fb);
        snprintf(err, cap, "%s: cannot write", bin);
        free(bin);
        return false;
    }
    FILE *f = fopen(out, "w");
    if (!f) {
        snprintf(err, cap, "%s: cannot write", out);
        free(bin);
        return false;
    }
    /* Reflectances: the usual RGB stand-ins for the measured spectra; light colour of its spectrum. */
    static const double ALBEDO[MAT_COUNT][3] = {{0.725, 0.71, 0.68}, {0.63, 0.065, 0.05}, {0.14, 0.45, 0.091}, {0.78, 0.78, 0.78}};
    static const char *NAMES[MAT_COUNT] = {"white", "red", "green", "light"};
    fprintf(f, "{\n \"asset\": {\"version\": \"2.0\", \"generator\": \"prw tests/reference/cornell_box\"},\n");
    fprintf(f, " \"extensionsUsed\": [\"KHR_materials_emissive_strength\", \"KHR_materials_specular\"],\n");
    fprintf(f, " \"scene\": 0, \"scenes\": [{\"nodes\": [0, 1]}],\n");
    fprintf(f, " \"nodes\": [{\"name\": \"box\", \"mesh\": 0}, {\"name\": \"camera\", \"camera\": 0, "
               "\"translation\": [0.278, 0.273, -0.8], \"rotation\": [0, 1, 0, 0]}],\n");
    fprintf(f, " \"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": %.9f, \"aspectRatio\": 1.0, "
               "\"znear\": 0.01, \"zfar\": 10.0}}],\n",
            2 * atan(12.5 / 35.0));
    fprintf(f, " \"materials\": [\n");
    for (int m = 0; m < MAT_COUNT; m++) {
        fprintf(f, "  {\"name\": \"%s\", \"doubleSided\": %s, \"pbrMetallicRoughness\": {\"baseColorFactor\": "
                   "[%.4f, %.4f, %.4f, 1.0], \"metallicFactor\": 0.0, \"roughnessFactor\": 1.0}",
                NAMES[m], m == LIGHT ? "false" : "true", ALBEDO[m][0], ALBEDO[m][1], ALBEDO[m][2]);
        fprintf(f, ", \"extensions\": {\"KHR_materials_specular\": {\"specularFactor\": 0.0}");
        if (m == LIGHT)
            fprintf(f, ", \"KHR_materials_emissive_strength\": {\"emissiveStrength\": %.9g}}, "
                       "\"emissiveFactor\": [1.0, 0.7, 0.25]",
                    emission);
        else
            fprintf(f, "}");
        fprintf(f, "}%s\n", m + 1 < MAT_COUNT ? "," : "");
    }
    fprintf(f, " ],\n \"meshes\": [{\"name\": \"cornell\", \"primitives\": [\n");
    for (int m = 0; m < MAT_COUNT; m++)
        fprintf(f, "  {\"attributes\": {\"POSITION\": %d, \"NORMAL\": %d}, \"indices\": %d, \"material\": %d}%s\n",
                3 * m, 3 * m + 1, 3 * m + 2, m, m + 1 < MAT_COUNT ? "," : "");
    fprintf(f, " ]}],\n \"accessors\": [\n");
    for (int m = 0; m < MAT_COUNT; m++) {
        fprintf(f, "  {\"bufferView\": 0, \"byteOffset\": %zu, \"componentType\": 5126, \"count\": %zu, \"type\": \"VEC3\", "
                   "\"min\": [%.9g, %.9g, %.9g], \"max\": [%.9g, %.9g, %.9g]},\n",
                vstart[m] * sizeof pos[0], vcount[m], lo[m][0], lo[m][1], lo[m][2], hi[m][0], hi[m][1], hi[m][2]);
        fprintf(f, "  {\"bufferView\": 1, \"byteOffset\": %zu, \"componentType\": 5126, \"count\": %zu, \"type\": \"VEC3\"},\n",
                vstart[m] * sizeof nrm[0], vcount[m]);
        fprintf(f, "  {\"bufferView\": 2, \"byteOffset\": %zu, \"componentType\": 5123, \"count\": %zu, \"type\": \"SCALAR\"}%s\n",
                istart[m] * sizeof idx[0], icount[m], m + 1 < MAT_COUNT ? "," : "");
    }
    fprintf(f, " ],\n \"bufferViews\": [\n");
    fprintf(f, "  {\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": %zu, \"target\": 34962},\n", pos_bytes);
    fprintf(f, "  {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu, \"target\": 34962},\n", pos_bytes, pos_bytes);
    fprintf(f, "  {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu, \"target\": 34963}\n", 2 * pos_bytes, idx_bytes);
    fprintf(f, " ],\n \"buffers\": [{\"uri\": \"%s\", \"byteLength\": %zu}]\n}\n", bin_name, 2 * pos_bytes + idx_bytes);
    free(bin);
    if (fclose(f) != 0) {
        snprintf(err, cap, "%s: cannot write", out);
        return false;
    }
    return true;
}

/* gltf_writer.c — see gltf_writer.h. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gltf_writer.h"
#include "prw_image.h"
#include "prw_math.h"
#include "prw_scene.h"
#include "prw_strbuf.h"
#include "prw_test.h"

void gltfw_mesh_free(gmesh *m)
{
    free(m->pos), free(m->nrm), free(m->uv), free(m->uv1), free(m->idx);
    memset(m, 0, sizeof *m);
}

/* centre +- hu +- hv (prw_scene_add_quad's convention: normal hu x hv, uv (0, 0) at centre - hu + hv). */
gmesh gltfw_quad(const double c[3], const double hu[3], const double hv[3], int material)
{
    gmesh m = {.nv = 4, .ni = 6, .material = material};
    m.pos = malloc(12 * sizeof(float)), m.nrm = malloc(12 * sizeof(float)), m.uv = malloc(8 * sizeof(float));
    m.idx = malloc(6 * sizeof(uint32_t));
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {1, 1, -1, -1}; /* top-left, top-right, bottom-right, bottom-left */
    double n[3] = {hu[1] * hv[2] - hu[2] * hv[1], hu[2] * hv[0] - hu[0] * hv[2], hu[0] * hv[1] - hu[1] * hv[0]};
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int v = 0; v < 4; v++) {
        for (int k = 0; k < 3; k++) {
            m.pos[3 * v + k] = (float)(su[v] * hu[k] + sv[v] * hv[k]);
            m.nrm[3 * v + k] = (float)(n[k] / l);
        }
        m.uv[2 * v] = (float)(0.5 + 0.5 * su[v]);
        m.uv[2 * v + 1] = (float)(0.5 - 0.5 * sv[v]);
    }
    const uint32_t idx[6] = {3, 2, 1, 3, 1, 0}; /* counter-clockwise seen from the normal's side */
    memcpy(m.idx, idx, sizeof idx);
    for (int k = 0; k < 3; k++) m.at[k] = c[k];
    return m;
}

gmesh gltfw_sphere(const double c[3], double r, int slices, int stacks, int material)
{
    gmesh m = {.nv = (uint32_t)((slices + 1) * (stacks + 1)), .ni = (uint32_t)(6 * slices * stacks), .material = material};
    m.pos = malloc(m.nv * 3 * sizeof(float)), m.nrm = malloc(m.nv * 3 * sizeof(float));
    m.uv = malloc(m.nv * 2 * sizeof(float)), m.idx = malloc(m.ni * sizeof(uint32_t));
    uint32_t v = 0, t = 0;
    for (int j = 0; j <= stacks; j++)
        for (int i = 0; i <= slices; i++, v++) {
            double th = PRW_PI * j / stacks, ph = 2 * PRW_PI * i / slices;
            double n[3] = {sin(th) * cos(ph), cos(th), -sin(th) * sin(ph)};
            for (int k = 0; k < 3; k++) m.pos[3 * v + k] = (float)(r * n[k]), m.nrm[3 * v + k] = (float)n[k];
            m.uv[2 * v] = (float)i / slices, m.uv[2 * v + 1] = (float)j / stacks;
        }
    for (int j = 0; j < stacks; j++)
        for (int i = 0; i < slices; i++) {
            uint32_t a = (uint32_t)(j * (slices + 1) + i), b = a + (uint32_t)slices + 1;
            const uint32_t q[6] = {a, b, a + 1, a + 1, b, b + 1};
            memcpy(m.idx + t, q, sizeof q);
            t += 6;
        }
    for (int k = 0; k < 3; k++) m.at[k] = c[k];
    return m;
}

static int add_view(uint8_t **bin, size_t *len, prw_strbuf *bv, int *views, const void *data, size_t n)
{
    size_t off = (*len + 3) & ~(size_t)3;
    *bin = realloc(*bin, off + n);
    memset(*bin + *len, 0, off - *len);
    memcpy(*bin + off, data, n);
    *len = off + n;
    prw_strbuf_printf(bv, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", *views ? "," : "", off, n);
    return (*views)++;
}

/* A node rotation looking from `from` towards `to` (-Z forward, +Y up). */
static prw_dquat look_rotation(const double from[3], const double to[3])
{
    prw_node n = prw_node_look_at("x", prw_v3(from[0], from[1], from[2]), prw_v3(to[0], to[1], to[2]), prw_v3(0, 1, 0));
    return n.rotation;
}

/* Writes <name>.gltf and <name>.bin into the scratch directory; returns the .gltf path. */
const char *gltfw_write(const char *name, const gfile *f, double aspect)
{
    uint8_t *bin = NULL;
    size_t len = 0;
    int views = 0, accs = 0;
    prw_strbuf bv = {0}, ac = {0}, me = {0}, no = {0}, sn = {0};
    for (int i = 0; i < f->mesh_count; i++) {
        const gmesh *m = &f->mesh[i];
        float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
        for (uint32_t v = 0; v < m->nv; v++)
            for (int c = 0; c < 3; c++) lo[c] = fminf(lo[c], m->pos[3 * v + c]), hi[c] = fmaxf(hi[c], m->pos[3 * v + c]);
        int a = accs;
        int vp = add_view(&bin, &len, &bv, &views, m->pos, m->nv * 12);
        int vn = add_view(&bin, &len, &bv, &views, m->nrm, m->nv * 12);
        int vu = add_view(&bin, &len, &bv, &views, m->uv, m->nv * 8);
        int vu1 = m->uv1 ? add_view(&bin, &len, &bv, &views, m->uv1, m->nv * 8) : -1;
        int vi = add_view(&bin, &len, &bv, &views, m->idx, m->ni * 4);
        prw_strbuf_printf(&ac, "%s{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\",\"min\":[%g,%g,%g],"
                       "\"max\":[%g,%g,%g]}",
                  accs ? "," : "", vp, m->nv, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        prw_strbuf_printf(&ac, ",{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\"}", vn, m->nv);
        prw_strbuf_printf(&ac, ",{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC2\"}", vu, m->nv);
        accs += 3;
        if (vu1 >= 0) {
            prw_strbuf_printf(&ac, ",{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC2\"}", vu1, m->nv);
            accs++;
        }
        prw_strbuf_printf(&ac, ",{\"bufferView\":%d,\"componentType\":5125,\"count\":%u,\"type\":\"SCALAR\"}", vi, m->ni);
        int ai = accs++;
        prw_strbuf_printf(&me, "%s{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d,\"TEXCOORD_0\":%d", i ? "," : "",
                  a, a + 1, a + 2);
        if (vu1 >= 0) prw_strbuf_printf(&me, ",\"TEXCOORD_1\":%d", a + 3);
        prw_strbuf_printf(&me, "},\"indices\":%d,\"material\":%d}]}", ai, m->material);
        prw_strbuf_printf(&no, "%s{\"name\":\"mesh%d\",\"mesh\":%d,\"translation\":[%.17g,%.17g,%.17g]}", i ? "," : "", i, i,
                  m->at[0], m->at[1], m->at[2]);
        prw_strbuf_printf(&sn, "%s%d", i ? "," : "", i);
    }
    int nodes = f->mesh_count;
    prw_dquat q = look_rotation(f->eye, f->target);
    prw_strbuf_printf(&no, ",{\"name\":\"cam\",\"camera\":0,\"translation\":[%.17g,%.17g,%.17g],\"rotation\":[%.17g,%.17g,%.17g,%.17g]}",
              f->eye[0], f->eye[1], f->eye[2], q.x, q.y, q.z, q.w);
    prw_strbuf_printf(&sn, ",%d", nodes++);
    const char *lights = "";
    if (f->light) {
        prw_dquat lq = look_rotation(f->light_at, f->light_to);
        prw_strbuf_printf(&no, ",{\"name\":\"light\",\"translation\":[%.17g,%.17g,%.17g],\"rotation\":[%.17g,%.17g,%.17g,%.17g],"
                       "\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}",
                  f->light_at[0], f->light_at[1], f->light_at[2], lq.x, lq.y, lq.z, lq.w);
        prw_strbuf_printf(&sn, ",%d", nodes++);
        lights = f->light == 1 ? "\"directional\"" : "\"point\"";
    }
    prw_strbuf tx = {0};
    for (int i = 0; i < f->image_count; i++)
        prw_strbuf_printf(&tx, "%s{\"source\":%d}", i ? "," : "", i);
    prw_strbuf im = {0};
    for (int i = 0; i < f->image_count; i++) prw_strbuf_printf(&im, "%s{\"uri\":\"%s\"}", i ? "," : "", f->images[i]);
    char binname[128];
    snprintf(binname, sizeof binname, "%s.bin", name);
    prw_strbuf j = {0};
    prw_strbuf_printf(&j, "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_lights_punctual\",\"KHR_materials_specular\"%s%s],",
              f->ext_used ? "," : "", f->ext_used ? f->ext_used : "");
    prw_strbuf_printf(&j, "\"scene\":0,\"scenes\":[{\"nodes\":[%s]}],\"nodes\":[%s],\"meshes\":[%s],", sn.p, no.p, me.p);
    prw_strbuf_printf(&j, "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":%.17g,\"znear\":0.05,\"aspectRatio\":%.17g}}],",
              f->yfov, aspect);
    if (f->light)
        prw_strbuf_printf(&j, "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":%s,\"intensity\":%.17g}]}},", lights,
                  f->intensity);
    prw_strbuf_printf(&j, "\"materials\":[%s],", f->materials);
    if (f->image_count) prw_strbuf_printf(&j, "\"textures\":[%s],\"images\":[%s],", tx.p, im.p);
    prw_strbuf_printf(&j, "\"buffers\":[{\"uri\":\"%s\",\"byteLength\":%zu}],\"bufferViews\":[%s],\"accessors\":[%s]}\n", binname,
              len, bv.p, ac.p);
    prw_test_write_file(prw_test_path(binname), bin, len);
    char gname[128];
    snprintf(gname, sizeof gname, "%s.gltf", name);
    char *path = prw_test_path(gname);
    prw_test_write_file(path, j.p, j.n);
    free(bin), free(bv.p), free(ac.p), free(me.p), free(no.p), free(sn.p), free(tx.p), free(im.p), free(j.p);
    return path;
}

bool gltfw_png(const char *name, int w, int h, const uint8_t *rgba)
{
    prw_error e;
    if (prw_png_write8(prw_test_path(name), w, h, 4, rgba, &e)) return true;
    fprintf(stderr, "%s\n", e.msg);
    return false;
}


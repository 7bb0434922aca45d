// draco_encode.cpp — test helper: a triangle mesh -> Draco stream with libdraco's encoder (the
// test writes its own KHR_draco_mesh_compression files; the loader only decodes).
#include "draco_encode.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <cstdlib>
#include <cstring>
#include <exception>

extern "C" bool test_draco_encode(const test_draco_input *in, test_draco_output *out)
{
    try {
        draco::Mesh mesh;
        mesh.set_num_points(in->vertex_count);
        struct {
            draco::GeometryAttribute::Type type;
            const float *data;
            int ncomp;
            uint32_t *uid;
        } atts[] = {{draco::GeometryAttribute::POSITION, in->positions, 3, &out->uid_position},
                    {draco::GeometryAttribute::NORMAL, in->normals, 3, &out->uid_normal},
                    {draco::GeometryAttribute::TEX_COORD, in->uvs, 2, &out->uid_uv}};
        for (auto &a : atts) {
            if (!a.data) continue;
            draco::GeometryAttribute ga;
            ga.Init(a.type, nullptr, (uint8_t)a.ncomp, draco::DT_FLOAT32, false, sizeof(float) * a.ncomp, 0);
            int id = mesh.AddAttribute(ga, true, in->vertex_count);
            if (id < 0) return false;
            for (uint32_t v = 0; v < in->vertex_count; v++)
                mesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(v), a.data + (size_t)v * a.ncomp);
            *a.uid = mesh.attribute(id)->unique_id();
        }
        for (uint32_t t = 0; t + 2 < in->index_count; t += 3)
            mesh.AddFace({draco::PointIndex(in->indices[t]), draco::PointIndex(in->indices[t + 1]),
                          draco::PointIndex(in->indices[t + 2])});
        draco::Encoder enc;
        enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, in->position_bits);
        enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
        enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
        enc.SetEncodingMethod(in->edgebreaker ? draco::MESH_EDGEBREAKER_ENCODING : draco::MESH_SEQUENTIAL_ENCODING);
        draco::EncoderBuffer buf;
        if (!enc.EncodeMeshToBuffer(mesh, &buf).ok()) return false;
        out->size = buf.size();
        out->data = (uint8_t *)malloc(buf.size());
        if (!out->data) return false;
        memcpy(out->data, buf.data(), buf.size());
        return true;
    } catch (...) {
        return false;
    }
}

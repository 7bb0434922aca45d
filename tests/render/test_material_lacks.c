/* What a material slot lacks (scene_gpu.h, prw_scene_gpu_material_lacks): the bits the base pipelines
 * are specialised on (PRW_SC_MAT).  A bit set where the slot has the thing would change the image,
 * so each bit is checked both ways: absent textures and indices past the scene's textures are lacking
 * (the descriptor then holds the fallback), metallic counts as 0 or 1 only when exactly that (and 1
 * only without a metal-roughness texture, which would scale it). */
#include "prw_test.h"
#include "scene_gpu.h"

static void test_textures(void)
{
    prw_material m = prw_material_default();
    m.metallic = 0.5f;
    const uint32_t all = PRW_GPU_MAT_NO_BASE_TEX | PRW_GPU_MAT_NO_MR_TEX | PRW_GPU_MAT_NO_NORMAL_TEX |
                         PRW_GPU_MAT_NO_EMISSIVE_TEX;
    CHECK(prw_scene_gpu_material_lacks(&m, 4) == all);
    m.base_color_tex = 0;
    CHECK(prw_scene_gpu_material_lacks(&m, 4) == (all & ~PRW_GPU_MAT_NO_BASE_TEX));
    m.metal_rough_tex = 3;
    CHECK(prw_scene_gpu_material_lacks(&m, 4) == (all & ~(PRW_GPU_MAT_NO_BASE_TEX | PRW_GPU_MAT_NO_MR_TEX)));
    m.normal_tex = 4; /* past the scene's 4 textures: the flat fallback, no normal map */
    m.emissive_tex = 1;
    CHECK(prw_scene_gpu_material_lacks(&m, 4) == PRW_GPU_MAT_NO_NORMAL_TEX);
    CHECK(prw_scene_gpu_material_lacks(&m, 0) == all); /* no textures at all */
}

static void test_metallic(void)
{
    prw_material m = prw_material_default();
    const uint32_t metal = PRW_GPU_MAT_NO_METAL | PRW_GPU_MAT_ALL_METAL;
    m.metallic = 0.0f;
    CHECK((prw_scene_gpu_material_lacks(&m, 0) & metal) == PRW_GPU_MAT_NO_METAL);
    m.metal_rough_tex = 0; /* 0 x any texel is still 0 */
    CHECK((prw_scene_gpu_material_lacks(&m, 1) & metal) == PRW_GPU_MAT_NO_METAL);
    m.metallic = 1.0f; /* 1 x a texel is not 1 */
    CHECK((prw_scene_gpu_material_lacks(&m, 1) & metal) == 0);
    m.metal_rough_tex = -1;
    CHECK((prw_scene_gpu_material_lacks(&m, 1) & metal) == PRW_GPU_MAT_ALL_METAL);
    m.metallic = 0.999999f;
    CHECK((prw_scene_gpu_material_lacks(&m, 1) & metal) == 0);
    m.metallic = 1e-7f;
    CHECK((prw_scene_gpu_material_lacks(&m, 1) & metal) == 0);
}

static const prw_test_case cases[] = {
    {"textures", test_textures},
    {"metallic", test_metallic},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, PRW_ARRAY_LEN(cases)); }

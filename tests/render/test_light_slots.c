/* The GPU light slots (shadow_plan.h): grouped by shading class in the order the base shaders'
 * specialisation constants expect, each group in scene order, every light once; the globals carry the
 * lights in that order (view_globals.c). */
#include <string.h>

#include "prw_test.h"
#include "shadow_plan.h"
#include "view_globals.h"

static int add_light(prw_scene *s, prw_light_type type, bool shadows, double x)
{
    prw_node n = prw_node_default();
    n.translation = prw_v3(x, 2, 0);
    prw_light l = {.type = type, .color = {1, 1, 1}, .intensity = 10 + x, .cast_shadows = shadows,
                   .outer_cone = 0.5, .inner_cone = 0.3, .width = 1, .height = 1};
    l.node = prw_scene_add_node(s, &n);
    return prw_scene_add_light(s, &l);
}

static int class_of(const prw_scene *s, const prw_shadow_plan *p, uint32_t i)
{
    bool rect = s->lights[i].type == PRW_LIGHT_RECT, sh = p->light_first[i] >= 0;
    return rect ? (sh ? PRW_LIGHT_CLASS_RECT_SHADOWED : PRW_LIGHT_CLASS_RECT)
                : !sh ? PRW_LIGHT_CLASS_PUNCTUAL
                : s->lights[i].type == PRW_LIGHT_POINT ? PRW_LIGHT_CLASS_POINT_SHADOWED : PRW_LIGHT_CLASS_PUNCTUAL_SHADOWED;
}

static void test_grouped(void)
{
    prw_scene *s = prw_scene_create();
    /* mixed kinds and shadowing, and more shadow layers asked for than the atlas has (32: 6 per point
     * light): the last spot light gets none and changes class */
    const prw_light_type types[] = {PRW_LIGHT_POINT, PRW_LIGHT_RECT, PRW_LIGHT_SPOT, PRW_LIGHT_DIRECTIONAL,
                                    PRW_LIGHT_RECT,  PRW_LIGHT_POINT, PRW_LIGHT_POINT, PRW_LIGHT_POINT,
                                    PRW_LIGHT_POINT, PRW_LIGHT_POINT, PRW_LIGHT_SPOT};
    const bool shadows[] = {true, false, true, false, true, false, true, true, true, true, true};
    int n = (int)PRW_ARRAY_LEN(types);
    for (int i = 0; i < n; i++) CHECK(add_light(s, types[i], shadows[i], i) == i);
    prw_scene_update(s);
    prw_shadow_plan p;
    prw_shadow_plan_make(s, &p);
    CHECK(p.slot_count == (uint32_t)n);
    bool seen[PRW_MAX_LIGHTS] = {0};
    uint32_t k = 0;
    for (int c = 0; c < PRW_LIGHT_CLASSES; c++) {
        uint32_t prev = 0;
        for (uint32_t j = 0; j < p.class_count[c]; j++, k++) {
            uint32_t i = p.slot_light[k];
            CHECK(i < (uint32_t)n && !seen[i]);
            seen[i] = true;
            CHECK_MSG(class_of(s, &p, i) == c, "slot %u: light %u is of class %d, in group %d", k, i, class_of(s, &p, i), c);
            CHECK(j == 0 || i > prev); /* scene order within the group */
            prev = i;
        }
    }
    CHECK(k == p.slot_count);
    CHECK(p.class_count[PRW_LIGHT_CLASS_RECT_SHADOWED] == 1 && p.class_count[PRW_LIGHT_CLASS_RECT] == 1);
    CHECK(p.light_first[9] >= 0 && p.light_first[10] < 0); /* 5 cubes + spot + rect = 32 layers, then none */
    CHECK(p.class_count[PRW_LIGHT_CLASS_PUNCTUAL_SHADOWED] == 1 && p.class_count[PRW_LIGHT_CLASS_POINT_SHADOWED] == 5 &&
          p.class_count[PRW_LIGHT_CLASS_PUNCTUAL] == 3);
    prw_view v = prw_view_look_at(prw_v3(0, 1, 5), prw_v3(0, 1, 0), prw_v3(0, 1, 0), 1.0, 0.05, 64, 48, 7);
    prw_gpu_globals g;
    prw_view_globals_fill(s, &p, 1024, &v, prw_v3(0, 0, 0), &g);
    CHECK(g.params[0] == (float)n);
    for (k = 0; k < p.slot_count; k++) {
        const prw_light *l = &s->lights[p.slot_light[k]];
        CHECK(g.lights[k].pos_type[3] == (float)l->type);
        CHECK(g.lights[k].radiance[0] == (float)(l->color[0] * l->intensity));
        CHECK((g.lights[k].cone_shadow[2] >= 0) == (p.light_first[p.slot_light[k]] >= 0));
    }
    prw_scene_destroy(s);
}

static const prw_test_case cases[] = {
    {"grouped", test_grouped},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, PRW_ARRAY_LEN(cases)); }

/* Writes the hand-made IGES test models into a directory: iges_assets_gen <dir>
 * (used to produce the assets/nurbs IGES files and the fuzz seed corpus). */
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "iges_models.h"

static int save(const char *dir, const char *name, char *data, size_t n)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n) {
        fprintf(stderr, "%s: cannot write\n", path);
        return 1;
    }
    fclose(f);
    free(data);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2 && !(argc == 3 && !strcmp(argv[2], "--brep"))) {
        fprintf(stderr, "usage: iges_assets_gen <dir> [--brep]\n  --brep: the B-rep test solids instead (box, cylinder, "
                        "free-form, free faces on 190 planes, a bounded band, a 144 on a 190, a boundary running back along itself, unit flag 0, conics 104, a spline surface 114, offset surfaces 140; not stored in assets/)\n");
        return 2;
    }
    if (argc == 3) {
        size_t n;
        int err = 0;
        char *s = iges_model_brep_box(&n);
        err |= save(argv[1], "brep_box.igs", s, n);
        s = iges_model_brep_cylinder(&n);
        err |= save(argv[1], "brep_cylinder.igs", s, n);
        s = iges_model_brep_freeform(&n);
        err |= save(argv[1], "brep_freeform.igs", s, n);
        s = iges_model_brep_box_variant(true, true, &n);
        err |= save(argv[1], "brep_free_faces_190.igs", s, n);
        s = iges_model_bounded_band(false, &n);
        err |= save(argv[1], "bounded_band.igs", s, n);
        s = iges_model_plane190_trimmed(&n);
        err |= save(argv[1], "plane190_trimmed.igs", s, n);
        s = iges_model_spike_loop(1e-3, &n);
        err |= save(argv[1], "spike_loop.igs", s, n);
        s = iges_model_units(0, "", 1, 0, 1, &n);
        err |= save(argv[1], "unit_flag_0.igs", s, n);
        s = iges_model_conics(&n);
        err |= save(argv[1], "conics_104.igs", s, n);
        s = iges_model_spline114(&n);
        err |= save(argv[1], "spline_114.igs", s, n);
        s = iges_model_offsets(&n);
        err |= save(argv[1], "offsets_140.igs", s, n);
        return err;
    }
    size_t n;
    int err = 0;
    char *s = iges_model_sphere_rev(&n);
    err |= save(argv[1], "sphere_rev.igs", s, n);
    s = iges_model_trimmed_plate(&n);
    err |= save(argv[1], "trimmed_plate.igs", s, n);
    s = iges_model_all_entities(&n);
    err |= save(argv[1], "all_entities.igs", s, n);
    return err;
}

/* cornell_box — writes the classic Cornell box as glTF (cornell_gltf.h says what it is).
 * usage: cornell_box OUT.gltf [--emission E]   (E: cd/m^2 of the light's white point, default 1000) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cornell_gltf.h"

static void usage(void) { fprintf(stderr, "usage: cornell_box OUT.gltf [--emission CD_PER_M2]\n"); }

int main(int argc, char **argv)
{
    if (argc < 2 || argv[1][0] == '-') {
        usage();
        return 2;
    }
    const char *out = argv[1];
    double emission = 1000;
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "--emission") == 0 && i + 1 < argc) {
            char *end;
            emission = strtod(argv[++i], &end);
            if (*end || !(emission > 0) || !isfinite(emission)) {
                fprintf(stderr, "cornell_box: --emission %s: must be a finite number > 0\n", argv[i]);
                return 2;
            }
        } else {
            usage();
            return 2;
        }
    }
    char err[512];
    if (!cornell_write_gltf(out, emission, err, sizeof err)) {
        fprintf(stderr, "cornell_box: %s\n", err);
        return 1;
    }
    printf("wrote %s (%d triangles)\n", out, CORNELL_TRIANGLES);
    return 0;
}

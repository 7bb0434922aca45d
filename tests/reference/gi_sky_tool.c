/* gi_sky — writes the sky map of assets/scenes/gi-room-sky.json (gi_sky.h says what it is).
 * usage: gi_sky OUT.exr */
#include <stdio.h>

#include "gi_sky.h"

int main(int argc, char **argv)
{
    if (argc != 2 || argv[1][0] == '-') {
        fprintf(stderr, "usage: gi_sky OUT.exr\n");
        return 2;
    }
    prw_image img = {0};
    prw_error e = {{0}};
    const prw_kv attrs[] = {{"prw:source", "tests/reference/gi_sky.c"}, {"prw:units", "cd/m^2"}};
    bool ok = gi_sky_image(&img, &e) && prw_exr_write(argv[1], &img, attrs, 2, &e);
    prw_image_free(&img);
    if (!ok) {
        fprintf(stderr, "gi_sky: %s\n", e.msg);
        return 1;
    }
    printf("gi_sky: wrote %s (%dx%d)\n", argv[1], GI_SKY_WIDTH, GI_SKY_HEIGHT);
    return 0;
}

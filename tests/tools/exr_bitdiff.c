/* exr_bitdiff — compares the pixels of EXR files bit for bit (attributes such as the git hash are
 * ignored): `exr_bitdiff A.exr B.exr [A2.exr B2.exr ...]` prints per pair the number of float values
 * whose bits differ and the largest absolute difference; exit 0 only when every pair is identical. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "prw_image.h"

int main(int argc, char **argv)
{
    if (argc < 3 || (argc - 1) % 2) {
        fprintf(stderr, "usage: exr_bitdiff A.exr B.exr [A2.exr B2.exr ...]\n");
        return 2;
    }
    int rc = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        prw_image a = {0}, b = {0};
        prw_error e = {{0}};
        if (!prw_exr_read(argv[i], NULL, &a, &e) || !prw_exr_read(argv[i + 1], NULL, &b, &e)) {
            fprintf(stderr, "exr_bitdiff: %s\n", e.msg);
            prw_image_free(&a);
            prw_image_free(&b);
            return 2;
        }
        if (a.width != b.width || a.height != b.height) {
            printf("DIFFER %s %s: size %dx%d vs %dx%d\n", argv[i], argv[i + 1], a.width, a.height, b.width, b.height);
            rc = 1;
        } else {
            size_t n = (size_t)a.width * a.height * 4, diff = 0;
            double worst = 0;
            for (size_t k = 0; k < n; k++)
                if (memcmp(&a.rgba[k], &b.rgba[k], sizeof(float)) != 0) {
                    diff++;
                    double d = fabs((double)a.rgba[k] - b.rgba[k]);
                    if (d > worst || isnan(d)) worst = d;
                }
            printf("%s %s %s: %zu of %zu values differ (largest %g)\n", diff ? "DIFFER" : "IDENTICAL", argv[i],
                   argv[i + 1], diff, n, worst);
            if (diff) rc = 1;
        }
        prw_image_free(&a);
        prw_image_free(&b);
    }
    return rc;
}

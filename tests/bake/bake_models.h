/* Small models shared by the bake tests, the fuzz corpus generator and the CLI tests. */
#ifndef BAKE_MODELS_H
#define BAKE_MODELS_H

/* Two unit squares side by side (one flat, one curved), sharing the edge x = 1. */
#define BAKE_TWO_PATCH_JSON                                                                                    \
    "{\"prw_nurbs\": 1, \"surfaces\": [\n"                                                                     \
    " {\"nurbs\": {\"degree\": [1, 1], \"count\": [2, 2], \"knots_u\": [0, 0, 1, 1], \"knots_v\": [0, 0, 1, 1],\n" \
    "  \"points\": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]}},\n"                                        \
    " {\"nurbs\": {\"degree\": [2, 1], \"count\": [3, 2], \"knots_u\": [0, 0, 0, 1, 1, 1], \"knots_v\": [0, 0, 1, 1],\n" \
    "  \"points\": [[1, 0, 0], [1.5, 0, 0.3, 0.8], [2, 0, 0], [1, 1, 0], [1.5, 1, 0.3, 0.8], [2, 1, 0]]}}\n"  \
    "]}\n"

#endif

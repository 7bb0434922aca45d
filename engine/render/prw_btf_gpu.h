/* prw_btf_gpu — a BTF material (prw_btf_eval.h) packed into one array of 32-bit words, the layout
 * shaders/btf_eval.glsl reads from a storage buffer (no constant arrays: lavapipe's JIT).
 *
 * Promises:
 *  - prw_btf_gpu_pack appends material m at the end of *words (a growing array, freed by the caller
 *    with free()) and returns the word offset of its header: several materials share one buffer.
 *  - The layout (offsets are absolute word indices into the whole array; 0: absent):
 *      header (PRW_BTF_GPU_HEADER words): codec, width, height, views, lights, components, clusters,
 *        -, w, -, -, index, sp_start, sp_pair, sp_val (offsets of the per-texel arrays), view table,
 *        light table (offsets of direction tables; equal when the sets are shared), blocks (offset of
 *        the RGB blocks in 4-word texels), cols (blocks per group), env (offset of the environment
 *        table);
 *      direction table (5 words): triangle count, offsets of tri_inv (floats), tri_vert, cos_theta
 *        (floats), grid (PRW_BTF_GRID_WORDS words);
 *      halves (w, sp_val) and sp_pair's u16 two per word, the lower first; floats as their bits;
 *      the RGB blocks: the codec's direction-side arrays, for each group g and column: the R rows'
 *        channel triples in ceil(3 R / 8) 4-word texels (row r channel c at half 3 r + c, two halves a
 *        word, the lower first; the rest 0), block (g, col) at texel blocks + (g cols + col) ceil(3 R / 8).
 *        FMF: one group, rows U[.][j] (R = K), columns the direction pairs; CLUSTER / SPARSE: group i,
 *        rows M[i], B[i][0..K-1] (R = K + 1), columns the pairs; PVF: group v, rows M[v], B[v][0..K-1],
 *        columns the lights (K components).  One fetch of a 4 x 32-bit texel brings 8 halves.
 *      the environment table (btf_env.glsl): per measured light direction k, 5 floats: the centroid
 *        c_k (unit, BTF frame) of its interpolation weight w_k(l) (prw_btf_dirtab_weights, light), the
 *        weight's integral over the hemisphere A_k (sr; sum_k A_k cos theta_k = pi), and the roughness
 *        of the environment's prefiltered levels (prw_env.h) whose kernel has w_k's median angle about c_k.
 *        Then sum_k f_k A_k L(c_k, roughness_k) is the interpolated BTF's integral against a distant
 *        light L filtered by each direction's weight (the weights' integrals are numerical, to < 1e-3).
 *    Values equal the C material's to the bit, so btf_eval.glsl decodes what prw_btf_material_eval
 *    decodes, in its order of operations.
 *  - Fails (naming `name`) when the array would pass 2^31 words or the material has more than
 *    PRW_BTF_GPU_KMAX components (what btf_eval.glsl holds per texel).
 */
#ifndef PRW_BTF_GPU_H
#define PRW_BTF_GPU_H

#include <stddef.h>
#include <stdint.h>

#include "prw_btf_eval.h"
#include "prw_core.h"

#define PRW_BTF_GPU_HEADER 20u
#define PRW_BTF_GPU_KMAX 16u /* btf_eval.glsl PRW_BTF_KMAX */

typedef struct prw_btf_gpu_words {
    uint32_t *w;
    size_t count, cap;
} prw_btf_gpu_words;

/* The base pass's specialisation of a BTF slot (6 bits, base_btf.frag): (codec - 1) | (components + 1) << 2
 * when the components are at most 14, else (codec - 1) (the components read from the words). */
uint32_t prw_btf_gpu_spec(const prw_btf_packed *p);

bool prw_btf_gpu_pack(const prw_btf_material *m, const char *name, prw_btf_gpu_words *words, uint32_t *offset,
                      prw_error *e);

#endif

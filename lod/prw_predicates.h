/* prw_predicates — robust 2-D geometric predicates in double precision.
 *
 * Promises: prw_orient2d returns the EXACT sign of det[[bx-ax, cx-ax], [by-ay, cy-ay]] for finite
 * inputs whose products neither overflow nor underflow: a fast floating-point evaluation whose
 * error bound (Shewchuk's stage-A bound, 3.33e-16·(|l|+|r|)) is checked, and otherwise an exact
 * evaluation of the six products a_x·b_y … as fma-based two-products summed into a floating-point
 * expansion (Shewchuk's Grow-Expansion).  +1: c left of a→b (counter-clockwise), -1 right, 0 on
 * the line. */
#ifndef PRW_PREDICATES_H
#define PRW_PREDICATES_H

#ifdef __cplusplus
extern "C" {
#endif

int prw_orient2d(const double *a, const double *b, const double *c);

#ifdef __cplusplus
}
#endif
#endif

/* Dot products for the runtimes' long sums, with independent partial sums in fixed lanes.
 *
 * sum_f a[f] b[f] is taken as eight interleaved partial sums (element f into lane f % 8) combined in a fixed order
 * at the end, then the tail. Each lane is a plain sequential sum, so the result is the same bits whatever the vector
 * width the lanes are mapped onto (no reassociation beyond this fixed order, no fused multiply-add in ISO C mode):
 * deterministic across machines and builds, while no loop-carried dependency on one accumulator limits the speed.
 * Round-off: that of a sum of len / 8 terms per lane plus the combination, about as good as the sequential sum.
 *
 * With GCC on x86-64 Linux the function is compiled twice, for the baseline and for AVX2 (without FMA), and the
 * loader picks the one the processor runs (target_clones; -DWEC_NO_CLONES builds the baseline alone): the same
 * bits, twice the width. */
#ifndef WEC_DOT_H
#define WEC_DOT_H

#include <stddef.h>

double wec_dot(const double *a, const double *b, size_t len);

#endif

/* Shared between the MIPS optimizer and the hierarchical driver. */
#ifndef SK_MIPS_INTERNAL_H
#define SK_MIPS_INTERNAL_H

#include <stdbool.h>

/* A parameter triangle counts as inverted when twice its signed area is below this fraction of
 * the product of its two edge lengths at a corner (sine of the angle there < 1e-12): the MIPS
 * energy is treated as infinite and the line search never goes there. */
#define SK_MIPS_MIN_SINE 1e-12

/* True when (x, qj, qk) is counter-clockwise with the margin above (x is the moving vertex). */
static inline bool sk__mips_corner_ok(const double x[2], const double qj[2], const double qk[2])
{
    double dj[2] = {x[0] - qj[0], x[1] - qj[1]}, dk[2] = {x[0] - qk[0], x[1] - qk[1]};
    double b = dj[0] * dk[1] - dj[1] * dk[0];
    double lj = dj[0] * dj[0] + dj[1] * dj[1], lk = dk[0] * dk[0] + dk[1] * dk[1];
    return b > 0.0 && b * b > SK_MIPS_MIN_SINE * SK_MIPS_MIN_SINE * lj * lk;
}

#endif

/* Internal to the solve module: CHOLMOD's side of an sk_solver, for solvers built on its
 * factor (src/solve/bordered.c). */
#ifndef SK_SOLVE_SOLVER_INTERNAL_H
#define SK_SOLVE_SOLVER_INTERNAL_H

#include "surfkit/solve.h"
#include <cholmod.h>

/* The factor and the CHOLMOD workspace of a factorized Cholesky solver; NULL (and *cc
 * untouched) for an LU solver or before a successful factorization. The factor stays the
 * solver's; it may be converted (cholmod_change_factor) but not freed. */
cholmod_factor *sk__solver_cholmod(sk_solver *s, cholmod_common **cc);

#endif

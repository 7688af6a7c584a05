/* Internal to the solve module: CHOLMOD's side of an sk_solver, for solvers built on its
 * factor (src/solve/bordered.c), and the METIS lock. */
#ifndef SK_SOLVE_SOLVER_INTERNAL_H
#define SK_SOLVE_SOLVER_INTERNAL_H

#include "surfkit/solve.h"
#include <cholmod.h>

/* The factor and the CHOLMOD workspace of a factorized Cholesky solver; NULL (and *cc
 * untouched) for an LU solver or before a successful factorization. The factor stays the
 * solver's; it may be converted (cholmod_change_factor) but not freed. */
cholmod_factor *sk__solver_cholmod(sk_solver *s, cholmod_common **cc);

/* One METIS ordering at a time in the process (why: may_run_metis in solver.c). Every call that
 * may run METIS holds this mutex; it works with or without OpenMP and for the caller's own
 * threads. */
void sk__metis_lock(void);
void sk__metis_unlock(void);

#endif

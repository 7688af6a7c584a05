/* Internal to the solve module. */
#ifndef SK_SOLVE_INTERNAL_H
#define SK_SOLVE_INTERNAL_H

/* One METIS ordering at a time in the process (why: may_run_metis in solver.c). Every call that
 * may run METIS holds this mutex; it works with or without OpenMP and for the caller's own
 * threads. */
void sk__metis_lock(void);
void sk__metis_unlock(void);

#endif

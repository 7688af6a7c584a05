/* The vertex systems (8) of Cottin & van Damme, section 4:
 *
 *     Delta_{m+1} (P_{m+1} - V) = nu^m Delta_m (P_{m-1} - V) + w_1^m (P_m - V),
 *
 * P_m in the tangent plane at V (2D coordinates p_m), minimising sum |P_m - P*_m|^2. The problem is
 * bilinear in (p, w): solved by Gauss-Newton / SQP on all unknowns together (docs/VC1-NOTES.md 3).
 * Each step minimises |p + dp - p*|^2 + eps |dw|^2 subject to the linearised constraints
 * c + J d(p, w) = 0. The step is computed from the Schur complement S = J H^-1 J^T of the KKT system
 * (H = diag(1, eps)) with a Cholesky factorisation that skips vanishing pivots (at a feasible point of
 * a cycle J loses one rank: det prod A_m = 1 holds by eq. (5)); if that does not converge, the
 * same iteration is run with LAPACKE_dgglse (QR-based equality-constrained least squares). */
#include "smooth/smooth_internal.h"
#include "core/internal.h"
#include "core/vec.h"

#include <lapacke.h>
#include <string.h>
#include <stdio.h>
#include <stdlib.h>

#define EPS_W 1e-2         /* damping of dw relative to dp (coordinates scaled to unit targets); 1e-6 stalls at |c| ~ 1e-11 by cancellation */
#define RESIDUAL_OK 1e-13   /* |c| relative to the target scale counted as "exact" */
#define MAX_ITER 200
#define MAX_C (2 * SK_VSYS_MAX)

/* constraint m uses p_{m-1}, p_m, p_{m+1} (indices modulo n for cycles) */
static int cons_count(const sk__vsys *s) { return s->closed ? s->n_edges : s->n_edges - 2; }
static int cons_edge(const sk__vsys *s, int i) { return s->closed ? i : i + 1; }
static int wrap(const sk__vsys *s, int j) { return (j + s->n_edges) % s->n_edges; }

static inline double residual(const sk__vsys *s, const double *p, const double *w, double *c)
{
    int nc = cons_count(s);
    double mx = 0.0;
    for (int i = 0; i < nc; ++i) {
        int m = cons_edge(s, i), a = wrap(s, m - 1), b = wrap(s, m + 1);
        for (int k = 0; k < 2; ++k) {
            double v = s->du[m] * p[2 * b + k] - s->nu[m] * s->dd[m] * p[2 * a + k] -
                       w[m] * p[2 * m + k];
            if (c)
                c[2 * i + k] = v;
            mx = mx > fabs(v) ? mx : fabs(v);
        }
    }
    return mx;
}

/* Cholesky of the n x n SPD (or semi-definite) matrix A in place (lower); pivots below
 * tol * max diagonal are dropped (their unknowns are set to 0 in the solve). */
static inline void chol_skip(double *A, int n, unsigned char *drop)
{
    double dmax = 0.0;
    for (int i = 0; i < n; ++i)
        dmax = dmax > A[i * n + i] ? dmax : A[i * n + i];
    double tol = 1e-13 * dmax;
    for (int j = 0; j < n; ++j) {
        double d = A[j * n + j];
        for (int k = 0; k < j; ++k)
            d -= A[j * n + k] * A[j * n + k];
        if (d <= tol) {
            drop[j] = 1;
            for (int i = j; i < n; ++i)
                A[i * n + j] = 0.0;
            continue;
        }
        drop[j] = 0;
        d = sqrt(d);
        A[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double v = A[i * n + j];
            for (int k = 0; k < j; ++k)
                v -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = v / d;
        }
    }
}

static inline void chol_solve(const double *L, int n, const unsigned char *drop, double *b)
{
    for (int i = 0; i < n; ++i) {
        if (drop[i]) {
            b[i] = 0.0;
            continue;
        }
        double v = b[i];
        for (int k = 0; k < i; ++k)
            v -= L[i * n + k] * b[k];
        b[i] = v / L[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        if (drop[i]) {
            b[i] = 0.0;
            continue;
        }
        double v = b[i];
        for (int k = i + 1; k < n; ++k)
            v -= L[k * n + i] * b[k];
        b[i] = v / L[i * n + i];
    }
}

/* coefficients of constraint i on the p's: p_{a} * ca + p_m * cm + p_b * cb (times I_2) */
typedef struct { int a, m, b; double ca, cm, cb; } crow;

static inline void rows(const sk__vsys *s, const double *w, crow *r, int nc)
{
    for (int i = 0; i < nc; ++i) {
        int m = cons_edge(s, i);
        r[i].a = wrap(s, m - 1);
        r[i].m = m;
        r[i].b = wrap(s, m + 1);
        r[i].ca = -s->nu[m] * s->dd[m];
        r[i].cm = -w[m];
        r[i].cb = s->du[m];
        /* a fixed end is a constant: no column in the Jacobian, so no step moves it (the steps
         * start from p = p* there and the least-squares term keeps dp = 0) */
        if (!s->closed && s->fixed_first && r[i].a == 0)
            r[i].ca = 0.0;
        if (!s->closed && s->fixed_last && r[i].b == s->n_edges - 1)
            r[i].cb = 0.0;
    }
}

#define FMAX(a, b) ((a) > (b) ? (a) : (b))

/* One Gauss-Newton / SQP step by the Schur complement; returns the step size |dx|. The kernel is
 * inlined with constant sizes for the common closed stars (valence 3, 5, 7 after edge deletion),
 * which lets the compiler unroll it; other stars use the generic instance. */
static inline __attribute__((always_inline)) double schur_kernel(const sk__vsys *s, double *p,
                                                                 double *w, double *mu,
                                                                 const int n, const int nc)
{
    const int ns = 2 * nc;
    double c[MAX_C], S[MAX_C * MAX_C], rhs[MAX_C], r[2 * SK_VSYS_MAX];
    double J[SK_VSYS_MAX * SK_VSYS_MAX]; /* dense nc x n coefficients of the p's */
    unsigned char drop[MAX_C];
    crow cr[SK_VSYS_MAX];
    residual(s, p, w, c);
    rows(s, w, cr, nc);
    for (int j = 0; j < 2 * n; ++j)
        r[j] = s->pstar[j] - p[j];
    for (int i = 0; i < nc; ++i) {
        double *row = J + i * n;
        for (int j = 0; j < n; ++j)
            row[j] = 0.0;
        row[cr[i].a] += cr[i].ca;
        row[cr[i].m] += cr[i].cm;
        row[cr[i].b] += cr[i].cb;
    }
    /* S = Jp Jp^T + (1/eps) Jw Jw^T; both coordinates decouple in Jp Jp^T */
    for (int i = 0; i < nc; ++i) {
        for (int k = 0; k <= i; ++k) {
            double v = 0.0;
            for (int j = 0; j < n; ++j)
                v += J[i * n + j] * J[k * n + j];
            S[(2 * i) * ns + 2 * k] = S[(2 * k) * ns + 2 * i] = v;
            S[(2 * i + 1) * ns + 2 * k + 1] = S[(2 * k + 1) * ns + 2 * i + 1] = v;
            S[(2 * i) * ns + 2 * k + 1] = S[(2 * k + 1) * ns + 2 * i] = 0.0;
            S[(2 * i + 1) * ns + 2 * k] = S[(2 * k) * ns + 2 * i + 1] = 0.0;
        }
        int m = cr[i].m;
        double px = p[2 * m], py = p[2 * m + 1];
        S[(2 * i) * ns + 2 * i] += px * px / EPS_W;
        S[(2 * i) * ns + 2 * i + 1] += px * py / EPS_W;
        S[(2 * i + 1) * ns + 2 * i] += py * px / EPS_W;
        S[(2 * i + 1) * ns + 2 * i + 1] += py * py / EPS_W;
        /* rhs = Jp r + c */
        for (int k = 0; k < 2; ++k)
            rhs[2 * i + k] = cr[i].ca * r[2 * cr[i].a + k] + cr[i].cm * r[2 * m + k] +
                             cr[i].cb * r[2 * cr[i].b + k] + c[2 * i + k];
    }
    chol_skip(S, ns, drop);
    chol_solve(S, ns, drop, rhs);
    memcpy(mu, rhs, sizeof(double) * (size_t)ns); /* the multipliers of the converged problem */
    /* dp = r - Jp^T lambda, dw_m = (1/eps) p_m . lambda_m */
    double dp[2 * SK_VSYS_MAX];
    for (int j = 0; j < 2 * n; ++j)
        dp[j] = r[j];
    double norm = 0.0;
    for (int i = 0; i < nc; ++i) {
        for (int k = 0; k < 2; ++k) {
            double l = rhs[2 * i + k];
            dp[2 * cr[i].a + k] -= cr[i].ca * l;
            dp[2 * cr[i].m + k] -= cr[i].cm * l;
            dp[2 * cr[i].b + k] -= cr[i].cb * l;
        }
        int m = cr[i].m;
        double dw = (p[2 * m] * rhs[2 * i] + p[2 * m + 1] * rhs[2 * i + 1]) / EPS_W;
        w[m] += dw;
        norm = FMAX(norm, fabs(dw));
    }
    for (int j = 0; j < 2 * n; ++j) {
        p[j] += dp[j];
        norm = FMAX(norm, fabs(dp[j]));
    }
    return norm;
}

static double step_schur(const sk__vsys *s, double *p, double *w, double *mu)
{
    if (s->closed) {
        switch (s->n_edges) {
        case 3: return schur_kernel(s, p, w, mu, 3, 3);
        case 5: return schur_kernel(s, p, w, mu, 5, 5);
        case 7: return schur_kernel(s, p, w, mu, 7, 7);
        default: break;
        }
    }
    return schur_kernel(s, p, w, mu, s->n_edges, cons_count(s));
}

/* dgglse's workspace: at least M + N + P, plus room for blocked QR (block size up to 32) */
#define DGGLSE_WORK (3 * SK_VSYS_MAX + 3 * SK_VSYS_MAX + 2 * MAX_C + 32 * 3 * SK_VSYS_MAX)

/* The same step with LAPACKE_dgglse: minimise |A x - c| subject to B x = d, x = (dp, dw). */
static int step_dgglse(const sk__vsys *s, double *p, double *w)
{
    int n = s->n_edges, nc = cons_count(s);
    int N = 2 * n + nc, M = N, P = 2 * nc;
    double A[(3 * SK_VSYS_MAX) * (3 * SK_VSYS_MAX)], B[MAX_C * 3 * SK_VSYS_MAX];
    double cvec[3 * SK_VSYS_MAX], d[MAX_C], x[3 * SK_VSYS_MAX], cons[MAX_C];
    crow cr[SK_VSYS_MAX];
    residual(s, p, w, cons);
    rows(s, w, cr, nc);
    memset(A, 0, sizeof(double) * (size_t)(M * N));
    memset(B, 0, sizeof(double) * (size_t)(P * N));
    for (int j = 0; j < 2 * n; ++j) {
        A[j * N + j] = 1.0;
        cvec[j] = s->pstar[j] - p[j];
    }
    for (int i = 0; i < nc; ++i) {
        A[(2 * n + i) * N + 2 * n + i] = sqrt(EPS_W);
        cvec[2 * n + i] = 0.0;
        for (int k = 0; k < 2; ++k) {
            double *row = B + (2 * i + k) * N;
            row[2 * cr[i].a + k] += cr[i].ca;
            row[2 * cr[i].m + k] += cr[i].cm;
            row[2 * cr[i].b + k] += cr[i].cb;
            row[2 * n + i] = -p[2 * cr[i].m + k];
            d[2 * i + k] = -cons[2 * i + k];
        }
    }
    /* Column-major with our own workspace (on the stack): LAPACKE's row-major and workspace-query
     * paths malloc (outside the allocator hook) and report a failed malloc as info -1010/-1011,
     * which read as "singular" here; this call allocates nothing, so info != 0 means singular. */
    for (int r = 0; r < M; ++r) /* A is square (M == N): transpose in place */
        for (int c = r + 1; c < N; ++c) {
            double t = A[r * N + c];
            A[r * N + c] = A[c * N + r];
            A[c * N + r] = t;
        }
    double Bc[MAX_C * 3 * SK_VSYS_MAX], work[DGGLSE_WORK];
    for (int r = 0; r < P; ++r)
        for (int c = 0; c < N; ++c)
            Bc[c * P + r] = B[r * N + c];
    lapack_int info = LAPACKE_dgglse_work(LAPACK_COL_MAJOR, M, N, P, A, M, Bc, P > 0 ? P : 1, cvec,
                                          d, x, work, DGGLSE_WORK);
    if (info != 0)
        return -1;
    for (int j = 0; j < 2 * n; ++j)
        p[j] += x[j];
    for (int i = 0; i < nc; ++i)
        w[cr[i].m] += x[2 * n + i];
    return 0;
}

/* Newton step on the full KKT system of min 1/2 |p - p*|^2 s.t. c = 0 (exact Hessian of the
 * Lagrangian: c is bilinear, d2 c_m / dp_m dw_m = -I), solved by dense LU with partial pivoting.
 * mu holds the multipliers (updated). Used when Gauss-Newton converges slowly (targets far from
 * satisfying (8), large multipliers). Returns the step size, or -1 when the system is singular. */
#define NEWTON_MAX_EDGES 16
static double step_newton(const sk__vsys *s, double *p, double *w, double *mu)
{
    int n = s->n_edges, nc = cons_count(s);
    int N = 2 * n + nc, P = 2 * nc, T = N + P;
    double K[(5 * NEWTON_MAX_EDGES) * (5 * NEWTON_MAX_EDGES)], rhs[5 * NEWTON_MAX_EDGES];
    double c[MAX_C];
    crow cr[SK_VSYS_MAX];
    residual(s, p, w, c);
    rows(s, w, cr, nc);
    memset(K, 0, sizeof(double) * (size_t)(T * T));
    for (int j = 0; j < 2 * n; ++j) {
        K[j * T + j] = 1.0;
        rhs[j] = -(p[j] - s->pstar[j]);
    }
    for (int i = 0; i < nc; ++i) {
        int wi = 2 * n + i, m = cr[i].m;
        K[wi * T + wi] = 1e-12; /* keeps the w block from being exactly zero */
        rhs[wi] = 0.0;
        for (int k = 0; k < 2; ++k) {
            int row = N + 2 * i + k;
            /* J */
            K[row * T + 2 * cr[i].a + k] += cr[i].ca;
            K[row * T + 2 * cr[i].m + k] += cr[i].cm;
            K[row * T + 2 * cr[i].b + k] += cr[i].cb;
            K[row * T + wi] = -p[2 * m + k];
            /* J^T */
            K[(2 * cr[i].a + k) * T + row] += cr[i].ca;
            K[(2 * cr[i].m + k) * T + row] += cr[i].cm;
            K[(2 * cr[i].b + k) * T + row] += cr[i].cb;
            K[wi * T + row] = -p[2 * m + k];
            /* Hessian of mu^T c: d2/dp_m dw_m = -mu */
            K[(2 * m + k) * T + wi] += -mu[2 * i + k];
            K[wi * T + 2 * m + k] += -mu[2 * i + k];
            rhs[row] = -c[2 * i + k];
        }
    }
    /* LU with partial pivoting; unknowns (dx, mu_new) */
    for (int k = 0; k < T; ++k) {
        int pr = k;
        for (int i = k + 1; i < T; ++i)
            if (fabs(K[i * T + k]) > fabs(K[pr * T + k]))
                pr = i;
        if (fabs(K[pr * T + k]) < 1e-300)
            return -1.0;
        if (pr != k) {
            for (int j = 0; j < T; ++j) {
                double t = K[k * T + j];
                K[k * T + j] = K[pr * T + j];
                K[pr * T + j] = t;
            }
            double t = rhs[k];
            rhs[k] = rhs[pr];
            rhs[pr] = t;
        }
        for (int i = k + 1; i < T; ++i) {
            double f = K[i * T + k] / K[k * T + k];
            if (f == 0.0)
                continue;
            for (int j = k + 1; j < T; ++j)
                K[i * T + j] -= f * K[k * T + j];
            rhs[i] -= f * rhs[k];
        }
    }
    for (int k = T - 1; k >= 0; --k) {
        double v = rhs[k];
        for (int j = k + 1; j < T; ++j)
            v -= K[k * T + j] * rhs[j];
        rhs[k] = v / K[k * T + k];
    }
    double norm = 0.0;
    for (int j = 0; j < N; ++j)
        if (!isfinite(rhs[j]))
            return -1.0;
    for (int j = 0; j < 2 * n; ++j) {
        p[j] += rhs[j];
        norm = fmax(norm, fabs(rhs[j]));
    }
    for (int i = 0; i < nc; ++i) {
        w[cr[i].m] += rhs[2 * n + i];
        norm = fmax(norm, fabs(rhs[2 * n + i]));
    }
    for (int j = 0; j < P; ++j)
        mu[j] = rhs[N + j];
    return norm;
}

static void initial_w(const sk__vsys *s, const double *p, double *w)
{
    int nc = cons_count(s);
    for (int m = 0; m < s->n_edges; ++m)
        w[m] = 0.0;
    for (int i = 0; i < nc; ++i) {
        int m = cons_edge(s, i), a = wrap(s, m - 1), b = wrap(s, m + 1);
        double num = 0.0, den = 0.0;
        for (int k = 0; k < 2; ++k) {
            double rhs = s->du[m] * p[2 * b + k] - s->nu[m] * s->dd[m] * p[2 * a + k];
            num += rhs * p[2 * m + k];
            den += p[2 * m + k] * p[2 * m + k];
        }
        w[m] = den > 0.0 ? num / den : 0.0;
    }
}

/* Minimum-norm Gauss-Newton steps on c(p, w) = 0 alone (the targets moved onto the iterate each
 * step), at most `max` of them; 0 when the constraints hold to rounding. On failure p, w are left
 * at their values on entry. */
static int project_n(const sk__vsys *s, double *p, double *w, int *iters, int max)
{
    int n = s->n_edges;
    sk__vsys f;
    f.n_edges = n;
    f.closed = s->closed;
    f.fixed_first = s->fixed_first;
    f.fixed_last = s->fixed_last;
    memcpy(f.du, s->du, sizeof(double) * (size_t)n);
    memcpy(f.dd, s->dd, sizeof(double) * (size_t)n);
    memcpy(f.nu, s->nu, sizeof(double) * (size_t)n);
    double p0[2 * SK_VSYS_MAX], w0[SK_VSYS_MAX], mu[MAX_C];
    memcpy(p0, p, sizeof(double) * (size_t)(2 * n));
    memcpy(w0, w, sizeof(double) * (size_t)n);
    for (int it = 0; it < max; ++it) {
        memcpy(f.pstar, p, sizeof(double) * (size_t)(2 * n));
        step_schur(&f, p, w, mu);
        ++*iters;
        double r2 = residual(s, p, w, NULL);
        if (!isfinite(r2))
            break;
        if (r2 <= 1e-15)
            return 0;
    }
    memcpy(p, p0, sizeof(double) * (size_t)(2 * n));
    memcpy(w, w0, sizeof(double) * (size_t)n);
    return -1;
}

static int project(const sk__vsys *s, double *p, double *w, int *iters)
{
    return project_n(s, p, w, iters, 4);
}

#define FINISH_DX 1e-3 /* step size (in units of the mean target length) that starts the finish */
#define GN_FIRST 12 /* Gauss-Newton iterations before switching to Newton on the KKT system */
/* Newton steps rejected one after the other before the iteration stays with Gauss-Newton: a
 * rejected step is undone and followed by the Gauss-Newton step from the same point, so stopping
 * the tries changes no iterate while Newton would keep failing. At the sectors of crease vertices
 * (fixed ends) it failed every other iteration up to MAX_ITER (cow: 38 of 270 sector solves ran
 * 200 iterations, with about 95 Newton tries each). Measured on the shared meshes (cow, pig,
 * lion-head, armadillo, bunny00, mushroom, three_peaks, fandisk, nefertiti, knot1): the smooth
 * reports' shape figures identical. With 16 the cow's mean fairness moved in the sixth digit
 * (a Newton step after more undone ones would have been taken) and fandisk's refinement in
 * test_tolerance (stalled_rounds, 2.8e-3) no longer stalled. */
#define NEWTON_REJECTS 40

static int iterate(sk__vsys *s, double *p, double *w, int use_lapack, int *iters, int *tries)
{
    int n = s->n_edges, nc = cons_count(s);
    double mu[MAX_C];
    int newton = 0, finish_tries = 0, rejects = 0;
    for (int it = 0; it < MAX_ITER; ++it) {
        double dx;
        if (use_lapack) {
            if (step_dgglse(s, p, w) != 0)
                return -1;
            dx = 0.0;
        } else if (newton) {
            double p0[2 * SK_VSYS_MAX], w0[SK_VSYS_MAX], mu0[MAX_C];
            memcpy(p0, p, sizeof p0);
            memcpy(w0, w, sizeof w0);
            memcpy(mu0, mu, sizeof mu0);
            double r0 = residual(s, p, w, NULL);
            ++*tries;
            dx = step_newton(s, p, w, mu);
            if (dx < 0.0 || !(residual(s, p, w, NULL) < 10.0 * r0 + 1e-14)) {
                /* Newton diverged: back to Gauss-Newton */
                memcpy(p, p0, sizeof p0);
                memcpy(w, w0, sizeof w0);
                memcpy(mu, mu0, sizeof mu0);
                newton = 0;
                ++rejects;
                dx = step_schur(s, p, w, mu);
            } else {
                rejects = 0;
            }
        } else {
            dx = step_schur(s, p, w, mu);
            if (it + 1 >= GN_FIRST && n <= NEWTON_MAX_EDGES && nc > 0 && rejects < NEWTON_REJECTS)
                newton = 1;
        }
        ++*iters;
        double r2 = residual(s, p, w, NULL);
        if (!isfinite(r2) || !isfinite(dx))
            return -1;
        /* converged: constraints exact and the step has settled (use_lapack: no step size) */
        if (r2 <= 1e-15 && (dx < 1e-8 || (use_lapack && it >= 3)))
            return 0;
        /* near the optimum (steps below FINISH_DX of the target scale, so P is within about that
         * of the least-squares optimum): finish with minimum-norm steps onto c = 0, which converge
         * quadratically where the linear rate of Gauss-Newton would need many more iterations */
        if (!use_lapack && dx < FINISH_DX && finish_tries < 2) {
            ++finish_tries;
            if (project(s, p, w, iters) == 0)
                return 0;
        }
    }
    return residual(s, p, w, NULL) <= RESIDUAL_OK ? 0 : -1;
}

int sk__vsys_solve(sk__vsys *s)
{
    int n = s->n_edges;
    double scale = 0.0;
    for (int j = 0; j < n; ++j)
        scale += hypot(s->pstar[2 * j], s->pstar[2 * j + 1]);
    scale = scale > 0.0 ? scale / n : 1.0;
    /* work in units of the mean target length */
    sk__vsys t = *s;
    for (int j = 0; j < 2 * n; ++j)
        t.pstar[j] = s->pstar[j] / scale;
    s->iterations = 0;
    s->newton_tries = 0;
    s->used_fallback = 0;
    int nc = cons_count(s);
    double p[2 * SK_VSYS_MAX], w[SK_VSYS_MAX] = {0};
    memcpy(p, t.pstar, sizeof(double) * (size_t)(2 * n));
    int ok = 0;
    if (nc > 0) {
        initial_w(&t, p, w);
        ok = iterate(&t, p, w, 0, &s->iterations, &s->newton_tries);
        if (ok != 0) {
            /* feasibility restoration: minimum-norm Gauss-Newton on c(p, w) = 0 alone from the last
             * iterate (targets moved onto the iterate each step); converges quadratically */
            sk__vsys f = t;
            double mu[MAX_C];
            for (int it = 0; it < 60 && ok != 0; ++it) {
                memcpy(f.pstar, p, sizeof(double) * (size_t)(2 * n));
                step_schur(&f, p, w, mu);
                ++s->iterations;
                double r2 = residual(&t, p, w, NULL);
                if (!isfinite(r2))
                    break;
                if (r2 <= 1e-15)
                    ok = 0;
            }
        }
        if (ok != 0) {
            s->used_fallback = 1;
            memcpy(p, t.pstar, sizeof(double) * (size_t)(2 * n));
            initial_w(&t, p, w);
            ok = iterate(&t, p, w, 1, &s->iterations, &s->newton_tries);
        }
    } else {
        for (int m = 0; m < n; ++m)
            w[m] = 0.0;
    }
    s->residual = residual(&t, p, w, NULL);
    for (int j = 0; j < 2 * n; ++j)
        s->p[j] = p[j] * scale;
    for (int m = 0; m < n; ++m)
        s->w[m] = w[m]; /* w is scale-free: (8) is homogeneous in p */
    return ok;
}

/* Lanes: the Gauss-Newton / SQP iterations of SK_VSYS_LANES closed systems of one size run in
 * lockstep. One step of one system is a chain of dependent divisions and square roots (the dense
 * Cholesky factor of S and the two substitutions), so a single solve waits on their latency;
 * interleaved, the lanes fill those waits (and pair up in SIMD registers). Every lane performs
 * exactly the operations of schur_kernel, in the same order, on its own data, so each system's
 * iterates, and its result, are those of sk__vsys_solve to the bit. A lane covers the Gauss-Newton
 * steps and the finishing projections of iterate(); a system that would go on to a Newton step
 * (GN_FIRST iterations), or whose iterate turns non-finite, is solved again from the start by
 * sk__vsys_solve (deterministic, so the result is the same as without lanes). */
#define LANE_N_MAX 7

/* One value per lane: GCC / Clang vector arithmetic is element-wise IEEE, the same rounding as
 * the scalar operations (packed SSE2 instructions on x86-64) */
typedef double lanes_t __attribute__((vector_size(SK_VSYS_LANES * sizeof(double))));

/* chol_skip's zeros below a dropped pivot j, in the lanes that dropped it */
static __attribute__((noinline)) void lanes_zero_column(lanes_t S[][2 * LANE_N_MAX], int j, int ns,
                                                      const unsigned char *drop)
{
    for (int l = 0; l < SK_VSYS_LANES; ++l)
        if (drop[l])
            for (int i = j + 1; i < ns; ++i)
                S[i][j][l] = 0.0;
}

/* chol_solve's zero for a dropped pivot, in the lanes that dropped it */
static __attribute__((noinline)) void lanes_zero_entry(lanes_t *x, const unsigned char *drop)
{
    for (int l = 0; l < SK_VSYS_LANES; ++l)
        if (drop[l])
            (*x)[l] = 0.0;
}

static inline __attribute__((always_inline)) void schur_lanes(const double *const *du_in,
                                                              const double *const *dd_in,
                                                              const double *const *nu_in,
                                                              const double *const *pstar,
                                                              double *const *pp, double *const *ww,
                                                              double *dx, const int n)
{
    enum { L = SK_VSYS_LANES };
    const int ns = 2 * n;
    lanes_t du[LANE_N_MAX], nd[LANE_N_MAX], p[2 * LANE_N_MAX], w[LANE_N_MAX];
    lanes_t c[2 * LANE_N_MAX], r[2 * LANE_N_MAX], J[LANE_N_MAX][LANE_N_MAX];
    lanes_t S[2 * LANE_N_MAX][2 * LANE_N_MAX], rhs[2 * LANE_N_MAX], dp[2 * LANE_N_MAX];
    lanes_t ca[LANE_N_MAX], cm[LANE_N_MAX], cb[LANE_N_MAX], dmax, tol;
    unsigned char drop[2 * LANE_N_MAX][L], any_drop[2 * LANE_N_MAX]; /* the pivot was dropped */
    const lanes_t zero = {0.0};
    for (int m = 0; m < n; ++m)
        for (int l = 0; l < L; ++l) {
            du[m][l] = du_in[l][m];
            nd[m][l] = nu_in[l][m] * dd_in[l][m];
            w[m][l] = ww[l][m];
        }
    for (int j = 0; j < ns; ++j)
        for (int l = 0; l < L; ++l) {
            p[j][l] = pp[l][j];
            r[j][l] = pstar[l][j] - pp[l][j];
        }
    /* residual() and rows() of a closed system: constraint i = edge m = i */
    for (int m = 0; m < n; ++m) {
        int a = (m - 1 + n) % n, b = (m + 1) % n;
        for (int k = 0; k < 2; ++k)
            c[2 * m + k] = du[m] * p[2 * b + k] - nd[m] * p[2 * a + k] - w[m] * p[2 * m + k];
        ca[m] = -nd[m];
        cm[m] = -w[m];
        cb[m] = du[m];
        for (int j = 0; j < n; ++j)
            J[m][j] = zero;
        J[m][a] += ca[m];
        J[m][m] += cm[m];
        J[m][b] += cb[m];
    }
    /* S = Jp Jp^T + (1/eps) Jw Jw^T (lower triangle: all chol_skip reads), rhs = Jp r + c */
    for (int i = 0; i < n; ++i) {
        int a = (i - 1 + n) % n, b = (i + 1) % n;
        for (int k = 0; k <= i; ++k) {
            lanes_t v = zero;
            for (int j = 0; j < n; ++j)
                v += J[i][j] * J[k][j];
            S[2 * i][2 * k] = v;
            S[2 * i + 1][2 * k + 1] = v;
            S[2 * i + 1][2 * k] = zero;
            S[2 * i][2 * k + 1] = zero; /* k = i: the upper triangle, unused */
        }
        lanes_t px = p[2 * i], py = p[2 * i + 1];
        S[2 * i][2 * i] += px * px / EPS_W;
        S[2 * i + 1][2 * i] += py * px / EPS_W;
        S[2 * i + 1][2 * i + 1] += py * py / EPS_W;
        for (int k = 0; k < 2; ++k)
            rhs[2 * i + k] = ca[i] * r[2 * a + k] + cm[i] * r[2 * i + k] + cb[i] * r[2 * b + k] +
                             c[2 * i + k];
    }
    /* chol_skip */
    dmax = zero;
    for (int i = 0; i < ns; ++i)
        for (int l = 0; l < L; ++l)
            dmax[l] = dmax[l] > S[i][i][l] ? dmax[l] : S[i][i][l];
    tol = 1e-13 * dmax;
    for (int j = 0; j < ns; ++j) {
        lanes_t d = S[j][j];
        for (int k = 0; k < j; ++k)
            d -= S[j][k] * S[j][k];
        any_drop[j] = 0;
        for (int l = 0; l < L; ++l) {
            drop[j][l] = d[l] <= tol[l];
            any_drop[j] |= drop[j][l];
            d[l] = drop[j][l] ? 0.0 : sqrt(d[l]);
        }
        S[j][j] = d;
        for (int i = j + 1; i < ns; ++i) {
            lanes_t v = S[i][j];
            for (int k = 0; k < j; ++k)
                v -= S[i][k] * S[j][k];
            S[i][j] = v / d;
        }
        if (any_drop[j]) /* mostly the last column, where there is nothing below */
            lanes_zero_column(S, j, ns, drop[j]);
    }
    /* chol_solve */
    for (int i = 0; i < ns; ++i) {
        lanes_t v = rhs[i];
        for (int k = 0; k < i; ++k)
            v -= S[i][k] * rhs[k];
        rhs[i] = v / S[i][i];
        if (any_drop[i])
            lanes_zero_entry(&rhs[i], drop[i]);
    }
    for (int i = ns - 1; i >= 0; --i) {
        lanes_t v = rhs[i];
        for (int k = i + 1; k < ns; ++k)
            v -= S[k][i] * rhs[k];
        rhs[i] = v / S[i][i];
        if (any_drop[i])
            lanes_zero_entry(&rhs[i], drop[i]);
    }
    /* dp = r - Jp^T lambda, dw_m = (1/eps) p_m . lambda_m */
    double norm[L] = {0.0};
    for (int j = 0; j < ns; ++j)
        dp[j] = r[j];
    for (int i = 0; i < n; ++i) {
        int a = (i - 1 + n) % n, b = (i + 1) % n;
        for (int k = 0; k < 2; ++k) {
            lanes_t lam = rhs[2 * i + k];
            dp[2 * a + k] -= ca[i] * lam;
            dp[2 * i + k] -= cm[i] * lam;
            dp[2 * b + k] -= cb[i] * lam;
        }
        lanes_t dw = (p[2 * i] * rhs[2 * i] + p[2 * i + 1] * rhs[2 * i + 1]) / EPS_W;
        for (int l = 0; l < L; ++l) {
            ww[l][i] += dw[l];
            norm[l] = FMAX(norm[l], fabs(dw[l]));
        }
    }
    for (int j = 0; j < ns; ++j)
        for (int l = 0; l < L; ++l) {
            pp[l][j] += dp[j][l];
            norm[l] = FMAX(norm[l], fabs(dp[j][l]));
        }
    for (int l = 0; l < L; ++l)
        dx[l] = norm[l];
}

static void step_lanes(const double *const *du, const double *const *dd, const double *const *nu,
                       const double *const *pstar, double *const *p, double *const *w, double *dx,
                       int n)
{
    switch (n) {
    case 3: schur_lanes(du, dd, nu, pstar, p, w, dx, 3); break;
    case 5: schur_lanes(du, dd, nu, pstar, p, w, dx, 5); break;
    default: schur_lanes(du, dd, nu, pstar, p, w, dx, 7); break;
    }
}

static int lane_size(const sk__vsys *s)
{
    return s->closed && (s->n_edges == 3 || s->n_edges == 5 || s->n_edges == 7);
}

/* One lane's solve: the state of sk__vsys_solve / iterate() / project_n() between steps. */
typedef struct lane {
    sk__vsys *s; /* NULL: the lane is empty */
    sk__vsys t;  /* s in units of its mean target length */
    double scale;
    double p[2 * LANE_N_MAX], w[LANE_N_MAX], p0[2 * LANE_N_MAX], w0[LANE_N_MAX];
    double target[2 * LANE_N_MAX]; /* the step's targets: t.pstar, or the projection's p */
    int idx, it, finish_tries, proj_k, project, newton_next, iters;
} lane;

/* sk__vsys_solve's start: scale, first iterate, initial w */
static void lane_start(lane *ln, sk__vsys *s)
{
    int n = s->n_edges;
    double scale = 0.0;
    for (int j = 0; j < n; ++j)
        scale += hypot(s->pstar[2 * j], s->pstar[2 * j + 1]);
    scale = scale > 0.0 ? scale / n : 1.0;
    ln->s = s;
    ln->scale = scale;
    ln->t.n_edges = n;
    ln->t.closed = 1;
    ln->t.fixed_first = s->fixed_first;
    ln->t.fixed_last = s->fixed_last;
    memcpy(ln->t.du, s->du, sizeof(double) * (size_t)n);
    memcpy(ln->t.dd, s->dd, sizeof(double) * (size_t)n);
    memcpy(ln->t.nu, s->nu, sizeof(double) * (size_t)n);
    for (int j = 0; j < 2 * n; ++j)
        ln->t.pstar[j] = s->pstar[j] / scale;
    memcpy(ln->p, ln->t.pstar, sizeof(double) * (size_t)(2 * n));
    memcpy(ln->target, ln->t.pstar, sizeof(double) * (size_t)(2 * n));
    initial_w(&ln->t, ln->p, ln->w);
    ln->it = ln->finish_tries = ln->proj_k = ln->project = ln->newton_next = ln->iters = 0;
}

/* sk__vsys_solve's end after a converged iterate */
static void lane_finish(lane *ln)
{
    sk__vsys *s = ln->s;
    int n = s->n_edges;
    s->iterations = ln->iters;
    s->newton_tries = 0;
    s->used_fallback = 0;
    s->residual = residual(&ln->t, ln->p, ln->w, NULL);
    for (int j = 0; j < 2 * n; ++j)
        s->p[j] = ln->p[j] * ln->scale;
    for (int m = 0; m < n; ++m)
        s->w[m] = ln->w[m];
    ln->s = NULL;
}

/* After the projection failed (project_n returns -1): iterate() goes on with its next iteration */
static int lane_next_iteration(lane *ln)
{
    int n = ln->t.n_edges;
    memcpy(ln->p, ln->p0, sizeof(double) * (size_t)(2 * n));
    memcpy(ln->w, ln->w0, sizeof(double) * (size_t)n);
    ln->project = 0;
    if (ln->newton_next || ++ln->it >= MAX_ITER)
        return -1;
    memcpy(ln->target, ln->t.pstar, sizeof(double) * (size_t)(2 * n));
    return 1;
}

/* iterate()'s decisions after a step of size dx: 1 = step again, 0 = converged, -1 = leave the
 * lanes (solved again by sk__vsys_solve) */
static int lane_after_step(lane *ln, double dx)
{
    int n = ln->t.n_edges;
    ++ln->iters;
    double r2 = residual(&ln->t, ln->p, ln->w, NULL);
    if (ln->project) { /* project_n's loop */
        if (!isfinite(r2))
            return lane_next_iteration(ln);
        if (r2 <= 1e-15)
            return 0;
        if (++ln->proj_k >= 4)
            return lane_next_iteration(ln);
        memcpy(ln->target, ln->p, sizeof(double) * (size_t)(2 * n));
        return 1;
    }
    if (!isfinite(r2) || !isfinite(dx))
        return -1;
    if (r2 <= 1e-15 && dx < 1e-8)
        return 0;
    ln->newton_next = ln->it + 1 >= GN_FIRST; /* n <= NEWTON_MAX_EDGES, nc > 0, no rejects yet */
    if (dx < FINISH_DX && ln->finish_tries < 2) {
        ++ln->finish_tries;
        memcpy(ln->p0, ln->p, sizeof(double) * (size_t)(2 * n));
        memcpy(ln->w0, ln->w, sizeof(double) * (size_t)n);
        memcpy(ln->target, ln->p, sizeof(double) * (size_t)(2 * n));
        ln->project = 1;
        ln->proj_k = 0;
        return 1;
    }
    if (ln->newton_next || ++ln->it >= MAX_ITER)
        return -1;
    return 1;
}

void sk__vsys_solve_lanes(sk__vsys *const *sys, int count, int *ret)
{
    lane ln[SK_VSYS_LANES];
    for (int n = 3; n <= LANE_N_MAX; n += 2) {
        int next = 0, active = 0;
        for (int l = 0; l < SK_VSYS_LANES; ++l)
            ln[l].s = NULL;
        for (;;) {
            for (int l = 0; l < SK_VSYS_LANES; ++l) { /* fill the empty lanes */
                while (!ln[l].s && next < count) {
                    int i = next++;
                    if (lane_size(sys[i]) && sys[i]->n_edges == n) {
                        lane_start(&ln[l], sys[i]);
                        ln[l].idx = i;
                        ++active;
                    }
                }
            }
            if (!active)
                break;
            const double *du[SK_VSYS_LANES], *dd[SK_VSYS_LANES], *nu[SK_VSYS_LANES];
            const double *tg[SK_VSYS_LANES];
            double *p[SK_VSYS_LANES], *w[SK_VSYS_LANES], dx[SK_VSYS_LANES];
            double spare_p[SK_VSYS_LANES][2 * LANE_N_MAX], spare_w[SK_VSYS_LANES][LANE_N_MAX];
            int first = 0;
            while (!ln[first].s)
                ++first;
            for (int l = 0; l < SK_VSYS_LANES; ++l) {
                const lane *src = ln[l].s ? &ln[l] : &ln[first]; /* empty: a copy, discarded */
                du[l] = src->t.du;
                dd[l] = src->t.dd;
                nu[l] = src->t.nu;
                tg[l] = src->target;
                if (ln[l].s) {
                    p[l] = ln[l].p;
                    w[l] = ln[l].w;
                } else {
                    memcpy(spare_p[l], src->p, sizeof spare_p[l]);
                    memcpy(spare_w[l], src->w, sizeof spare_w[l]);
                    p[l] = spare_p[l];
                    w[l] = spare_w[l];
                }
            }
            step_lanes(du, dd, nu, tg, p, w, dx, n);
            for (int l = 0; l < SK_VSYS_LANES; ++l) {
                if (!ln[l].s)
                    continue;
                int k = lane_after_step(&ln[l], dx[l]);
                if (k == 1)
                    continue;
                sk__vsys *s = ln[l].s;
                if (k == 0)
                    lane_finish(&ln[l]);
                ln[l].s = NULL;
                --active;
                ret[ln[l].idx] = k == 0 ? 0 : sk__vsys_solve(s);
            }
        }
    }
    for (int i = 0; i < count; ++i)
        if (!lane_size(sys[i]))
            ret[i] = sk__vsys_solve(sys[i]);
}

void sk__vsys_angles(const sk__vsys *s, double *min_angle, double *max_angle)
{
    int n = s->n_edges, pairs = s->closed ? n : n - 1;
    double lo = 4.0 * M_PI, hi = -1.0;
    for (int k = 0; k < pairs; ++k) {
        const double *a = s->p + 2 * k, *b = s->p + 2 * ((k + 1) % n);
        double ang = atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]);
        if (ang < 0.0)
            ang += 2.0 * M_PI;
        lo = fmin(lo, ang);
        hi = fmax(hi, ang);
    }
    *min_angle = lo;
    *max_angle = hi;
}

/* The memo: a ring of the last MEMO_SLOTS solves (a vertex's variants, tried one after the
 * other, are what repeats). in: pstar (2 n), du, dd, nu (n each), compared bit for bit. */
#define MEMO_SLOTS 16

typedef struct memo_entry {
    int n, closed, fixed_first, fixed_last, ret, iterations, newton_tries, used_fallback;
    double in[5 * SK_VSYS_MAX];
    double p[2 * SK_VSYS_MAX], w[SK_VSYS_MAX], residual;
} memo_entry;

struct sk__vsys_memo {
    memo_entry e[MEMO_SLOTS];
    unsigned used, next;
};

sk__vsys_memo *sk__vsys_memo_create(void)
{
    return sk__calloc_array(1, sizeof(sk__vsys_memo));
}

void sk__vsys_memo_destroy(sk__vsys_memo *memo)
{
    sk__free(memo);
}

static void memo_key(const sk__vsys *s, double *in)
{
    size_t n = (size_t)s->n_edges;
    memcpy(in, s->pstar, 2 * n * sizeof(double));
    memcpy(in + 2 * n, s->du, n * sizeof(double));
    memcpy(in + 3 * n, s->dd, n * sizeof(double));
    memcpy(in + 4 * n, s->nu, n * sizeof(double));
}

int sk__vsys_solve_memo(sk__vsys *s, sk__vsys_memo *memo)
{
    if (!memo || s->n_edges <= 0 || s->n_edges > SK_VSYS_MAX)
        return sk__vsys_solve(s);
    size_t n = (size_t)s->n_edges;
    double in[5 * SK_VSYS_MAX];
    memo_key(s, in);
    for (unsigned i = 0; i < memo->used; ++i) {
        const memo_entry *e = &memo->e[i];
        if (e->n != s->n_edges || e->closed != s->closed || e->fixed_first != s->fixed_first ||
            e->fixed_last != s->fixed_last || memcmp(e->in, in, 5 * n * sizeof(double)) != 0)
            continue;
        memcpy(s->p, e->p, 2 * n * sizeof(double));
        memcpy(s->w, e->w, n * sizeof(double));
        s->residual = e->residual;
        s->iterations = e->iterations;
        s->newton_tries = e->newton_tries;
        s->used_fallback = e->used_fallback;
        return e->ret;
    }
    int ret = sk__vsys_solve(s);
    memo_entry *e = &memo->e[memo->next];
    memo->next = (memo->next + 1) % MEMO_SLOTS;
    memo->used += memo->used < MEMO_SLOTS;
    e->n = s->n_edges;
    e->closed = s->closed;
    e->fixed_first = s->fixed_first;
    e->fixed_last = s->fixed_last;
    memcpy(e->in, in, 5 * n * sizeof(double));
    memcpy(e->p, s->p, 2 * n * sizeof(double));
    memcpy(e->w, s->w, n * sizeof(double));
    e->residual = s->residual;
    e->iterations = s->iterations;
    e->newton_tries = s->newton_tries;
    e->used_fallback = s->used_fallback;
    e->ret = ret;
    return ret;
}

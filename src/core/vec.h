/* Small vector math on double[3] and double[2] (internal, header-only). */
#ifndef SK_CORE_VEC_H
#define SK_CORE_VEC_H

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static inline void sk__sub3(double r[3], const double a[3], const double b[3])
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

static inline void sk__add3(double r[3], const double a[3], const double b[3])
{
    r[0] = a[0] + b[0];
    r[1] = a[1] + b[1];
    r[2] = a[2] + b[2];
}

static inline void sk__scale3(double r[3], const double a[3], double s)
{
    r[0] = a[0] * s;
    r[1] = a[1] * s;
    r[2] = a[2] * s;
}

/* r = a + s * b */
static inline void sk__axpy3(double r[3], const double a[3], double s, const double b[3])
{
    r[0] = a[0] + s * b[0];
    r[1] = a[1] + s * b[1];
    r[2] = a[2] + s * b[2];
}

static inline double sk__dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void sk__cross3(double r[3], const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    r[0] = x;
    r[1] = y;
    r[2] = z;
}

static inline double sk__norm3(const double a[3])
{
    return sqrt(sk__dot3(a, a));
}

static inline double sk__dist3(const double a[3], const double b[3])
{
    double d[3];
    sk__sub3(d, a, b);
    return sk__norm3(d);
}

/* Normalises a in place; returns the old length (0 leaves a unchanged). */
static inline double sk__normalize3(double a[3])
{
    double n = sk__norm3(a);
    if (n > 0.0) {
        a[0] /= n;
        a[1] /= n;
        a[2] /= n;
    }
    return n;
}

/* A tangent basis of the unit normal n: e1, e2 orthonormal with e1 x e2 = n (e1 from the axis
 * farthest from n). */
static inline void sk__tangent_basis(const double n[3], double e1[3], double e2[3])
{
    double a[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.6)
        a[0] = 0, a[1] = 1;
    sk__cross3(e1, a, n);
    sk__normalize3(e1);
    sk__cross3(e2, n, e1);
}

/* Angle between a and b in [0, pi], robust near 0 and pi (atan2 of |a x b| and a.b). */
static inline double sk__angle3(const double a[3], const double b[3])
{
    double c[3];
    sk__cross3(c, a, b);
    return atan2(sk__norm3(c), sk__dot3(a, b));
}

static inline double sk__cross2(const double a[2], const double b[2])
{
    return a[0] * b[1] - a[1] * b[0];
}

static inline double sk__dot2(const double a[2], const double b[2])
{
    return a[0] * b[0] + a[1] * b[1];
}

#endif

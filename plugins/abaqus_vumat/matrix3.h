/*
 * matrix3.h — 3x3 matrix helpers of the VUMAT adapter, inline: they are called a few dozen
 * times per material point. Matrices are row-indexed C arrays, m[i][j] = entry (i, j).
 */
#ifndef MUSCLEFEM_VUMAT_MATRIX3_H
#define MUSCLEFEM_VUMAT_MATRIX3_H

/* F (row-indexed) from the host's column-major 9 values. */
static inline void mat_from_column_major(const double* f, double m[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[i][j] = f[i + 3 * j];
}

/* out = a b (out may not alias a or b). */
static inline void mat_mul(const double a[3][3], const double b[3][3], double out[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
}

/* out = a^T b. */
static inline void mat_mul_tn(const double a[3][3], const double b[3][3], double out[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[i][j] = a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
}

/* out = a b^T. */
static inline void mat_mul_nt(const double a[3][3], const double b[3][3], double out[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[i][j] = a[i][0] * b[j][0] + a[i][1] * b[j][1] + a[i][2] * b[j][2];
}

static inline double mat_det(const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* out = a^-1; returns det a (out untouched when it is 0). */
static inline double mat_inverse(const double a[3][3], double out[3][3]) {
    double det = mat_det(a);
    if (det == 0.0) return 0.0;
    double s = 1.0 / det;
    out[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) * s;
    out[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * s;
    out[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * s;
    out[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) * s;
    out[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * s;
    out[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * s;
    out[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) * s;
    out[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * s;
    out[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * s;
    return det;
}

/* out = q^T a q (a tensor's components in the basis of q's columns). */
static inline void to_basis(const double q[3][3], const double a[3][3], double out[3][3]) {
    double aq[3][3];
    mat_mul(a, q, aq);
    mat_mul_tn(q, aq, out);
}

/* out = q a q^T (back to the global basis). */
static inline void from_basis(const double q[3][3], const double a[3][3], double out[3][3]) {
    double qa[3][3];
    mat_mul(q, a, qa);
    mat_mul_nt(qa, q, out);
}

#endif /* MUSCLEFEM_VUMAT_MATRIX3_H */

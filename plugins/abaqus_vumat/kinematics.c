/*
 * kinematics.c — the tensors the adapters hand to Abaqus/Explicit's VUMAT (polar
 * decomposition, material basis, strain and spin increments, component orders) and to
 * Abaqus/Standard's UMAT (strain increment, rotation increment, component order). See
 * musclefem_vumat.h and musclefem_umat.h for each function's contract and docs/vumat.md for
 * the choices.
 */
#include <math.h>
#include <string.h>

#include "matrix3.h"
#include "musclefem_umat.h"
#include "musclefem_vumat.h"

static double frobenius_squared(const double a[3][3]) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) s += a[i][j] * a[i][j];
    return s;
}

/*
 * The orthogonal factor of X (det X > 0), in place. While X is far from orthogonal
 * (|I - X^T X|_max > 1/4): Newton's iteration X <- (g X + X^-T / g)/2 with Higham's scaling
 * g = sqrt(|X^-1|_F / |X|_F). Then the Newton-Schulz iteration X <- X (I + E/2),
 * E = I - X^T X, which needs no inverse and converges quadratically to the same factor
 * (E becomes 3/4 E^2 + 1/4 E^3); it ends with the step at which |E|_max < 1e-8, after which
 * |E| ~ 1e-16, round-off. Returns 0, or 1 if X is singular, inverted or not finite.
 */
static int orthogonal_factor(double x[3][3]) {
    for (int iteration = 0; iteration < 100; ++iteration) {
        double xtx[3][3], e[3][3], largest = 0.0;
        mat_mul_tn(x, x, xtx);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                e[i][j] = (i == j ? 1.0 : 0.0) - xtx[i][j];
                double size = fabs(e[i][j]);
                if (size > largest || size != size) largest = size;
            }
        if (!isfinite(largest)) return 1;
        if (largest > 0.25) {
            double inverse[3][3];
            double det = mat_inverse(x, inverse);
            if (!(det > 0.0)) return 1;
            double g = sqrt(sqrt(frobenius_squared(inverse) / frobenius_squared(x)));
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) x[i][j] = 0.5 * (g * x[i][j] + inverse[j][i] / g);
            continue;
        }
        double xe[3][3];
        mat_mul(x, e, xe);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) x[i][j] += 0.5 * xe[i][j];
        if (largest < 1e-8) return 0;
    }
    return 1;
}

/* R = the orthogonal factor of F, U = sym(R^T F). */
int polar_decomposition(const double f[3][3], double r[3][3], double u[3][3]) {
    memcpy(r, f, 9 * sizeof(double));
    if (orthogonal_factor(r) != 0) return 1;
    double rt_f[3][3];
    mat_mul_tn(r, f, rt_f);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) u[i][j] = 0.5 * (rt_f[i][j] + rt_f[j][i]);
    return 0;
}

/* b completes a: the global axis least aligned with a (the first on ties), made
 * orthogonal to a and normalised. For a along a global axis, (a, b, c) are global axes. */
void material_basis(const double fiber[3], int convention, double q[3][3]) {
    memset(q, 0, 9 * sizeof(double));
    q[0][0] = q[1][1] = q[2][2] = 1.0;
    if (convention != VUMAT_FIBER_ORIENTATION) return;
    double norm = sqrt(fiber[0] * fiber[0] + fiber[1] * fiber[1] + fiber[2] * fiber[2]);
    double a[3] = {fiber[0] / norm, fiber[1] / norm, fiber[2] / norm};
    int axis = 0;
    for (int i = 1; i < 3; ++i)
        if (fabs(a[i]) < fabs(a[axis])) axis = i;
    double b[3] = {-a[axis] * a[0], -a[axis] * a[1], -a[axis] * a[2]};
    b[axis] += 1.0;
    double b_norm = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    for (int i = 0; i < 3; ++i) b[i] /= b_norm;
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    for (int i = 0; i < 3; ++i) {
        q[i][0] = a[i];
        q[i][1] = b[i];
        q[i][2] = c[i];
    }
}

/* The midpoint rule of a central-difference code: dL = (F_new - F_old) F_mid^-1. The frame
 * spin uses the same rule on R, (R_new - R_old) Rbar^-1 with Rbar = (R_old + R_new)/2, so
 * that a rigid rotation (F = R) has no strain increment (the Cayley transform of an
 * orthogonal matrix is skew) and no relative spin, to round-off. The mid-increment frame
 * R_mid is the orthogonal factor of Rbar (one or two Newton-Schulz steps, Rbar being
 * orthogonal to O(dt^2)); it is that of F_mid for a rigid rotation and within O(dt^2) of it
 * otherwise, the order of the midpoint rule. */
int increment_kinematics(const double f_old[3][3], const double f_new[3][3],
                         const double r_old[3][3], const double r_new[3][3],
                         double strain_inc[3][3], double spin_inc[3], double* j_mid) {
    double f_mid[3][3], df[3][3], r_bar[3][3], dr[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            f_mid[i][j] = 0.5 * (f_old[i][j] + f_new[i][j]);
            df[i][j] = f_new[i][j] - f_old[i][j];
            r_bar[i][j] = 0.5 * (r_old[i][j] + r_new[i][j]);
            dr[i][j] = r_new[i][j] - r_old[i][j];
        }
    double r_mid[3][3], f_mid_inverse[3][3], r_bar_inverse[3][3];
    *j_mid = mat_inverse(f_mid, f_mid_inverse);
    if (!(*j_mid > 0.0) || mat_inverse(r_bar, r_bar_inverse) == 0.0) return 1;
    memcpy(r_mid, r_bar, sizeof r_mid);
    if (orthogonal_factor(r_mid) != 0) return 1;
    double dl[3][3], frame_spin[3][3], sym[3][3], relative[3][3];
    mat_mul(df, f_mid_inverse, dl);
    mat_mul(dr, r_bar_inverse, frame_spin);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            sym[i][j] = 0.5 * (dl[i][j] + dl[j][i]);
            relative[i][j] = 0.5 * (dl[i][j] - dl[j][i]) - 0.5 * (frame_spin[i][j] - frame_spin[j][i]);
        }
    double rotated[3][3];
    to_basis(r_mid, sym, strain_inc);
    to_basis(r_mid, relative, rotated);
    spin_inc[0] = rotated[2][1];
    spin_inc[1] = rotated[0][2];
    spin_inc[2] = rotated[1][0];
    return 0;
}

void put_abaqus_symmetric(const double s[3][3], double* out, size_t stride) {
    out[0] = s[0][0];
    out[stride] = s[1][1];
    out[2 * stride] = s[2][2];
    out[3 * stride] = s[0][1];
    out[4 * stride] = s[1][2];
    out[5 * stride] = s[2][0];
}

void get_abaqus_symmetric(const double* in, size_t stride, double s[3][3]) {
    s[0][0] = in[0];
    s[1][1] = in[stride];
    s[2][2] = in[2 * stride];
    s[0][1] = s[1][0] = in[3 * stride];
    s[1][2] = s[2][1] = in[4 * stride];
    s[2][0] = s[0][2] = in[5 * stride];
}

void put_abaqus_full(const double a[3][3], double* out, size_t stride) {
    static const int row[9] = {0, 1, 2, 0, 1, 2, 1, 2, 0};
    static const int column[9] = {0, 1, 2, 1, 2, 0, 0, 1, 2};
    for (int c = 0; c < 9; ++c) out[c * stride] = a[row[c]][column[c]];
}

void put_host_voigt(const double s[3][3], double* out) {
    out[0] = s[0][0];
    out[1] = s[1][1];
    out[2] = s[2][2];
    out[3] = s[1][2];
    out[4] = s[0][2];
    out[5] = s[0][1];
}

/* --- Abaqus/Standard (UMAT) ------------------------------------------------------------ */

int umat_increment_kinematics(const double f_old[3][3], const double f_new[3][3],
                              double dstran[6], double drot[3][3]) {
    double f_mid[3][3], df[3][3], f_mid_inverse[3][3], dl[3][3], sym[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            f_mid[i][j] = 0.5 * (f_old[i][j] + f_new[i][j]);
            df[i][j] = f_new[i][j] - f_old[i][j];
        }
    if (!(mat_inverse(f_mid, f_mid_inverse) > 0.0)) return 1;
    mat_mul(df, f_mid_inverse, dl);
    double minus[3][3], plus[3][3], minus_inverse[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double w = 0.5 * (dl[i][j] - dl[j][i]);
            sym[i][j] = 0.5 * (dl[i][j] + dl[j][i]);
            minus[i][j] = (i == j ? 1.0 : 0.0) - 0.5 * w;
            plus[i][j] = (i == j ? 1.0 : 0.0) + 0.5 * w;
        }
    /* det(I - W/2) = 1 + |w|^2/4 > 0 for skew W. */
    if (mat_inverse(minus, minus_inverse) == 0.0) return 1;
    mat_mul(minus_inverse, plus, drot);
    put_umat_symmetric(sym, 1, dstran);
    return 0;
}

void put_umat_symmetric(const double s[3][3], int engineering, double out[6]) {
    const double shear = engineering ? 2.0 : 1.0;
    out[0] = s[0][0];
    out[1] = s[1][1];
    out[2] = s[2][2];
    out[3] = shear * s[0][1];
    out[4] = shear * s[0][2];
    out[5] = shear * s[1][2];
}

void get_umat_symmetric(const double in[6], int engineering, double s[3][3]) {
    const double shear = engineering ? 0.5 : 1.0;
    s[0][0] = in[0];
    s[1][1] = in[1];
    s[2][2] = in[2];
    s[0][1] = s[1][0] = shear * in[3];
    s[0][2] = s[2][0] = shear * in[4];
    s[1][2] = s[2][1] = shear * in[5];
}

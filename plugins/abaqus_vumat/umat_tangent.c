/*
 * umat_tangent.c — an Abaqus/Standard UMAT's DDSDDE as the tangent the host asks for, the
 * first elasticity tensor A = dP/dF (P = J sigma F^-T, musclefem_material.h).
 *
 * Abaqus/Standard's finite-strain UMAT (NLGEOM) defines DDSDDE through the Jaumann rate of
 * the Kirchhoff stress tau = J sigma, divided by J (TFEL/MFront's `ABAQUS` tangent
 * operator, "the moduli associated with the Jaumann rate of the Kirchhoff stress divided by
 * J"; the compressible neo-Hookean UMAT of Abaqus's own examples has exactly this DDSDDE;
 * docs/vumat.md, "The tangent"):
 *
 *     tau^J = tau' - W tau + tau W = J C : D,   D = sym(L), W = skew(L),
 *
 * with C_ijkl = DDSDDE(I, K), I = (ij), K = (kl) in the order 11, 22, 33, 12, 13, 23 (the
 * engineering shear 2 D_kl of the strain increment counts C_ijkl and C_ijlk together, so C
 * has the minor symmetry in kl by construction). The Oldroyd rate of tau,
 * tau^O = tau' - L tau - tau L^T = c : D (c the spatial moduli of the Kirchhoff stress),
 * is tau^O = tau^J - D tau - tau D, hence
 *
 *     c_ijkl = J C_ijkl - (delta_ik tau_jl + delta_il tau_jk + tau_ik delta_jl
 *                          + tau_il delta_jk) / 2
 *
 * (TFEL's convertSpatialModuliToKirchhoffJaumanRateModuli is the inverse of this). For a
 * variation dF = l F of the deformation gradient, dtau = c : sym(l) + l tau + tau l^T and
 * d(F^-T) = -F^-T dF^T F^-T, so dP F^T = dtau - tau l^T = c : sym(l) + l tau:
 *
 *     a_ijkl = A_iJkL F_jJ F_lL = c_ijkl + delta_ik tau_jl,
 *     A_iJkL = a_ijkl F^-1_Jj F^-1_Ll.
 *
 * This is exact for a UMAT whose stress is a function of DFGRD1 (hyperelastic) and
 * DDSDDE its exact Jacobian; for rate-form UMATs it is the tangent Abaqus/Standard itself
 * assembles from DDSDDE.
 */
#include "matrix3.h"
#include "musclefem_umat.h"

/* The UMAT-order index of the symmetric pair (i, j). */
static int voigt(int i, int j) {
    static const int index[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    return index[i][j];
}

void umat_first_elasticity(const double ddsdde[36], const double sigma[3][3],
                           const double f[3][3], double* tangent) {
    double f_inverse[3][3];
    const double j = mat_inverse(f, f_inverse);
    double tau[3][3];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) tau[i][k] = j * sigma[i][k];
    /* a_ijkl, then A_iJkL = a_ijkl F^-1_Jj F^-1_Ll. */
    double a[3][3][3][3];
    for (int i = 0; i < 3; ++i)
        for (int jj = 0; jj < 3; ++jj)
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l) {
                    const double d_ik = i == k, d_il = i == l, d_jk = jj == k, d_jl = jj == l;
                    const double c = j * ddsdde[voigt(i, jj) + 6 * voigt(k, l)] -
                                     0.5 * (d_ik * tau[jj][l] + d_il * tau[jj][k] +
                                            tau[i][k] * d_jl + tau[i][l] * d_jk);
                    a[i][jj][k][l] = c + d_ik * tau[jj][l];
                }
    for (int i = 0; i < 3; ++i)
        for (int big_j = 0; big_j < 3; ++big_j)
            for (int k = 0; k < 3; ++k)
                for (int big_l = 0; big_l < 3; ++big_l) {
                    double sum = 0.0;
                    for (int jj = 0; jj < 3; ++jj)
                        for (int l = 0; l < 3; ++l)
                            sum += a[i][jj][k][l] * f_inverse[big_j][jj] * f_inverse[big_l][l];
                    tangent[(i + 3 * big_j) + 9 * (k + 3 * big_l)] = sum;
                }
}

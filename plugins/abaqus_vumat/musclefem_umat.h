/*
 * musclefem_umat.h — internals of the Abaqus/Standard UMAT adapter (umat_adapter.c,
 * umat_tangent.c), built by `musclefem umat build` with the shared files of this folder
 * (kinematics.c, abaqus_utilities.c, matrix3.h). docs/vumat.md, "UMAT", describes every
 * argument and the tangent.
 *
 * Matrices are row-indexed C arrays, m[i][j] = entry (i, j); Abaqus/Standard's symmetric
 * tensors are in the order 11, 22, 33, 12, 13, 23 (not the VUMAT's 12, 23, 31), shears
 * of strains as engineering shears (2 e_12).
 */
#ifndef MUSCLEFEM_UMAT_H
#define MUSCLEFEM_UMAT_H

#include <stddef.h>

/* State variables the adapter keeps before the user's nstatev: the Cauchy stress STRESS
 * [Pa] and the strain STRAN (both in UMAT order), SSE, SPD, SCD [J/m^3 as the UMAT keeps
 * them], and the number of increments accepted (KINC - 1 of the next one). */
#define UMAT_ADAPTER_STATES 16
#define UMAT_STATE_STRESS 0
#define UMAT_STATE_STRAN 6
#define UMAT_STATE_SSE 12
#define UMAT_STATE_SPD 13
#define UMAT_STATE_SCD 14
#define UMAT_STATE_INCREMENTS 15

/* Parameters the adapter declares after the user's props: umat_char_length (CELENT) and
 * umat_temperature (TEMP). */
#define UMAT_ADAPTER_PARAMETERS 2

/* The user's subroutine, as gfortran names and calls it: every argument by reference,
 * DDSDDE(NTENS, NTENS), DROT, DFGRD0, DFGRD1 (3, 3) column-major, the hidden length of
 * CHARACTER*80 CMNAME after the 38 declared arguments. */
void umat_(double* stress, double* statev, double* ddsdde, double* sse, double* spd,
           double* scd, double* rpl, double* ddsddt, double* drplde, double* drpldt,
           const double* stran, const double* dstran, const double* time, const double* dtime,
           const double* temp, const double* dtemp, const double* predef, const double* dpred,
           const char* cmname, const int* ndi, const int* nshr, const int* ntens,
           const int* nstatv, const double* props, const int* nprops, const double* coords,
           const double* drot, double* pnewdt, const double* celent, const double* dfgrd0,
           const double* dfgrd1, const int* noel, const int* npt, const int* layer,
           const int* kspt, const int* jstep, const int* kinc, size_t cmname_length);

/* Kinematics of one Abaqus/Standard increment from F_old to F_new (global basis), the
 * midpoint rule of Abaqus/Standard's finite-strain UMAT interface: with
 * F_mid = (F_old + F_new)/2 and dL = (F_new - F_old) F_mid^-1,
 *   dstran[6]  = sym(dL) in UMAT order, engineering shears (DSTRAN),
 *   drot[3][3] = (I - W/2)^-1 (I + W/2), W = skew(dL) (DROT, Hughes and Winget's rotation
 *                increment: exactly R_new R_old^T for a rigid rotation).
 * Returns 0, or 1 if F_mid is singular or inverted. kinematics.c. */
int umat_increment_kinematics(const double f_old[3][3], const double f_new[3][3],
                              double dstran[6], double drot[3][3]);

/* A symmetric tensor to and from UMAT order; `engineering` doubles the shears (strains). */
void put_umat_symmetric(const double s[3][3], int engineering, double out[6]);
void get_umat_symmetric(const double in[6], int engineering, double s[3][3]);

/* The first elasticity tensor dP/dF (the host's tangent: 81 values, entry
 * [(i+3J) + 9(k+3L)] = dP_iJ/dF_kL) of a UMAT's DDSDDE (6x6, column-major as Fortran
 * stores it: DDSDDE(I, J) at ddsdde[I + 6 J]), at the Cauchy stress sigma and the
 * deformation gradient F it belongs to. umat_tangent.c, where the formula is derived. */
void umat_first_elasticity(const double ddsdde[36], const double sigma[3][3],
                           const double f[3][3], double* tangent);

#endif /* MUSCLEFEM_UMAT_H */

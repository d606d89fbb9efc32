/*
 * musclefem_vumat.h — internals of the Abaqus/Explicit VUMAT adapter (plugins/abaqus_vumat).
 *
 * The adapter is a musclefem material plugin (musclefem_material.h) that hands each block
 * of material points to a user's Fortran `SUBROUTINE VUMAT` with Abaqus/Explicit's calling
 * convention. `musclefem vumat build` (crates/vumat) compiles the user's file with gfortran,
 * writes `vumat_config.h` (name, props, nstatev, fiber convention) and compiles and links
 * the files of this folder with it. docs/vumat.md describes every argument.
 *
 * Matrices here are row-indexed C arrays: m[i][j] is entry (i, j) (i, j = 0, 1, 2).
 */
#ifndef MUSCLEFEM_VUMAT_H
#define MUSCLEFEM_VUMAT_H

#include <setjmp.h>
#include <stddef.h>
#include <stdint.h>

/* The largest block handed to the VUMAT at once: Abaqus/Explicit's n_vec_Length (maxblk
 * of vaba_param.inc), which some VUMATs use to dimension local arrays. */
#define VUMAT_MAX_BLOCK 136

/* Where the VUMAT finds the fiber direction (docs/vumat.md, "Fiber direction"). */
#define VUMAT_FIBER_NONE 0        /* global basis; the fiber direction is not passed */
#define VUMAT_FIBER_ORIENTATION 1 /* every tensor in the material basis (a, b, c), a the
                                     reference fiber: the fiber is local direction 1, as
                                     with *ORIENTATION */
#define VUMAT_FIBER_STATE 2       /* global basis; the unit reference fiber in the first
                                     three user state variables at the first increment, as
                                     with *INITIAL CONDITIONS, TYPE=SOLUTION */

/* State variables the adapter keeps before the user's nstatev: the co-rotational stress
 * (Abaqus order 11, 22, 33, 12, 23, 31) [Pa], enerInternOld, enerInelasOld [J/kg], and a
 * flag that is 0 until the first increment with dt > 0 has been accepted. */
#define VUMAT_ADAPTER_STATES 9
#define VUMAT_STATE_ENER_INTERN 6
#define VUMAT_STATE_ENER_INELAS 7
#define VUMAT_STATE_STARTED 8

/* Parameters the adapter declares after the user's props. */
#define VUMAT_ADAPTER_PARAMETERS 3

/* The user's subroutine, as gfortran names and calls it: every argument by reference,
 * arrays (nblock, k) column-major, INTEGER = int, REAL*8 = double, and the hidden length of
 * CHARACTER*80 cmname after the 33 declared arguments. */
void vumat_(const int* nblock, const int* ndir, const int* nshr, const int* nstatev,
            const int* nfieldv, const int* nprops, const int* lanneal, const double* step_time,
            const double* total_time, const double* dt, const char* cmname,
            const double* coord_mp, const double* char_length, const double* props,
            const double* density, const double* strain_inc, const double* rel_spin_inc,
            const double* temp_old, const double* stretch_old, const double* defgrad_old,
            const double* field_old, const double* stress_old, const double* state_old,
            const double* ener_intern_old, const double* ener_inelas_old,
            const double* temp_new, const double* stretch_new, const double* defgrad_new,
            const double* field_new, double* stress_new, double* state_new,
            double* ener_intern_new, double* ener_inelas_new, size_t cmname_length);

/* Every argument of one VUMAT call (scalars by value, arrays by pointer). */
typedef struct {
    int nblock, nstatev, nprops;
    double step_time, total_time, dt;
    const char* cmname; /* 80 characters, blank padded, not NUL-terminated */
    const double *coord_mp, *char_length, *props, *density, *strain_inc, *rel_spin_inc;
    const double *temp_old, *stretch_old, *defgrad_old, *field_old, *stress_old, *state_old;
    const double *ener_intern_old, *ener_inelas_old;
    const double *temp_new, *stretch_new, *defgrad_new, *field_new;
    double *stress_new, *state_new, *ener_intern_new, *ener_inelas_new;
} VumatArguments;

/* One guarded call of a user subroutine (VUMAT or UMAT): where XPLB_ABQERR / STDB_ABQERR
 * (lop = -2, -3), XPLB_EXIT / XIT and STOP leave their message, and where lop = -3, the exits
 * and STOP jump back to. */
typedef struct {
    jmp_buf jump;
    const char* routine; /* "VUMAT" or "UMAT", for the messages */
    int failed; /* an error was reported (lop = -2 or -3), an exit routine or STOP was called */
    char message[512];
} AbaqusCall;

/* Runs body(arguments), which calls the user's subroutine, with `call` as the thread's
 * current call; returns 0, or 1 when the subroutine reported an error or stopped the
 * analysis (the message is then in call->message). abaqus_utilities.c. */
int abaqus_call_guarded(AbaqusCall* call, const char* routine, void (*body)(const void*),
                        const void* arguments);

/* --- kinematics.c (the 3x3 helpers are in matrix3.h) --------------------------------- */

/* The polar decomposition F = R U (R a rotation, U symmetric positive definite) of F with
 * det F > 0; returns 0, or 1 if the iteration did not converge. */
int polar_decomposition(const double f[3][3], double r[3][3], double u[3][3]);

/* The material basis of a reference fiber direction: its columns are a = fiber/|fiber|, b
 * and c = a x b (VUMAT_FIBER_ORIENTATION); the identity for the other conventions. */
void material_basis(const double fiber[3], int convention, double q[3][3]);

/* Kinematics of one increment from F_old = R_old U_old to F_new = R_new U_new (both in
 * the VUMAT's basis), with F_mid = (F_old + F_new)/2, dL = (F_new - F_old) F_mid^-1 the
 * velocity gradient times dt at mid-increment, Rbar = (R_old + R_new)/2 and R_mid its
 * orthogonal factor (the mid-increment co-rotational frame):
 *   strain_inc[3][3] = R_mid^T sym(dL) R_mid (co-rotational strain increment),
 *   spin_inc[3]      = the axial vector (A_32, A_13, A_21) of
 *                      A = R_mid^T (skew(dL) - skew((R_new - R_old) Rbar^-1)) R_mid, the
 *                      spin of the material relative to the co-rotational frame times dt,
 *   *j_mid           = det F_mid.
 * Returns 0, or 1 if a polar decomposition failed. */
int increment_kinematics(const double f_old[3][3], const double f_new[3][3],
                         const double r_old[3][3], const double r_new[3][3],
                         double strain_inc[3][3], double spin_inc[3], double* j_mid);

/* A symmetric tensor to and from Abaqus order (11, 22, 33, 12, 23, 31), element c of
 * point k at out[k + stride c]. */
void put_abaqus_symmetric(const double s[3][3], double* out, size_t stride);
void get_abaqus_symmetric(const double* in, size_t stride, double s[3][3]);
/* A general tensor in Abaqus order (11, 22, 33, 12, 23, 31, 21, 32, 13). */
void put_abaqus_full(const double a[3][3], double* out, size_t stride);
/* A symmetric tensor into the host's Voigt order (xx, yy, zz, yz, xz, xy). */
void put_host_voigt(const double s[3][3], double* out);

#endif /* MUSCLEFEM_VUMAT_H */

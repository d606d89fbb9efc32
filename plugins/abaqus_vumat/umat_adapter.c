/*
 * umat_adapter.c — the musclefem material plugin that runs an Abaqus/Standard UMAT.
 *
 * Per host block (musclefem_material.h), point by point (a UMAT takes one point per call),
 * in the global basis (VUMAT_FIBER_NONE or VUMAT_FIBER_STATE):
 *
 *   DFGRD0, DFGRD1 = F_old, F_new;
 *   DSTRAN, DROT   from umat_increment_kinematics (midpoint strain increment, Hughes and
 *                  Winget's rotation increment);
 *   STRESS         = DROT sigma_old DROT^T, sigma_old the Cauchy stress the adapter kept
 *                  from the last accepted increment (Abaqus rotates it before the call);
 *   STRAN          = DROT eps_old DROT^T, eps_old the kept total strain (the sum of the
 *                  rotated increments, as Abaqus keeps it);
 *   STATEV         = the user's state variables (the unit fiber direction in the first
 *                  three at the first increment under VUMAT_FIBER_STATE);
 *   SSE, SPD, SCD  = kept; TIME(1) = TIME(2) = time - dt (the start of the increment),
 *                  DTIME = dt; TEMP = umat_temperature, DTEMP = 0; CELENT = umat_char_length;
 *                  COORDS = 0; NOEL = 1 + the point's index in the block, NPT = LAYER = KSPT
 *                  = 1; JSTEP = (1, 1, 1, 0); KINC = 1 + the increments accepted; PNEWDT = 1;
 *   DDSDDE         filled with a NaN of a fixed bit pattern.
 *
 * After the call: STRESS (Cauchy, global) goes to the host in its Voigt order; the tangent,
 * when the host asks for it, is DDSDDE converted to dP/dF (umat_tangent.c) or, when the
 * UMAT left every entry of DDSDDE unset, central differences of P = J sigma F^-T over F_new
 * (h = 1e-6, 18 more calls of the UMAT, the host's own rule). A DDSDDE set only in part is
 * an error, as are non-finite outputs and PNEWDT < 1 (musclefem cannot shorten the
 * increment on a material's request; the implicit solver's step cutting may retry it).
 *
 * dt = 0 is not a step: the state is returned unchanged. With F_new = F_old at every point
 * and no tangent asked for (the host re-evaluating the accepted state) the UMAT is not
 * called and the kept stress is returned; otherwise the UMAT is called with DTIME = 0.
 */
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "matrix3.h"
#include "musclefem_material.h"
#include "musclefem_umat.h"
#include "musclefem_vumat.h"
#include "vumat_config.h"

#define STATE_COUNT (UMAT_ADAPTER_STATES + VUMAT_NSTATEV)
#define PROPERTY_COUNT (VUMAT_NPROPS + UMAT_ADAPTER_PARAMETERS)

static const size_t USER_STATES = VUMAT_NSTATEV;

static const MusclefemParameterInfo parameters[PROPERTY_COUNT] = {
    VUMAT_PROPS_TABLE
    {"umat_char_length", "m", "CELENT passed to the UMAT", 1.0e-3, 0.0, INFINITY, 0, 0},
    {"umat_temperature", "K", "TEMP passed to the UMAT (DTEMP = 0)", 0.0, -INFINITY, INFINITY,
     0, 0},
};

static const MusclefemStateInfo states[STATE_COUNT] = {
    {"umat_stress_11", "Pa", 0.0}, {"umat_stress_22", "Pa", 0.0}, {"umat_stress_33", "Pa", 0.0},
    {"umat_stress_12", "Pa", 0.0}, {"umat_stress_13", "Pa", 0.0}, {"umat_stress_23", "Pa", 0.0},
    {"umat_stran_11", "1", 0.0},   {"umat_stran_22", "1", 0.0},   {"umat_stran_33", "1", 0.0},
    {"umat_stran_12", "1", 0.0},   {"umat_stran_13", "1", 0.0},   {"umat_stran_23", "1", 0.0},
    {"umat_sse", "J/m^3", 0.0},    {"umat_spd", "J/m^3", 0.0},    {"umat_scd", "J/m^3", 0.0},
    {"umat_increments", "1", 0.0},
    VUMAT_USER_STATES_TABLE
};

/* A quiet NaN with a payload no arithmetic produces: DDSDDE's "never set" mark. */
static const uint64_t UNSET_BITS = UINT64_C(0x7FF8DEADBEEF5EED);
static const char* const COMPONENTS[6] = {"11", "22", "33", "12", "13", "23"};
/* The host's perturbation of F for finite-difference tangents (TANGENT_PERTURBATION). */
static const double PERTURBATION = 1e-6;

static int32_t fail(char* message, uint64_t capacity, const char* format, ...) {
    if (message != NULL && capacity > 0) {
        int used = snprintf(message, (size_t)capacity, "UMAT (cmname '%s'): ", VUMAT_CMNAME);
        if (used >= 0 && (uint64_t)used < capacity) {
            va_list args;
            va_start(args, format);
            vsnprintf(message + used, (size_t)(capacity - (uint64_t)used), format, args);
            va_end(args);
        }
    }
    return 1;
}

static int is_unset(double value) {
    uint64_t bits;
    memcpy(&bits, &value, sizeof bits);
    return bits == UNSET_BITS;
}

/* Every argument of one UMAT call. */
typedef struct {
    double stress[6], ddsdde[36], sse, spd, scd, rpl, ddsddt[6], drplde[6], drpldt;
    double stran[6], dstran[6], time[2], dtime, temp, dtemp, predef[1], dpred[1];
    double coords[3], drot[9], pnewdt, celent, dfgrd0[9], dfgrd1[9];
    int ndi, nshr, ntens, nstatv, nprops, noel, npt, layer, kspt, jstep[4], kinc;
    const double* props;
    char cmname[80];
    double* statev; /* USER_STATES values (one when there are none) */
} UmatArguments;

static void call_umat(const void* arguments) {
    UmatArguments* a = (UmatArguments*)arguments;
    umat_(a->stress, a->statev, a->ddsdde, &a->sse, &a->spd, &a->scd, &a->rpl, a->ddsddt,
          a->drplde, &a->drpldt, a->stran, a->dstran, a->time, &a->dtime, &a->temp, &a->dtemp,
          a->predef, a->dpred, a->cmname, &a->ndi, &a->nshr, &a->ntens, &a->nstatv, a->props,
          &a->nprops, a->coords, a->drot, &a->pnewdt, &a->celent, a->dfgrd0, a->dfgrd1,
          &a->noel, &a->npt, &a->layer, &a->kspt, a->jstep, &a->kinc, (size_t)80);
}

static void to_column_major(const double m[3][3], double* out) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[i + 3 * j] = m[i][j];
}

/* q a q^T of a symmetric tensor in UMAT order. */
static void rotate_umat(const double q[3][3], const double* in, int engineering, double* out) {
    double s[3][3], rotated[3][3];
    get_umat_symmetric(in, engineering, s);
    from_basis(q, s, rotated);
    put_umat_symmetric(rotated, engineering, out);
}

/* The arguments for point p of the block at the deformation gradient f_new (F_new, or a
 * perturbation of it). */
static int32_t prepare(const MusclefemPointBlock* block, uint64_t p, const double f_new[3][3],
                       UmatArguments* a, char* message, uint64_t capacity) {
    const double* old = block->state_old + STATE_COUNT * p;
    double f_old[3][3], drot[3][3];
    mat_from_column_major(block->deformation_gradient_old + 9 * p, f_old);
    if (umat_increment_kinematics(f_old, f_new, a->dstran, drot) != 0)
        return fail(message, capacity, "F_mid = (F_old + F_new)/2 is singular or inverted at "
                    "point %" PRIu64 " (det F_old = %g, det F_new = %g)", p, mat_det(f_old),
                    mat_det(f_new));
    rotate_umat(drot, old + UMAT_STATE_STRESS, 0, a->stress);
    rotate_umat(drot, old + UMAT_STATE_STRAN, 1, a->stran);
    to_column_major(drot, a->drot);
    to_column_major(f_old, a->dfgrd0);
    to_column_major(f_new, a->dfgrd1);
    double unset;
    memcpy(&unset, &UNSET_BITS, sizeof unset);
    for (int c = 0; c < 36; ++c) a->ddsdde[c] = unset;
    memset(a->ddsddt, 0, sizeof a->ddsddt);
    memset(a->drplde, 0, sizeof a->drplde);
    a->rpl = a->drpldt = 0.0;
    a->sse = old[UMAT_STATE_SSE];
    a->spd = old[UMAT_STATE_SPD];
    a->scd = old[UMAT_STATE_SCD];
    a->time[0] = a->time[1] = block->time - block->dt;
    a->dtime = block->dt;
    a->temp = block->properties[VUMAT_NPROPS + 1];
    a->dtemp = a->predef[0] = a->dpred[0] = 0.0;
    a->celent = block->properties[VUMAT_NPROPS];
    memset(a->coords, 0, sizeof a->coords);
    a->pnewdt = 1.0;
    a->ndi = a->nshr = 3;
    a->ntens = 6;
    a->nstatv = VUMAT_NSTATEV;
    a->nprops = VUMAT_NPROPS;
    a->props = block->properties;
    a->noel = (int)(p + 1);
    a->npt = a->layer = a->kspt = 1;
    a->jstep[0] = a->jstep[1] = a->jstep[2] = 1;
    a->jstep[3] = 0;
    a->kinc = (int)old[UMAT_STATE_INCREMENTS] + 1;
    memset(a->cmname, ' ', sizeof a->cmname);
    memcpy(a->cmname, VUMAT_CMNAME, strlen(VUMAT_CMNAME));
    for (size_t i = 0; i < USER_STATES; ++i) a->statev[i] = old[UMAT_ADAPTER_STATES + i];
    if (VUMAT_FIBER == VUMAT_FIBER_STATE && VUMAT_NSTATEV >= 3 && a->kinc == 1) {
        const double* fiber = block->fiber_direction + 3 * p;
        double norm = sqrt(fiber[0] * fiber[0] + fiber[1] * fiber[1] + fiber[2] * fiber[2]);
        for (size_t i = 0; i < 3; ++i) a->statev[i] = fiber[i] / norm;
    }
    return 0;
}

/* Run the UMAT on prepared arguments and check what it returned (not DDSDDE). `what`
 * says which call it was, for the messages. */
static int32_t run(UmatArguments* a, uint64_t p, const char* what, char* message,
                   uint64_t capacity) {
    AbaqusCall call;
    if (abaqus_call_guarded(&call, "UMAT", call_umat, a) != 0)
        return fail(message, capacity, "the UMAT stopped on point %" PRIu64 " of the block at "
                    "TIME(2) = %g%s: %s", p, a->time[1], what, call.message);
    for (int c = 0; c < 6; ++c)
        if (!isfinite(a->stress[c]))
            return fail(message, capacity, "the UMAT returned %s in STRESS(%d) (component %s of "
                        "point %" PRIu64 " of the block) at TIME(2) = %g%s",
                        isnan(a->stress[c]) ? "NaN" : "an infinite value", c + 1, COMPONENTS[c],
                        p, a->time[1], what);
    for (size_t i = 0; i < USER_STATES; ++i)
        if (!isfinite(a->statev[i]))
            return fail(message, capacity, "the UMAT returned a non-finite STATEV(%zu) (sdv%zu of "
                        "point %" PRIu64 " of the block) at TIME(2) = %g%s", i + 1, i + 1, p,
                        a->time[1], what);
    if (!isfinite(a->sse) || !isfinite(a->spd) || !isfinite(a->scd))
        return fail(message, capacity, "the UMAT returned a non-finite %s (point %" PRIu64
                    " of the block) at TIME(2) = %g%s", !isfinite(a->sse) ? "SSE" :
                    (!isfinite(a->spd) ? "SPD" : "SCD"), p, a->time[1], what);
    if (!(a->pnewdt >= 1.0))
        return fail(message, capacity, "the UMAT asked for a shorter increment (PNEWDT = %g) at "
                    "point %" PRIu64 " of the block at TIME(2) = %g%s; musclefem does not "
                    "shorten increments on a material's request (the implicit solver's step "
                    "cutting retries a failed increment with half of it)", a->pnewdt, p,
                    a->time[1], what);
    return 0;
}

/* The first Piola-Kirchhoff stress J sigma F^-T of STRESS at F. */
static void first_piola(const double stress[6], const double f[3][3], double p_out[3][3]) {
    double sigma[3][3], f_inverse[3][3];
    get_umat_symmetric(stress, 0, sigma);
    const double j = mat_inverse(f, f_inverse);
    for (int i = 0; i < 3; ++i)
        for (int big_j = 0; big_j < 3; ++big_j)
            p_out[i][big_j] = j * (sigma[i][0] * f_inverse[big_j][0] +
                                   sigma[i][1] * f_inverse[big_j][1] +
                                   sigma[i][2] * f_inverse[big_j][2]);
}

/* dP/dF of point p by central differences of the UMAT's stress over F_new. */
static int32_t difference_tangent(const MusclefemPointBlock* block, uint64_t p,
                                  const double f_new[3][3], UmatArguments* a, double* tangent,
                                  char* message, uint64_t capacity) {
    const char* what = " (a call with a perturbed F for the finite-difference tangent: the "
                       "UMAT set no entry of DDSDDE)";
    for (int column = 0; column < 9; ++column) {
        double p_plus[3][3], p_minus[3][3];
        for (int sign = 1; sign >= -1; sign -= 2) {
            double f[3][3];
            memcpy(f, f_new, sizeof f);
            f[column % 3][column / 3] += sign * PERTURBATION;
            int32_t code = prepare(block, p, f, a, message, capacity);
            if (code == 0) code = run(a, p, what, message, capacity);
            if (code != 0) return code;
            first_piola(a->stress, f, sign > 0 ? p_plus : p_minus);
        }
        for (int row = 0; row < 9; ++row)
            tangent[row + 9 * column] =
                (p_plus[row % 3][row / 3] - p_minus[row % 3][row / 3]) / (2.0 * PERTURBATION);
    }
    return 0;
}

/* The call `a`'s DDSDDE as the tangent dP/dF; DDSDDE all unset: central differences
 * instead, with `scratch` for the calls. */
static int32_t point_tangent(const MusclefemPointBlock* block, uint64_t p,
                             const double f_new[3][3], const UmatArguments* a,
                             UmatArguments* scratch, double* tangent, char* message,
                             uint64_t capacity) {
    int unset = 0, first_unset = -1, first_set = -1;
    for (int c = 0; c < 36; ++c) {
        if (is_unset(a->ddsdde[c])) {
            ++unset;
            if (first_unset < 0) first_unset = c;
        } else {
            if (first_set < 0) first_set = c;
            if (!isfinite(a->ddsdde[c]))
                return fail(message, capacity, "the UMAT returned %s in DDSDDE(%d, %d) (point %"
                            PRIu64 " of the block) at TIME(2) = %g",
                            isnan(a->ddsdde[c]) ? "NaN" : "an infinite value", c % 6 + 1,
                            c / 6 + 1, p, a->time[1]);
        }
    }
    if (unset == 36)
        return difference_tangent(block, p, f_new, scratch, tangent, message, capacity);
    if (unset > 0)
        return fail(message, capacity, "the UMAT set DDSDDE only in part: DDSDDE(%d, %d) was set "
                    "but DDSDDE(%d, %d) was not (point %" PRIu64 " of the block; DDSDDE is "
                    "filled with NaN before the call and %d of its 36 entries still hold it: set "
                    "all of them, or none for a finite-difference tangent)", first_set % 6 + 1,
                    first_set / 6 + 1, first_unset % 6 + 1, first_unset / 6 + 1, p, unset);
    double sigma[3][3];
    get_umat_symmetric(a->stress, 0, sigma);
    umat_first_elasticity(a->ddsdde, sigma, f_new, tangent);
    return 0;
}

/* dt = 0, F_new = F_old, no tangent: the kept stress, the state unchanged. */
static void reevaluate(const MusclefemPointBlock* block) {
    for (uint64_t p = 0; p < block->point_count; ++p) {
        const double* old = block->state_old + STATE_COUNT * p;
        double sigma[3][3];
        get_umat_symmetric(old + UMAT_STATE_STRESS, 0, sigma);
        put_host_voigt(sigma, block->cauchy_stress + 6 * p);
        memcpy(block->state_new + STATE_COUNT * p, old, STATE_COUNT * sizeof(double));
    }
}

static int32_t advance(const MusclefemPointBlock* block, char* message, uint64_t capacity) {
    /* Two sets of user state variables: the call's, and the finite differences'. */
    double* statev = (double*)calloc(2 * (USER_STATES + 1), sizeof(double));
    if (statev == NULL) return fail(message, capacity, "out of memory");
    UmatArguments a, perturbed;
    a.statev = statev;
    perturbed.statev = statev + USER_STATES + 1;
    int32_t code = 0;
    for (uint64_t p = 0; p < block->point_count && code == 0; ++p) {
        double f_new[3][3];
        mat_from_column_major(block->deformation_gradient_new + 9 * p, f_new);
        code = prepare(block, p, f_new, &a, message, capacity);
        if (code == 0) code = run(&a, p, "", message, capacity);
        if (code == 0 && block->tangent != NULL)
            code = point_tangent(block, p, f_new, &a, &perturbed, block->tangent + 81 * p,
                                 message, capacity);
        if (code != 0) break;
        double sigma[3][3];
        get_umat_symmetric(a.stress, 0, sigma);
        put_host_voigt(sigma, block->cauchy_stress + 6 * p);
        const double* old = block->state_old + STATE_COUNT * p;
        double* state = block->state_new + STATE_COUNT * p;
        if (block->dt == 0.0) {
            memcpy(state, old, STATE_COUNT * sizeof(double));
            continue;
        }
        for (int c = 0; c < 6; ++c) {
            state[UMAT_STATE_STRESS + c] = a.stress[c];
            state[UMAT_STATE_STRAN + c] = a.stran[c] + a.dstran[c];
        }
        state[UMAT_STATE_SSE] = a.sse;
        state[UMAT_STATE_SPD] = a.spd;
        state[UMAT_STATE_SCD] = a.scd;
        state[UMAT_STATE_INCREMENTS] = old[UMAT_STATE_INCREMENTS] + 1.0;
        for (size_t i = 0; i < USER_STATES; ++i) state[UMAT_ADAPTER_STATES + i] = a.statev[i];
    }
    free(statev);
    return code;
}

static int32_t update(const MusclefemPointBlock* block, char* message, uint64_t capacity) {
    if (block == NULL) return fail(message, capacity, "the block pointer is NULL");
    if (block->struct_size < sizeof(MusclefemPointBlock))
        return fail(message, capacity, "the host's block is smaller than this plugin's");
    if (block->property_count != PROPERTY_COUNT || block->properties == NULL)
        return fail(message, capacity, "expected %d properties (the UMAT's nprops = %d, then "
                    "umat_char_length, umat_temperature), got %" PRIu64, PROPERTY_COUNT,
                    VUMAT_NPROPS, block->property_count);
    if (block->point_count == 0) return 0;
    if (block->dt == 0.0 && block->tangent == NULL &&
        memcmp(block->deformation_gradient_old, block->deformation_gradient_new,
               9 * sizeof(double) * block->point_count) == 0) {
        reevaluate(block);
        return 0;
    }
    return advance(block, message, capacity);
}

static const MusclefemMaterialPlugin plugin = {
    MUSCLEFEM_MATERIAL_ABI_VERSION,
    (uint32_t)sizeof(MusclefemMaterialPlugin),
    VUMAT_NAME,
    VUMAT_DESCRIPTION,
    PROPERTY_COUNT,
    parameters,
    STATE_COUNT,
    states,
    UMAT_TANGENT, /* provides_tangent: DDSDDE (or the adapter's differences); 0: the host's */
    update,
};

MUSCLEFEM_EXPORT const MusclefemMaterialPlugin* musclefem_material_plugin(void) {
    return &plugin;
}

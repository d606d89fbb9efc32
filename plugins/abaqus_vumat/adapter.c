/*
 * adapter.c — the musclefem material plugin that runs an Abaqus/Explicit VUMAT.
 *
 * Per host block (musclefem_material.h) with dt > 0, in chunks of at most VUMAT_MAX_BLOCK
 * points, for each point p with reference fiber direction a and material basis Q
 * (material_basis: Q = I unless the fiber convention is VUMAT_FIBER_ORIENTATION):
 *
 *   F_old, F_new  -> Q^T F Q (the VUMAT's basis), polar decompositions F = R U;
 *   stretchOld/New = U, defgradOld/New = F (in that basis);
 *   strainInc, relSpinInc from increment_kinematics (midpoint rule, co-rotational);
 *   stressOld     = the co-rotational stress the adapter kept in the point's state;
 *   stateOld      = the user's state variables (the fiber direction written into the first
 *                   three at the first increment under VUMAT_FIBER_STATE);
 *   density       = rho_0 / det F_mid [kg/m^3], charLength, tempOld = tempNew from the
 *                   adapter's parameters; coordMp = 0 (the host does not pass positions);
 *   stepTime = totalTime = time - dt (the start of the increment), lanneal = 0.
 *
 * After the call, the Cauchy stress sigma = Q R_new stressNew R_new^T Q^T goes to the host
 * in its Voigt order (xx, yy, zz, yz, xz, xy), and stressNew, the energies and stateNew are
 * kept as the point's state.
 *
 * dt = 0 is not a step (musclefem_material.h): the state is returned unchanged. When F_new
 * = F_old at every point (the host re-evaluating the accepted state for frames and history)
 * the VUMAT is not called: the kept stress is rotated with R of F_new. Otherwise (the host
 * differentiating the stress at t = 0 for the explicit solver's stable step) the VUMAT is
 * called with dt = 0 and stepTime = totalTime = time, like Abaqus/Explicit's data-check
 * call with a fictitious strain increment, and its stress is returned but not kept.
 *
 * stressNew is filled with a NaN of a fixed bit pattern before the call: an entry that
 * still holds it was never set. stateNew and the energies start as copies of the old
 * values (so a VUMAT that leaves a state variable alone keeps it). Every output is checked
 * to be finite; an error names the array, the entry and the point.
 */
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "matrix3.h"
#include "musclefem_material.h"
#include "musclefem_vumat.h"
#include "vumat_config.h"

#define STATE_COUNT (VUMAT_ADAPTER_STATES + VUMAT_NSTATEV)
#define PROPERTY_COUNT (VUMAT_NPROPS + VUMAT_ADAPTER_PARAMETERS)

/* The user's nstatev as a variable, so that loops over it compile without warnings when
 * it is 0. */
static const size_t USER_STATES = VUMAT_NSTATEV;

static const MusclefemParameterInfo parameters[PROPERTY_COUNT] = {
    VUMAT_PROPS_TABLE
    {"vumat_density", "kg/m^3", "reference density rho_0; the VUMAT's density is rho_0/J",
     1000.0, 0.0, INFINITY, 0, 0},
    {"vumat_char_length", "m", "charLength passed to the VUMAT", 1.0e-3, 0.0, INFINITY, 0, 0},
    {"vumat_temperature", "K", "tempOld = tempNew passed to the VUMAT", 0.0, -INFINITY,
     INFINITY, 0, 0},
};

static const MusclefemStateInfo states[STATE_COUNT] = {
    {"vumat_stress_11", "Pa", 0.0},
    {"vumat_stress_22", "Pa", 0.0},
    {"vumat_stress_33", "Pa", 0.0},
    {"vumat_stress_12", "Pa", 0.0},
    {"vumat_stress_23", "Pa", 0.0},
    {"vumat_stress_31", "Pa", 0.0},
    {"vumat_ener_intern", "J/kg", 0.0},
    {"vumat_ener_inelas", "J/kg", 0.0},
    {"vumat_started", "1", 0.0},
    VUMAT_USER_STATES_TABLE
};

/* A quiet NaN with a payload no arithmetic produces: stressNew's "never set" mark. */
static const uint64_t UNSET_BITS = UINT64_C(0x7FF8DEADBEEF5EED);
static const char* const COMPONENTS[6] = {"11", "22", "33", "12", "23", "31"};

static int32_t fail(char* message, uint64_t capacity, const char* format, ...) {
    if (message != NULL && capacity > 0) {
        int used = snprintf(message, (size_t)capacity, "VUMAT (cmname '%s'): ", VUMAT_CMNAME);
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

/* The point's fiber basis Q, and F_new (and F_old) in it. */
static void point_tensors(const MusclefemPointBlock* block, uint64_t p, double q[3][3],
                          double f_old[3][3], double f_new[3][3]) {
    double global[3][3];
    material_basis(block->fiber_direction + 3 * p, VUMAT_FIBER, q);
    mat_from_column_major(block->deformation_gradient_old + 9 * p, global);
    to_basis(q, global, f_old);
    mat_from_column_major(block->deformation_gradient_new + 9 * p, global);
    to_basis(q, global, f_new);
}

/* sigma = Q R sigma_hat R^T Q^T into the host's Voigt order. */
static void put_cauchy(const double q[3][3], const double r[3][3], const double sigma_hat[3][3],
                       double* out) {
    double local[3][3], global[3][3];
    from_basis(r, sigma_hat, local);
    from_basis(q, local, global);
    put_host_voigt(global, out);
}

/* The unit reference fiber, written into the first three user state variables until the
 * first increment has been accepted (VUMAT_FIBER_STATE only). */
static void initial_fiber_state(const MusclefemPointBlock* block, uint64_t p, double* user,
                                size_t stride) {
    if (VUMAT_FIBER != VUMAT_FIBER_STATE || block->state_old[STATE_COUNT * p + VUMAT_STATE_STARTED] != 0.0)
        return;
    const double* a = block->fiber_direction + 3 * p;
    double norm = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int i = 0; i < 3; ++i) user[stride * (size_t)i] = a[i] / norm;
}

/* dt = 0 and F_new = F_old: the kept co-rotational stress, rotated with R of F_new; the
 * state unchanged. */
static int32_t reevaluate(const MusclefemPointBlock* block, char* message, uint64_t capacity) {
    for (uint64_t p = 0; p < block->point_count; ++p) {
        double q[3][3], f_old[3][3], f_new[3][3], r[3][3], u[3][3], sigma_hat[3][3];
        point_tensors(block, p, q, f_old, f_new);
        if (polar_decomposition(f_new, r, u) != 0)
            return fail(message, capacity, "the polar decomposition of F failed at point %" PRIu64
                        " (det F = %g)", p, mat_det(f_new));
        const double* old = block->state_old + STATE_COUNT * p;
        get_abaqus_symmetric(old, 1, sigma_hat);
        put_cauchy(q, r, sigma_hat, block->cauchy_stress + 6 * p);
        double* new_state = block->state_new + STATE_COUNT * p;
        memcpy(new_state, old, STATE_COUNT * sizeof(double));
        if (VUMAT_NSTATEV >= 3) initial_fiber_state(block, p, new_state + VUMAT_ADAPTER_STATES, 1);
    }
    return 0;
}

/* The VUMAT's arrays for a chunk of up to `nb` points, in one allocation. */
typedef struct {
    double *coord_mp, *char_length, *density, *strain_inc, *rel_spin_inc, *temp_old, *temp_new;
    double *stretch_old, *stretch_new, *defgrad_old, *defgrad_new, *stress_old, *stress_new;
    double *state_old, *state_new, *ener_intern_old, *ener_intern_new, *ener_inelas_old;
    double *ener_inelas_new, *rotation, *basis;
    double empty[1]; /* fieldOld/fieldNew (nfieldv = 0), and stateOld/New when nstatev = 0 */
    double* memory;
} Workspace;

static int workspace_allocate(Workspace* w, size_t nb) {
    const size_t per_point = 80 + 2 * (size_t)VUMAT_NSTATEV;
    w->memory = (double*)calloc(nb * per_point, sizeof(double));
    if (w->memory == NULL) return 1;
    double* next = w->memory;
#define TAKE(field, count) (w->field = next, next += nb * (size_t)(count))
    TAKE(coord_mp, 3), TAKE(char_length, 1), TAKE(density, 1), TAKE(strain_inc, 6);
    TAKE(rel_spin_inc, 3), TAKE(temp_old, 1), TAKE(temp_new, 1), TAKE(stretch_old, 6);
    TAKE(stretch_new, 6), TAKE(defgrad_old, 9), TAKE(defgrad_new, 9), TAKE(stress_old, 6);
    TAKE(stress_new, 6), TAKE(ener_intern_old, 1), TAKE(ener_intern_new, 1);
    TAKE(ener_inelas_old, 1), TAKE(ener_inelas_new, 1), TAKE(rotation, 9), TAKE(basis, 9);
    TAKE(state_old, VUMAT_NSTATEV), TAKE(state_new, VUMAT_NSTATEV);
#undef TAKE
    if (VUMAT_NSTATEV == 0) w->state_old = w->state_new = w->empty;
    return 0;
}

/* Fill the VUMAT's inputs for points start .. start+nb-1. */
static int32_t gather(const MusclefemPointBlock* block, uint64_t start, size_t nb, Workspace* w,
                      char* message, uint64_t capacity) {
    const double* props = block->properties;
    const double rho_0 = props[VUMAT_NPROPS], char_length = props[VUMAT_NPROPS + 1];
    const double temperature = props[VUMAT_NPROPS + 2];
    double unset;
    memcpy(&unset, &UNSET_BITS, sizeof unset);
    for (size_t k = 0; k < nb; ++k) {
        const uint64_t p = start + k;
        double q[3][3], f_old[3][3], f_new[3][3], r_old[3][3], u_old[3][3], r_new[3][3];
        double u_new[3][3], strain[3][3], spin[3], j_mid;
        point_tensors(block, p, q, f_old, f_new);
        if (polar_decomposition(f_old, r_old, u_old) != 0 ||
            polar_decomposition(f_new, r_new, u_new) != 0 ||
            increment_kinematics(f_old, f_new, r_old, r_new, strain, spin, &j_mid) != 0)
            return fail(message, capacity, "the polar decomposition of F failed at point %" PRIu64
                        " (det F_old = %g, det F_new = %g)", p, mat_det(f_old), mat_det(f_new));
        put_abaqus_symmetric(strain, w->strain_inc + k, nb);
        for (size_t c = 0; c < 3; ++c) w->rel_spin_inc[k + nb * c] = spin[c];
        put_abaqus_symmetric(u_old, w->stretch_old + k, nb);
        put_abaqus_symmetric(u_new, w->stretch_new + k, nb);
        put_abaqus_full(f_old, w->defgrad_old + k, nb);
        put_abaqus_full(f_new, w->defgrad_new + k, nb);
        memcpy(w->rotation + 9 * k, r_new, sizeof r_new);
        memcpy(w->basis + 9 * k, q, sizeof q);
        w->density[k] = rho_0 / j_mid;
        w->char_length[k] = char_length;
        w->temp_old[k] = w->temp_new[k] = temperature;
        const double* old = block->state_old + STATE_COUNT * p;
        for (size_t c = 0; c < 6; ++c) {
            w->stress_old[k + nb * c] = old[c];
            w->stress_new[k + nb * c] = unset;
        }
        w->ener_intern_old[k] = w->ener_intern_new[k] = old[VUMAT_STATE_ENER_INTERN];
        w->ener_inelas_old[k] = w->ener_inelas_new[k] = old[VUMAT_STATE_ENER_INELAS];
        for (size_t i = 0; i < USER_STATES; ++i)
            w->state_old[k + nb * i] = old[VUMAT_ADAPTER_STATES + i];
        if (VUMAT_NSTATEV >= 3) initial_fiber_state(block, p, w->state_old + k, nb);
        for (size_t i = 0; i < USER_STATES; ++i)
            w->state_new[k + nb * i] = w->state_old[k + nb * i];
    }
    return 0;
}

/* Check the VUMAT's outputs and hand them to the host. */
static int32_t scatter(const MusclefemPointBlock* block, uint64_t start, size_t nb,
                       const Workspace* w, double step_time, char* message, uint64_t capacity) {
    const char* zero_step = block->dt == 0.0 ? " (a call with dt = 0: the host differentiates "
        "the stress in no time, as Abaqus/Explicit's data-check call does; the VUMAT must not "
        "divide by dt there)" : "";
    for (size_t k = 0; k < nb; ++k) {
        const uint64_t p = start + k;
        for (size_t c = 0; c < 6; ++c) {
            double v = w->stress_new[k + nb * c];
            if (is_unset(v))
                return fail(message, capacity, "the VUMAT never set stressNew(%zu, %zu) (component "
                            "%s of point %" PRIu64 " of the block; stressNew is filled with NaN "
                            "before the call and this entry still holds it)", k + 1, c + 1,
                            COMPONENTS[c], p);
            if (!isfinite(v))
                return fail(message, capacity, "the VUMAT returned %s in stressNew(%zu, %zu) "
                            "(component %s of point %" PRIu64 " of the block) at stepTime = %g%s",
                            isnan(v) ? "NaN" : "an infinite value", k + 1, c + 1, COMPONENTS[c],
                            p, step_time, zero_step);
        }
        for (size_t i = 0; i < USER_STATES; ++i)
            if (!isfinite(w->state_new[k + nb * i]))
                return fail(message, capacity, "the VUMAT returned a non-finite stateNew(%zu, %zu) "
                            "(sdv%zu of point %" PRIu64 " of the block) at stepTime = %g", k + 1,
                            i + 1, i + 1, p, step_time);
        if (!isfinite(w->ener_intern_new[k]) || !isfinite(w->ener_inelas_new[k]))
            return fail(message, capacity, "the VUMAT returned a non-finite %s(%zu) (point %" PRIu64
                        " of the block) at stepTime = %g", isfinite(w->ener_intern_new[k]) ?
                        "enerInelasNew" : "enerInternNew", k + 1, p, step_time);
        double sigma_hat[3][3], q[3][3], r[3][3];
        get_abaqus_symmetric(w->stress_new + k, nb, sigma_hat);
        memcpy(q, w->basis + 9 * k, sizeof q);
        memcpy(r, w->rotation + 9 * k, sizeof r);
        put_cauchy(q, r, sigma_hat, block->cauchy_stress + 6 * p);
        double* state = block->state_new + STATE_COUNT * p;
        if (block->dt == 0.0) {
            memcpy(state, block->state_old + STATE_COUNT * p, STATE_COUNT * sizeof(double));
            continue;
        }
        for (size_t c = 0; c < 6; ++c) state[c] = w->stress_new[k + nb * c];
        state[VUMAT_STATE_ENER_INTERN] = w->ener_intern_new[k];
        state[VUMAT_STATE_ENER_INELAS] = w->ener_inelas_new[k];
        state[VUMAT_STATE_STARTED] = 1.0;
        for (size_t i = 0; i < USER_STATES; ++i)
            state[VUMAT_ADAPTER_STATES + i] = w->state_new[k + nb * i];
    }
    return 0;
}

/* The VUMAT's call with every argument by reference (abaqus_call_guarded's body). */
static void call_vumat(const void* arguments) {
    static const int ndir = 3, nshr = 3, nfieldv = 0, lanneal = 0;
    const VumatArguments* a = (const VumatArguments*)arguments;
    vumat_(&a->nblock, &ndir, &nshr, &a->nstatev, &nfieldv, &a->nprops, &lanneal, &a->step_time,
           &a->total_time, &a->dt, a->cmname, a->coord_mp, a->char_length, a->props, a->density,
           a->strain_inc, a->rel_spin_inc, a->temp_old, a->stretch_old, a->defgrad_old,
           a->field_old, a->stress_old, a->state_old, a->ener_intern_old, a->ener_inelas_old,
           a->temp_new, a->stretch_new, a->defgrad_new, a->field_new, a->stress_new, a->state_new,
           a->ener_intern_new, a->ener_inelas_new, (size_t)80);
}

static int32_t advance(const MusclefemPointBlock* block, char* message, uint64_t capacity) {
    const uint64_t n = block->point_count;
    const size_t most = n < VUMAT_MAX_BLOCK ? (size_t)n : VUMAT_MAX_BLOCK;
    char cmname[80];
    memset(cmname, ' ', sizeof cmname);
    memcpy(cmname, VUMAT_CMNAME, strlen(VUMAT_CMNAME));
    Workspace w;
    if (workspace_allocate(&w, most) != 0)
        return fail(message, capacity, "out of memory for a block of %zu points", most);
    int32_t code = 0;
    /* The start of the increment; with dt = 0, the time itself. */
    const double step_time = block->time - block->dt;
    for (uint64_t start = 0; start < n && code == 0; start += most) {
        const size_t nb = (n - start < most) ? (size_t)(n - start) : most;
        code = gather(block, start, nb, &w, message, capacity);
        if (code != 0) break;
        VumatArguments a = {
            .nblock = (int)nb, .nstatev = VUMAT_NSTATEV, .nprops = VUMAT_NPROPS,
            .step_time = step_time, .total_time = step_time, .dt = block->dt, .cmname = cmname,
            .coord_mp = w.coord_mp, .char_length = w.char_length, .props = block->properties,
            .density = w.density, .strain_inc = w.strain_inc, .rel_spin_inc = w.rel_spin_inc,
            .temp_old = w.temp_old, .stretch_old = w.stretch_old, .defgrad_old = w.defgrad_old,
            .field_old = w.empty, .stress_old = w.stress_old, .state_old = w.state_old,
            .ener_intern_old = w.ener_intern_old, .ener_inelas_old = w.ener_inelas_old,
            .temp_new = w.temp_new, .stretch_new = w.stretch_new, .defgrad_new = w.defgrad_new,
            .field_new = w.empty, .stress_new = w.stress_new, .state_new = w.state_new,
            .ener_intern_new = w.ener_intern_new, .ener_inelas_new = w.ener_inelas_new,
        };
        AbaqusCall call;
        if (abaqus_call_guarded(&call, "VUMAT", call_vumat, &a) != 0) {
            code = fail(message, capacity, "the VUMAT stopped on points %" PRIu64 "..%" PRIu64
                        " of the block at stepTime = %g: %s", start, start + nb - 1, step_time,
                        call.message);
            break;
        }
        code = scatter(block, start, nb, &w, step_time, message, capacity);
    }
    free(w.memory);
    return code;
}

static int32_t update(const MusclefemPointBlock* block, char* message, uint64_t capacity) {
    if (block == NULL) return fail(message, capacity, "the block pointer is NULL");
    if (block->struct_size < sizeof(MusclefemPointBlock))
        return fail(message, capacity, "the host's block is smaller than this plugin's");
    if (block->property_count != PROPERTY_COUNT || block->properties == NULL)
        return fail(message, capacity, "expected %d properties (the VUMAT's nprops = %d, then "
                    "vumat_density, vumat_char_length, vumat_temperature), got %" PRIu64,
                    PROPERTY_COUNT, VUMAT_NPROPS, block->property_count);
    if (block->point_count == 0) return 0;
    if (block->dt == 0.0 && memcmp(block->deformation_gradient_old, block->deformation_gradient_new,
                                   9 * sizeof(double) * block->point_count) == 0)
        return reevaluate(block, message, capacity);
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
    0, /* provides_tangent: the host differentiates the stress */
    update,
};

MUSCLEFEM_EXPORT const MusclefemMaterialPlugin* musclefem_material_plugin(void) {
    return &plugin;
}

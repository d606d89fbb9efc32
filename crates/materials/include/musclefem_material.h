/*
 * musclefem_material.h — the C ABI of musclefem material plugins (ABI version 1).
 *
 * A material plugin is a shared library (.so / .dylib / .dll) that exports ONE symbol,
 *
 *     const MusclefemMaterialPlugin* musclefem_material_plugin(void);
 *
 * returning a pointer to a table that lives as long as the library stays loaded (in
 * practice: a static). The table names the material, declares its parameters and state
 * variables, and holds the batched, VUMAT-like `update` function. The host (musclefem)
 * loads the library with `MaterialLibrary::load_plugin`, checks the table once, and from
 * then on the material is used exactly like a built-in one: scene files refer to it by its
 * name, and user parameter values are checked against the declared ranges by the host
 * before the plugin ever sees them.
 *
 * Any language that can export a C function works (C, C++, Rust, Fortran with
 * ISO_C_BINDING). See plugins/neo_hookean_c/neo_hookean.c and plugins/neo_hookean_rust/.
 *
 * Conventions (identical to the Rust interface, crates/materials/src/material.rs):
 *   - SI units: Pa, s, m.
 *   - Matrices are stored column-major: entry (i, J) of the deformation gradient F of
 *     point p is at F[9p + i + 3J] (i, J = 0, 1, 2).
 *   - Cauchy stress in Voigt order (xx, yy, zz, yz, xz, xy) [Pa], 6 per point.
 *   - Tangent: the first elasticity tensor dP/dF (P = J sigma F^-T, the first
 *     Piola-Kirchhoff stress), a 9x9 matrix on column-major vec(F), itself stored
 *     column-major: entry [81p + (i+3J) + 9(k+3L)] = dP_iJ / dF_kL [Pa]. It must be the
 *     consistent tangent of the stress actually returned (state at the start of the step
 *     held fixed).
 *
 * Rules a plugin must follow:
 *   1. Never let an exception, a Rust panic or a longjmp cross the ABI: a Rust panic that
 *      reaches an extern "C" boundary aborts the whole host process. Catch it inside the
 *      exported function (Rust: std::panic::catch_unwind) and return an error code.
 *   2. `update` must be reentrant: the host calls it concurrently from several threads,
 *      each call with its own block and its own output arrays. Keep no mutable global
 *      state (or synchronise it yourself). Each call should process its block serially:
 *      the host parallelises over blocks.
 *   3. Do not keep pointers from a block after `update` returns.
 *   4. Report failures (e.g. a local Newton solve that did not converge) by returning a
 *      non-zero code with a NUL-terminated message; never return NaN on purpose. The host
 *      also checks every result for NaN/Inf and reports the material and point.
 *   5. Everything the table points to (strings, parameter and state tables) must stay
 *      valid and unchanged while the library is loaded. The host copies what it needs at
 *      load time.
 *
 * The host checks at load: abi_version == MUSCLEFEM_MATERIAL_ABI_VERSION, struct_size >=
 * sizeof(MusclefemMaterialPlugin) of this header, a non-empty UTF-8 name, a non-NULL
 * update function, and a consistent parameter table (valid bounds, default within its
 * own range, unique names).
 */
#ifndef MUSCLEFEM_MATERIAL_H
#define MUSCLEFEM_MATERIAL_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The ABI version this header describes; a plugin puts it in `abi_version`. */
#define MUSCLEFEM_MATERIAL_ABI_VERSION 1u

/* The name of the one exported symbol. */
#define MUSCLEFEM_MATERIAL_PLUGIN_SYMBOL "musclefem_material_plugin"

/* Marks the exported function as visible from outside the shared library. */
#if defined(_WIN32)
#define MUSCLEFEM_EXPORT __declspec(dllexport)
#elif defined(__GNUC__) || defined(__clang__)
#define MUSCLEFEM_EXPORT __attribute__((visibility("default")))
#else
#define MUSCLEFEM_EXPORT
#endif

/* Declaration of one material parameter. The host resolves the user's values against
 * these declarations (unknown names, missing required values, NaN, +-Inf and values
 * outside the range are errors the host reports) and passes the values to `update` in
 * the order of this table. */
typedef struct {
    const char* name;        /* as written in scene files; non-empty UTF-8, unique */
    const char* unit;        /* SI unit, "1" for dimensionless; UTF-8, not NULL */
    const char* description; /* one line; UTF-8, may be NULL */
    double default_value;    /* NaN = required, no default; else finite and in range */
    double lower, upper;     /* valid range; -INFINITY / INFINITY = unbounded */
    int32_t lower_inclusive; /* non-zero: lower itself is allowed (ignored if unbounded) */
    int32_t upper_inclusive; /* non-zero: upper itself is allowed (ignored if unbounded) */
} MusclefemParameterInfo;

/* Declaration of one state variable carried by each material point. */
typedef struct {
    const char* name;     /* non-empty UTF-8 */
    const char* unit;     /* SI unit, "1" for dimensionless; UTF-8, not NULL */
    double initial_value; /* finite: the value at the start of the analysis */
} MusclefemStateInfo;

/* One batch of material points for one step. Written by the host; the plugin reads the
 * inputs and writes the outputs. */
typedef struct {
    uint64_t struct_size;   /* sizeof(MusclefemPointBlock) of the host, set by the host */
    uint64_t point_count;   /* number of points p = 0 .. point_count-1 (may be 0) */
    double time;            /* time at the END of the step, t+dt [s] */
    double dt;              /* step [s], >= 0. dt = 0 is a re-evaluation, not a step:
                               the host calls it with F_old = F_new and state_old =
                               the accepted state to write frames and history, and
                               expects the stress of that accepted state, state_new =
                               state_old, and no error (the Hill model: the contractile
                               element cannot move in no time, so nothing changes). */
    const double* properties;  /* parameter values in declared order */
    uint64_t property_count;   /* = parameter_count of the table */
    const double* deformation_gradient_old; /* 9 per point, column-major: F(i,J) at
                                                [9p + i + 3J], start of the step, det > 0 */
    const double* deformation_gradient_new; /* 9 per point, end of the step, det > 0 */
    const double* fiber_direction; /* 3 per point, reference configuration; non-zero but
                                      not necessarily unit: normalise it if you need to */
    const double* state_old;       /* state_count per point, start of the step */
    double* state_new;             /* state_count per point, end of the step: write all */
    double* cauchy_stress;         /* 6 per point, Voigt (xx, yy, zz, yz, xz, xy) [Pa]:
                                      write all */
    double* tangent; /* NULL, or 81 per point: dP/dF, 9x9 column-major on column-major
                        vec(F): entry [81p + (i+3J) + 9(k+3L)] = dP_iJ/dF_kL [Pa].
                        Only ever non-NULL when the plugin sets provides_tangent. */
} MusclefemPointBlock;

/* Updates a block: returns 0 on success; otherwise a non-zero code and a NUL-terminated
 * message (UTF-8) in message[0 .. message_capacity), which the host reports together with
 * the plugin path and the material name. */
typedef int32_t (*MusclefemUpdateFn)(const MusclefemPointBlock* block, char* message,
                                     uint64_t message_capacity);

/* The plugin's table. */
typedef struct {
    uint32_t abi_version;  /* MUSCLEFEM_MATERIAL_ABI_VERSION */
    uint32_t struct_size;  /* sizeof(MusclefemMaterialPlugin) */
    const char* name;        /* registry name, non-empty UTF-8, must not clash with
                                another material (e.g. "neo-hookean" is built in) */
    const char* description; /* one line; UTF-8, may be NULL */
    uint32_t parameter_count;
    const MusclefemParameterInfo* parameters; /* parameter_count entries (NULL if 0) */
    uint32_t state_count;
    const MusclefemStateInfo* states;         /* state_count entries (NULL if 0) */
    int32_t provides_tangent; /* 0: the host builds the tangent by central finite
                                 differences of the stress (18 extra one-point calls per
                                 point); non-zero: `update` fills `tangent` when non-NULL */
    MusclefemUpdateFn update; /* not NULL */
} MusclefemMaterialPlugin;

/* The one exported symbol. Must not fail; returns the same pointer on every call. */
MUSCLEFEM_EXPORT const MusclefemMaterialPlugin* musclefem_material_plugin(void);

/* The host mirrors these layouts in Rust (crates/materials/src/plugin/abi.rs) and checks
 * the same sizes at compile time. */
#if defined(__STDC_VERSION__) && __STDC_VERSION__ >= 201112L && defined(UINTPTR_MAX) && \
    UINTPTR_MAX == 0xFFFFFFFFFFFFFFFFu
_Static_assert(sizeof(MusclefemParameterInfo) == 56, "MusclefemParameterInfo layout");
_Static_assert(sizeof(MusclefemStateInfo) == 24, "MusclefemStateInfo layout");
_Static_assert(sizeof(MusclefemPointBlock) == 104, "MusclefemPointBlock layout");
_Static_assert(sizeof(MusclefemMaterialPlugin) == 72, "MusclefemMaterialPlugin layout");
#endif

#ifdef __cplusplus
}
#endif

#endif /* MUSCLEFEM_MATERIAL_H */

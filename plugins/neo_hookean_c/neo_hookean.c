/*
 * Example musclefem material plugin in C: the compressible neo-Hookean solid, as
 * material "neo-hookean-c-plugin".
 *
 *   W = mu/2 (I1bar - 3) + (J - 1)^2 / D,   sigma = (mu/J) dev(Bbar) + 2 (J - 1)/D I,
 *
 * with Bbar = Fbar Fbar^T, Fbar = J^(-1/3) F. The same model, in the same order of
 * operations, as musclefem's built-in "neo-hookean" and the Rust plugin
 * plugins/neo_hookean_rust; crates/materials/tests/plugins.rs checks that they agree.
 * No tangent is supplied (provides_tangent = 0): the host differentiates the stress.
 *
 * Build (Linux; -ffp-contract=off keeps a*b+c from being fused, for bit-level agreement
 * with the Rust versions on targets with FMA):
 *
 *   cc -shared -fPIC -O2 -ffp-contract=off -I crates/materials/include \
 *      plugins/neo_hookean_c/neo_hookean.c -o libneo_hookean_c.so -lm
 *
 * Plain C cannot throw, so there is nothing to catch at the boundary; a C++ plugin must
 * catch every exception inside update() and return an error code instead.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "musclefem_material.h"

static const MusclefemParameterInfo parameters[2] = {
    {"mu", "Pa", "shear modulus", 11370.0, 0.0, INFINITY, 0, 0},                   /* > 0 */
    {"D", "1/Pa", "compressibility, bulk modulus = 2/D", 5.0e-9, 0.0, INFINITY, 0, 0}, /* > 0 */
};

/* Write a NUL-terminated message, cut to fit; returns `code`. */
static int32_t fail(char* message, uint64_t capacity, int32_t code, const char* text) {
    if (message != NULL && capacity > 0) {
        snprintf(message, (size_t)capacity, "%s", text);
    }
    return code;
}

/* sigma = (mu/J) dev(Bbar) + 2(J - 1)/D I; f and sigma are row-indexed: f[i][j] = F(i,j). */
static void cauchy_stress(double f[3][3], double mu, double d, double sigma[3][3]) {
    double minor_12_23 = f[1][1] * f[2][2] - f[2][1] * f[1][2];
    double minor_11_23 = f[1][0] * f[2][2] - f[2][0] * f[1][2];
    double minor_11_22 = f[1][0] * f[2][1] - f[2][0] * f[1][1];
    double j = f[0][0] * minor_12_23 - f[0][1] * minor_11_23 + f[0][2] * minor_11_22;
    double j_minus_third = 1.0 / cbrt(j);
    double f_bar[3][3], b_bar[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) f_bar[r][c] = f[r][c] * j_minus_third;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            b_bar[r][c] = f_bar[r][0] * f_bar[c][0] + f_bar[r][1] * f_bar[c][1] +
                          f_bar[r][2] * f_bar[c][2];
    double third_trace = (b_bar[0][0] + b_bar[1][1] + b_bar[2][2]) / 3.0;
    double pressure = 2.0 * (j - 1.0) / d;
    double scale = mu / j;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            double dev = (r == c) ? b_bar[r][c] - third_trace : b_bar[r][c];
            sigma[r][c] = dev * scale + ((r == c) ? pressure : 0.0);
        }
}

static int32_t update(const MusclefemPointBlock* block, char* message, uint64_t capacity) {
    if (block == NULL) return fail(message, capacity, 1, "the block pointer is NULL");
    if (block->struct_size < sizeof(MusclefemPointBlock))
        return fail(message, capacity, 1, "the host's block is smaller than this plugin's");
    if (block->property_count != 2 || block->properties == NULL)
        return fail(message, capacity, 1, "expected 2 properties (mu, D)");
    const double mu = block->properties[0];
    const double d = block->properties[1];
    for (uint64_t p = 0; p < block->point_count; ++p) {
        const double* fp = block->deformation_gradient_new + 9 * p;
        double f[3][3], sigma[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) f[i][j] = fp[i + 3 * j]; /* column-major input */
        cauchy_stress(f, mu, d, sigma);
        double* out = block->cauchy_stress + 6 * p; /* Voigt: xx, yy, zz, yz, xz, xy */
        out[0] = sigma[0][0];
        out[1] = sigma[1][1];
        out[2] = sigma[2][2];
        out[3] = sigma[1][2];
        out[4] = sigma[0][2];
        out[5] = sigma[0][1];
    }
    return 0;
}

static const MusclefemMaterialPlugin plugin = {
    MUSCLEFEM_MATERIAL_ABI_VERSION,
    (uint32_t)sizeof(MusclefemMaterialPlugin),
    "neo-hookean-c-plugin",
    "compressible neo-Hookean solid (C plugin example): W = mu/2 (I1bar - 3) + (J - 1)^2 / D",
    2,
    parameters,
    0,
    NULL,
    0, /* provides_tangent: the host uses finite differences */
    update,
};

MUSCLEFEM_EXPORT const MusclefemMaterialPlugin* musclefem_material_plugin(void) {
    return &plugin;
}

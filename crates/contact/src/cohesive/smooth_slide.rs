//! Smoothly sliding bonds ([`super::TangentialMode::SmoothSlide`]): as in FreeSlide the
//! surfaces slide freely and only the normal cohesion acts, but the gap and the direction
//! of the traction are measured along the smooth normal field of the main surface
//! ([`crate::normal_field`]: vertex normals, the projection along them, the walk across
//! edges and the tangent), so the force is a continuous function of the positions when a
//! node slides over the edges and vertices of the faceted main surface, concave ones
//! included (there the closest point of FreeSlide jumps between the faces, and so does its
//! force direction).
//!
//! - Every force evaluation walks from the bond's committed triangle (line-search trials
//!   see their own positions); search and commit move the bond's starting triangle to the
//!   one reached.
//! - Gap d = g |N| [m] and direction ν = N / |N|; opening δ_n = d − d₀, d₀ the gap at
//!   formation (the bond's rest state); normal traction t = t_n(δ_n) of the law [Pa], no
//!   shear; force on the secondary node f_s = A t ν [N] (A its area [m²]), −φ_k f_s on the
//!   corners of a deformable main triangle, −f_s on a rigid main.
//! - Tangent with the vertex normals held fixed ([`smooth_tangent`], t' = dt_n/dδ_n):
//!   exact for a rigid main; for a deformable main the turn of the normals with the nodes
//!   around the triangle is left out, a relative error of the order of the gap g over the
//!   element size, which costs Newton its quadratic rate, and its convergence once that
//!   ratio reaches ~10 (see `interface.rs`). It is not symmetric.

use nalgebra::{Isometry3, Matrix3, Vector3};
use rayon::prelude::*;

use super::bonds::{Bond, BondState};
use super::law::CohesiveLaw;
use crate::normal_field::{Foot, NormalField, smooth_tangent, walk};
use crate::surface::ContactTarget;

/// [`walk`] for every bond from its triangle, moving the bond to the triangle and the
/// foot reached; in parallel over fixed blocks of bonds (each on its own).
pub fn slide_all_smooth(
    bonds: &mut [Bond],
    main: &ContactTarget,
    field: &NormalField,
    at: (&[Vector3<f64>], &Isometry3<f64>),
) {
    bonds.par_iter_mut().with_min_len(64).for_each(|bond| {
        let x = at.0[bond.node as usize];
        let foot = walk(field, main, at, bond.node, bond.triangle, &x);
        bond.triangle = foot.triangle;
        bond.coordinates = foot.projection.barycentric;
    });
}

/// Evaluates every bond as a smoothly sliding bond ([`walk`] from its triangle, then
/// [`evaluate_smooth`]) into `states`; in parallel over fixed blocks of bonds, each state
/// depending on its bond only.
pub fn evaluate_all_smooth(
    bonds: &[Bond],
    law: &CohesiveLaw,
    main: &ContactTarget,
    field: &NormalField,
    at: (&[Vector3<f64>], &Isometry3<f64>),
    with_stiffness: bool,
    states: &mut [BondState],
) {
    states
        .par_iter_mut()
        .zip(bonds.par_iter())
        .with_min_len(64)
        .for_each(|(state, bond)| {
            let x = at.0[bond.node as usize];
            let foot = walk(field, main, at, bond.node, bond.triangle, &x);
            *state = evaluate_smooth(bond, law, &foot, with_stiffness);
        });
}

/// The smoothly sliding `bond` with its node projected at `foot`: f_s = A t_n(d − d₀) ν
/// and, `with_stiffness`, its tangent (see the module docs).
pub fn evaluate_smooth(
    bond: &Bond,
    law: &CohesiveLaw,
    foot: &Foot,
    with_stiffness: bool,
) -> BondState {
    let p = &foot.projection;
    let length = p.normal.norm();
    let direction = p.normal / length;
    let opening = p.gap() - bond.reference_separation.x;
    let response = law.evaluate(&Vector3::new(opening, 0.0, 0.0), bond.history);
    let traction = response.traction.x;
    let (coupling, coordinate_gradients) = if with_stiffness {
        let scalars = (bond.area * traction, bond.area * response.tangent[(0, 0)]);
        smooth_tangent(p, &direction, length, scalars)
    } else {
        ([Matrix3::zeros(); 4], [Matrix3::zeros(); 4])
    };
    BondState {
        force: bond.area * traction * direction,
        coupling,
        coordinate_gradients,
        turning: [Matrix3::zeros(); 3],
        turning_curvature: [[Matrix3::zeros(); 3]; 3],
        traction: -traction * direction,
        separation: Vector3::new(opening, 0.0, 0.0),
        triangle: foot.triangle,
        coordinates: p.barycentric,
        history: response.history,
        damage: response.damage,
        energy: bond.area * response.energy,
    }
}

#[cfg(test)]
mod tests;

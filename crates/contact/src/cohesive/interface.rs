//! [`CohesiveInterface`]: a secondary surface bonded to a main surface (deformable or
//! rigid) by the cohesive law, as an [`Interaction`] of the solvers.
//!
//! - Bonds form once, at construction (`bonds.rs`). In [`TangentialMode::Elastic`] a bond
//!   is a material-point bond: its main triangle and barycentric coordinates stay fixed
//!   for the run, so the shear separation is the relative displacement of two material
//!   points. That is exact for a tie with elastic shear, and right while the surfaces
//!   slide less than about a triangle; beyond that (tangential separations approaching
//!   the main mesh size) the bonded point should be re-projected, which the elastic shear
//!   law does not foresee (it would forget the shear separation). In
//!   [`TangentialMode::FreeSlide`] the shear traction is zero and the bonded point slides:
//!   every search moves it to the closest point of the main surface (`slide.rs`), so the
//!   normal separation stays the distance to the surface however far the surfaces slide.
//!   [`TangentialMode::SmoothSlide`] slides as well, but measures the gap and the force
//!   direction along the smooth field of averaged vertex normals of the main surface
//!   (`smooth_slide.rs`): every force evaluation walks from the bond's triangle to the
//!   foot of that projection, so the force is a continuous function of the positions,
//!   also where the closest point jumps (across a concave edge or vertex).
//! - Forces: material-point bonds (`bonds.rs`) f_s = A R t_law(Rᵀ δ) on the secondary
//!   node, R the frame of the main triangle; sliding bonds (`slide.rs`) f_s = A t_n(g) ν,
//!   g the gap to the surface, ν its direction; smoothly sliding bonds
//!   (`smooth_slide.rs`) f_s = A t_n(d) ν with d the gap along the interpolated normal N
//!   and ν = N/|N|; −ξ_k f_s on the corners of a deformable main triangle.
//! - Stiffness: the blocks ∂f/∂x of the node and the main triangle's corners. Material-point
//!   bonds: A R C Rᵀ times (1, −ξ_k) ⊗ (1, −ξ_l), holding R fixed, plus the turn of a
//!   rest offset (`bonds.rs`). For a rigid main R depends on time only: the tangent is
//!   consistent. For a deformable main the variation of R in Rᵀ δ is left out; that term
//!   vanishes in Elastic mode with K_nn = K_ss = K_tt while the bond is open
//!   (t = (1 − D) K δ does not depend on the frame), and otherwise costs Newton its
//!   quadratic rate, not its solution. Sliding
//!   bonds: the full linearization (`slide_tangent.rs`), with the turning of the main
//!   triangle (or of the direction ν about an edge) and the shift of the closest point,
//!   checked against finite differences over the face, interior edges and corners, and
//!   past the rim. The turning matters once the gap is comparable to the triangle size
//!   (its lever arm is g/h). Measured on two stacked blocks with a 12 × 12 interface
//!   (h = 0.83 mm) in FreeSlide, 9 load steps: gaps up to 12 h with a slide of 4 mm
//!   converge in 2–4 Newton iterations per step; a gap of 30 h with a slide of 2.3 mm did
//!   not converge, the closest points jumping between the faces of the deformed main
//!   surface's concave edges (the force direction jumps there). Openings in the muscle
//!   model are far below the element size (t/K_nn = 1 kPa / 5e7 N/m³ = 20 µm).
//!   Smoothly sliding bonds: the implicit differentiation of the projection with the
//!   vertex normals held fixed (`smooth_slide.rs`), exact for a rigid main; for a
//!   deformable main the turn of the normals with the nodes around the triangle is left
//!   out. That term grows with the opening and the rest gap over the element size h.
//!   Measured on two stacked blocks 10 × 10 × 5 mm with a 12 × 12 interface
//!   (h = 0.83 mm, E = 260 MPa), the lower block held at its bottom, the top of the upper
//!   one slid 2.3 mm and lifted, in 9 steps: lifted by 20 µm, 2–3 Newton iterations per
//!   step as in FreeSlide; lifted by 2 mm (2.4 h) across a rest gap of h, 3 to 8
//!   iterations (FreeSlide 3), and across 12 h no convergence (FreeSlide 3); with the
//!   whole lower block held (fixed normals) 2 iterations, as FreeSlide.
//! - [`Interaction::symmetric_stiffness`] is the law's: true in FreeSlide or with equal
//!   stiffnesses (the default), false otherwise (mixed-mode softening couples unequal
//!   stiffnesses asymmetrically); and false for bonds sliding on a deformable main, and
//!   in SmoothSlide.
//! - [`Interaction::commit`] stores each bond's damage history κ: damage never heals, and
//!   a trial that opens a bond further changes nothing until the step is accepted. A
//!   smoothly sliding bond also moves its starting triangle to the one its walk reached.

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{
    CheckpointReader, CheckpointWriter, Interaction, InteractionReport, NodalField, SolverError,
};
use nalgebra::{Matrix3, Vector3};

use super::bond_checkpoint::{restore_bonds, save_bonds};
use super::bonds::{Bond, BondState, closest_distance, evaluate_all, form_bonds};
use super::error::CohesiveError;
use super::law::CohesiveLaw;
use super::settings::{CohesiveSettings, TangentialMode};
use super::slide::{Neighbours, slide_all};
use super::smooth_slide::{evaluate_all_smooth, slide_all_smooth};
use crate::main_side::MainSide;
use crate::normal_field::NormalField;
use crate::surface::{ContactTarget, DeformableSurface};

/// A cohesive interface between two surfaces (see the module docs).
#[derive(Debug, Clone)]
pub struct CohesiveInterface {
    name: String,
    secondary: String,
    law: CohesiveLaw,
    main: ContactTarget,
    bonds: Vec<Bond>,
    states: Vec<BondState>,
    /// How the bonded points move.
    sliding: Sliding,
}

/// How the bonded points of a [`CohesiveInterface`] move on the main surface.
#[derive(Debug, Clone)]
enum Sliding {
    /// Material points ([`TangentialMode::Elastic`]).
    Fixed,
    /// To the closest point, by walks over the vertex rings of the main triangles
    /// ([`TangentialMode::FreeSlide`]).
    Closest(Neighbours),
    /// Along the smooth normal field of the main surface
    /// ([`TangentialMode::SmoothSlide`]).
    Smooth(NormalField),
}

impl CohesiveInterface {
    /// The interface `name` bonding the nodes of the `secondary` surface to the `main`
    /// surface (a [`DeformableSurface`] or a [`crate::RigidSurface`], placed at t = 0) of
    /// `mesh`, with `settings`.
    ///
    /// Errors if the settings are invalid, a surface names a node not in `mesh`, or no
    /// secondary node lies within the bond tolerance of the main surface
    /// ([`CohesiveError::NoBond`], with the closest distance found).
    pub fn new(
        name: &str,
        secondary: &DeformableSurface,
        main: impl Into<ContactTarget>,
        mesh: &Mesh,
        settings: &CohesiveSettings,
    ) -> Result<Self, CohesiveError> {
        let main = main.into();
        let law = CohesiveLaw::new(settings, name)?;
        let positions: Vec<Vector3<f64>> = (0..mesh.node_count())
            .map(|i| mesh.nodes.position(i))
            .collect();
        let outside = |surface: &str, nodes: &[u32]| {
            nodes
                .iter()
                .find(|&&n| n as usize >= positions.len())
                .map_or(Ok(()), |node| {
                    Err(CohesiveError::InvalidSurface {
                        interface: name.to_string(),
                        reason: format!(
                            "node {node} of surface '{surface}' is not in the mesh ({} nodes)",
                            positions.len()
                        ),
                    })
                })
        };
        outside(&secondary.name, &secondary.nodes)?;
        if let ContactTarget::Deformable(surface) = &main {
            outside(&surface.name, surface.triangles.as_flattened())?;
        }
        let tolerance = settings.bond_tolerance;
        let bonds = form_bonds(
            &secondary.nodes,
            &secondary.node_area,
            &main,
            &positions,
            tolerance,
        );
        if bonds.is_empty() {
            return Err(CohesiveError::NoBond {
                interface: name.to_string(),
                secondary: secondary.name.clone(),
                main: main.name().to_string(),
                nodes: secondary.nodes.len(),
                tolerance,
                closest: closest_distance(&secondary.nodes, &main, &positions),
            });
        }
        let sliding = match settings.tangential {
            TangentialMode::Elastic => Sliding::Fixed,
            TangentialMode::FreeSlide => Sliding::Closest(Neighbours::new(main.triangles())),
            TangentialMode::SmoothSlide => Sliding::Smooth(NormalField::new(&main, &positions)),
        };
        let states = bonds
            .iter()
            .map(|bond| BondState {
                triangle: bond.triangle,
                coordinates: bond.coordinates,
                ..BondState::default()
            })
            .collect();
        let mut interface = CohesiveInterface {
            name: name.to_string(),
            secondary: secondary.name.clone(),
            law,
            states,
            main,
            bonds,
            sliding,
        };
        if !matches!(interface.sliding, Sliding::Fixed) {
            // A sliding bond measures its gap as the distance to an edge or a vertex it
            // pivots about (FreeSlide) or along the smooth normal field (SmoothSlide), not
            // along the face normal: its rest gap is the gap it measures at the start
            // (and a smoothly sliding bond starts from the triangle its walk reached).
            for bond in &mut interface.bonds {
                bond.reference_separation = Vector3::zeros();
            }
            interface
                .forces(
                    0.0,
                    &positions,
                    false,
                    &mut vec![Vector3::zeros(); positions.len()],
                )
                .expect("evaluating cohesive bonds cannot fail");
            for (bond, state) in interface.bonds.iter_mut().zip(&interface.states) {
                bond.reference_separation = Vector3::new(state.separation.x, 0.0, 0.0);
                bond.triangle = state.triangle;
                bond.coordinates = state.coordinates;
            }
        }
        Ok(interface)
    }

    /// The names of the secondary and main surfaces.
    pub fn surfaces(&self) -> (&str, &str) {
        (&self.secondary, self.main.name())
    }

    /// The law.
    pub fn law(&self) -> &CohesiveLaw {
        &self.law
    }

    /// Number of bonds (secondary nodes bonded at the start).
    pub fn bond_count(&self) -> usize {
        self.bonds.len()
    }

    /// Total tributary area of the bonds [m²].
    pub fn bonded_reference_area(&self) -> f64 {
        self.bonds.iter().map(|b| b.area).sum()
    }

    /// The bonds as they formed: node, tributary area, main triangle, bonded point and
    /// rest separation.
    pub fn bonds(&self) -> &[Bond] {
        &self.bonds
    }

    /// The main surface.
    pub fn main(&self) -> &ContactTarget {
        &self.main
    }

    /// The bonded secondary nodes, in bond order.
    pub fn bonded_nodes(&self) -> impl Iterator<Item = u32> + '_ {
        self.bonds.iter().map(|b| b.node)
    }

    /// Per bond at the last force evaluation: (secondary node, local separation
    /// (δ_n, δ_s, δ_t) [m], damage D).
    pub fn bond_states(&self) -> impl Iterator<Item = (u32, Vector3<f64>, f64)> + '_ {
        self.bonds
            .iter()
            .zip(&self.states)
            .map(|(b, s)| (b.node, s.separation, s.damage))
    }

    /// The stiffness blocks of one bond, `add(a, b, K_ab)`, skipping zero blocks: with
    /// f_s the force on the secondary node s and f_k = −ξ_k f_s − T_kᵀ f_s on main corner
    /// k, K_sj = ∂f_s/∂x_j (`coupling`) and
    /// K_kj = −f_s ⊗ ∂ξ_k/∂x_j − ξ_k K_sj − T_kᵀ K_sj − ∂(T_kᵀ f_s)/∂x_j, over j = s and
    /// the corners.
    fn bond_stiffness(
        &self,
        bond: &Bond,
        state: &BondState,
        add: &mut dyn FnMut(u32, u32, &Matrix3<f64>),
    ) {
        let mut add_nonzero = |a: u32, b: u32, k: &Matrix3<f64>| {
            if k.iter().any(|&v| v != 0.0) {
                add(a, b, k);
            }
        };
        let Some(corners) = self.main.nodes(state.triangle as usize) else {
            add_nonzero(bond.node, bond.node, &state.coupling[0]);
            return;
        };
        let nodes = [bond.node, corners[0], corners[1], corners[2]];
        for (j, &column) in nodes.iter().enumerate() {
            add_nonzero(bond.node, column, &state.coupling[j]);
            for k in 0..3 {
                let shift = state.force * state.coordinate_gradients[j].row(k);
                let mut block = -shift
                    - state.coordinates[k] * state.coupling[j]
                    - state.turning[k].transpose() * state.coupling[j];
                if j > 0 {
                    block -= state.turning_curvature[k][j - 1];
                }
                add_nonzero(corners[k], column, &block);
            }
        }
    }
}

impl Interaction for CohesiveInterface {
    fn name(&self) -> &str {
        &self.name
    }

    /// Sliding bonds move to the closest point of the main surface (FreeSlide) or to the
    /// foot of their projection along its normal field (SmoothSlide), in parallel over
    /// blocks of bonds, each on its own; material-point bonds (Elastic) have nothing to
    /// search.
    fn search(&mut self, time: f64, positions: &[Vector3<f64>]) -> Result<(), SolverError> {
        let placement = self.main.placement(time);
        match &mut self.sliding {
            Sliding::Fixed => {}
            Sliding::Closest(neighbours) => slide_all(
                &mut self.bonds,
                &self.main,
                neighbours,
                positions,
                &placement,
            ),
            Sliding::Smooth(field) => {
                // The normals around the bonds' triangles (those the walks go on to are
                // computed as they go).
                field.update_around(
                    &self.main,
                    positions,
                    self.bonds.iter().map(|bond| bond.triangle),
                );
                slide_all_smooth(&mut self.bonds, &self.main, field, (positions, &placement));
            }
        }
        Ok(())
    }

    fn forces(
        &mut self,
        time: f64,
        positions: &[Vector3<f64>],
        with_stiffness: bool,
        force: &mut [Vector3<f64>],
    ) -> Result<(), SolverError> {
        let placement = self.main.placement(time);
        match &mut self.sliding {
            Sliding::Smooth(field) => {
                field.update_around(
                    &self.main,
                    positions,
                    self.bonds.iter().map(|bond| bond.triangle),
                );
                evaluate_all_smooth(
                    &self.bonds,
                    &self.law,
                    &self.main,
                    field,
                    (positions, &placement),
                    with_stiffness,
                    &mut self.states,
                );
            }
            sliding => evaluate_all(
                &self.bonds,
                &self.law,
                &self.main,
                positions,
                &placement,
                (matches!(sliding, Sliding::Closest(_)), with_stiffness),
                &mut self.states,
            ),
        }
        for (bond, state) in self.bonds.iter().zip(&self.states) {
            force[bond.node as usize] += state.force;
            if let Some(nodes) = self.main.nodes(state.triangle as usize) {
                for (k, node) in nodes.iter().enumerate() {
                    force[*node as usize] -= state.coordinates[k] * state.force
                        + state.turning[k].transpose() * state.force;
                }
            }
        }
        Ok(())
    }

    fn stiffness(&self, add: &mut dyn FnMut(u32, u32, &Matrix3<f64>)) {
        for (bond, state) in self.bonds.iter().zip(&self.states) {
            self.bond_stiffness(bond, state, add);
        }
    }

    /// On a deformable main, sliding bonds make the stiffness unsymmetric whatever the
    /// law: they push along the current normal of the main triangle, past its rim or over
    /// an edge that is not the gradient of a potential (`slide_tangent.rs`). Smoothly
    /// sliding bonds push along the interpolated normal, not the gradient of their gap:
    /// unsymmetric on any main (`smooth_slide.rs`). Material-point bonds, rest offsets
    /// included, are the gradient of an energy when the law is (`bonds.rs`).
    fn symmetric_stiffness(&self) -> bool {
        let unsymmetric_sliding = match self.sliding {
            Sliding::Fixed => false,
            Sliding::Closest(_) => matches!(self.main, ContactTarget::Deformable(_)),
            Sliding::Smooth(_) => true,
        };
        self.law.has_symmetric_tangent() && !unsymmetric_sliding
    }

    /// Stores each bond's damage history, and moves a smoothly sliding bond's starting
    /// triangle to the one its last walk reached.
    fn commit(&mut self) {
        let smooth = matches!(self.sliding, Sliding::Smooth(_));
        for (bond, state) in self.bonds.iter_mut().zip(&self.states) {
            bond.history = state.history;
            if smooth {
                bond.triangle = state.triangle;
                bond.coordinates = state.coordinates;
            }
        }
    }

    /// The bonds and their last evaluated states (`bond_checkpoint.rs`).
    fn save_state(&mut self, out: &mut CheckpointWriter) -> Result<(), SolverError> {
        save_bonds(&self.bonds, &self.states, out);
        Ok(())
    }

    fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        restore_bonds(&mut self.bonds, &mut self.states, input)
    }

    /// `force`: the force the interface exerts on the secondary surface, Σ −f_s [N] (for a
    /// rigid main, the resultant on all nodes; for a deformable main the main surface
    /// takes the opposite); `active_points`/`active_area`: bonds carrying a traction and
    /// their reference area; `bonded_area`: reference area of the bonds not failed
    /// (D < 1); `stored_energy`: Σ A ½ t·δ [J].
    fn report(&self) -> InteractionReport {
        let mut report = InteractionReport {
            name: self.name.clone(),
            ..InteractionReport::default()
        };
        for (bond, state) in self.bonds.iter().zip(&self.states) {
            report.force -= state.force;
            if state.force != Vector3::zeros() {
                report.active_points += 1;
                report.active_area += bond.area;
            }
            if state.damage < 1.0 {
                report.bonded_area += bond.area;
            }
            report.stored_energy += state.energy;
        }
        report
    }

    /// `cohesive_traction`: the traction on the secondary surface [Pa] (3 per node, the
    /// force per reference area that the interface exerts on the node: toward the main
    /// surface in tension); `cohesive_damage`: D (1 per node). Zero off the bonded nodes.
    fn nodal_fields(&self, node_count: usize) -> Vec<NodalField> {
        let mut traction = vec![0.0; 3 * node_count];
        let mut damage = vec![0.0; node_count];
        for (bond, state) in self.bonds.iter().zip(&self.states) {
            let n = bond.node as usize;
            traction[3 * n..3 * n + 3].copy_from_slice(state.traction.as_slice());
            damage[n] = state.damage;
        }
        vec![
            NodalField {
                name: "cohesive_traction".to_string(),
                components: 3,
                values: traction,
            },
            NodalField {
                name: "cohesive_damage".to_string(),
                components: 1,
                values: damage,
            },
        ]
    }
}

#[cfg(test)]
mod tests;

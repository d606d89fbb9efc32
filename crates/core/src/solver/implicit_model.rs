//! The implicit solver's discrete problem: the parts with their element chunks, the
//! equation numbers of the free degrees of freedom, the sparse stiffness and its scatter
//! maps, and the evaluation of internal forces, residual and stiffness at given positions
//! (elements in parallel chunks, everything gathered serially in element order, so the
//! result does not depend on the number of threads).

use std::time::Instant;

use nalgebra::Vector3;
use rayon::prelude::*;

use musclefem_materials::Material;

use super::amg_cg::LinearSolver;
use super::chunk::chunk_ranges;
use super::element_fields::{AcceptedPoints, PartFields, part_fields};
use super::implicit_chunk::{ImplicitChunk, StiffnessWork};
use super::implicit_dynamics::Inertia;
use super::implicit_settings::ImplicitSettings;
use super::interaction::Interaction;
use super::sparse::{PRESCRIBED, SparseSystem};
use super::{Loads, Part, RigidReaction, SolverError};
use crate::element::BlockKernel;
use crate::mesh::{ElementBlock, Mesh};

/// One part during a run.
pub(super) struct PartRun<'a> {
    pub block: usize,
    pub kernel: BlockKernel,
    pub material: &'a dyn Material,
    pub chunks: Vec<ImplicitChunk>,
    /// Where each element's stiffness goes: for element e, column c = 3b + k of its
    /// matrix and node a, the position in the sparse values of the first free degree of
    /// freedom of node a in the column of (b, k) (the node's free rows follow it), or
    /// [`PRESCRIBED`] when (b, k) is prescribed or node a is held in every direction.
    pub scatter: Vec<u32>,
}

/// The discrete problem: parts, equation numbers, the sparse system and work vectors.
pub(super) struct Model<'a> {
    pub mesh: &'a Mesh,
    pub runs: Vec<PartRun<'a>>,
    /// Equation of each degree of freedom 3 node + dof, or [`PRESCRIBED`].
    pub equation: Vec<u32>,
    pub system: SparseSystem,
    /// Internal forces of all nodes [N].
    pub force: Vec<Vector3<f64>>,
    /// External nodal forces at the end of the step being solved [N].
    pub external: Vec<Vector3<f64>>,
    /// Residual of the free degrees of freedom [N].
    pub residual: Vec<f64>,
    /// K_fp Δū of the predictor [N].
    pub lift: Vec<f64>,
    pub symmetric: bool,
    /// Positions of the diagonal entries in the sparse values.
    pub diagonal: Vec<usize>,
    /// Largest |K_ii| of the last stiffness [N/m].
    pub stiffness_scale: f64,
    /// Largest |x| of the last evaluation's positions [m].
    pub position_scale: f64,
    pub times: EvaluationTimes,
    /// Lumped mass and Newmark state of a dynamic run (`None`: quasi-static).
    pub inertia: Option<Inertia>,
    /// Whether an indefinite tangent is solved with a larger mass term
    /// ([`super::implicit::ImplicitSettings::mass_shift_for_indefinite_tangents`]), and
    /// each equation's mass term m/(β Δt²) at the last evaluation with stiffness [N/m].
    pub mass_shift: bool,
    pub mass_diagonal: Vec<f64>,
    /// Inertial forces M a⁺ at the last evaluation [N] (zero when quasi-static).
    pub inertial: Vec<Vector3<f64>>,
    /// Reference positions of the nodes [m].
    pub reference: Vec<Vector3<f64>>,
    /// Contact and cohesion, evaluated with the elements (`implicit_interactions.rs`).
    pub interactions: &'a mut [Box<dyn Interaction>],
    /// Node pairs coupled by interactions beyond the elements, all in the pattern
    /// (sorted; the pattern only grows).
    pub coupled_pairs: Vec<(u32, u32)>,
    /// Threshold of parallel factorizations [unknowns] (kept for rebuilding the system).
    pub parallel_factorization_unknowns: usize,
    /// Whether the last evaluation asked for the stiffness and it is not built yet.
    pub stiffness_due: bool,
    /// Positions [m] and prescribed increments Δū [m] (the predictor's) of the last
    /// evaluation with stiffness.
    pub stiffness_positions: Vec<Vector3<f64>>,
    pub stiffness_delta: Option<Vec<f64>>,
    /// Where each column's entries start in the sparse values (column pointers).
    pub column_starts: Vec<usize>,
    /// Room for the element matrices of a few chunks at a time (`implicit_stiffness.rs`).
    pub stiffness_work: Vec<StiffnessWork>,
    /// Why the last stiffness could not be built (a material error while its tangents
    /// were computed), reported by the next [`Self::solve`].
    pub stiffness_failure: Option<SolverError>,
}

/// Counts and wall-clock times [s] of a run's evaluations.
#[derive(Debug, Clone, Default)]
pub struct EvaluationTimes {
    /// Evaluations of the internal forces (with or without stiffness).
    pub evaluations: usize,
    /// Stiffness matrices built (at most one per evaluation; none at the evaluations
    /// where Newton converged).
    pub stiffness_builds: usize,
    /// Element updates in parallel: deformation, material, nodal forces, and for the
    /// stiffness the material tangents and element matrices.
    pub element_seconds: f64,
    /// Of `element_seconds`, the element stiffness matrices (the rest: deformation,
    /// material, forces).
    pub stiffness_seconds: f64,
    /// Serial gathering of the forces and scattering of the stiffness into the matrix.
    pub assembly_seconds: f64,
}

/// Factor on the round-off estimate of the residual (see [`Norms::floor`]).
const ROUND_OFF_FACTOR: f64 = 10.0;

/// Norms of one evaluation.
#[derive(Debug, Clone, Copy)]
pub(super) struct Norms {
    /// ‖r_f‖ [N].
    pub residual: f64,
    /// max(‖f_int‖, ‖f_ext‖) over all degrees of freedom [N].
    pub force: f64,
    /// Round-off level of ‖r_f‖ [N]: F = Σ x_a ⊗ ∇N_a carries errors ε|x|/h, so nodal
    /// forces carry ε |x| K_ii; the floor is 10 ε max|x| max|K_ii| √n. For a nearly
    /// incompressible material at small loads it lies above tol_r ‖f_int‖.
    pub floor: f64,
}

/// How far the round-off floor may grow within one step before a state's own floor stops
/// counting (see [`Norms::is_at_round_off`]).
const FLOOR_GROWTH: f64 = 2.0;

impl Norms {
    /// Whether ‖r_f‖ is at its round-off floor, the floor taken no larger than
    /// [`FLOOR_GROWTH`] times the floor at the step's start (`start`). Within a converging
    /// step the floor hardly changes; a diverging iterate's does: near-inverted elements
    /// raise max|K_ii| by orders of magnitude, and with its own floor the line search took
    /// residuals of 1e8–1e18 N as round-off (the coarse active squat, 2026-11-24).
    pub fn is_at_round_off(self, start: Norms) -> bool {
        self.residual <= self.floor.min(FLOOR_GROWTH * start.floor)
    }

    pub fn relative(self) -> f64 {
        if self.residual == 0.0 {
            0.0
        } else {
            self.residual / self.force
        }
    }
}

/// The scatter map of a block (see [`PartRun::scatter`]).
fn scatter_map(block: &ElementBlock, equation: &[u32], system: &SparseSystem) -> Vec<u32> {
    let npe = block.shape.nodes_per_element();
    let mut map = Vec::with_capacity(block.len() * 3 * npe * npe);
    for ids in block.elements() {
        for &b in ids {
            for k in 0..3 {
                let column = equation[3 * b as usize + k];
                for &a in ids {
                    let rows = &equation[3 * a as usize..3 * a as usize + 3];
                    let first = rows.iter().find(|&&r| r != PRESCRIBED);
                    map.push(match (column, first) {
                        (PRESCRIBED, _) | (_, None) => PRESCRIBED,
                        (column, Some(&row)) => {
                            system.position(row as usize, column as usize) as u32
                        }
                    });
                }
            }
        }
    }
    map
}

impl<'a> Model<'a> {
    pub fn new(
        mesh: &'a Mesh,
        parts: &'a [Part],
        loads: &Loads,
        interactions: &'a mut [Box<dyn Interaction>],
        parallel_factorization_unknowns: usize,
        mixed_pressure_tangent: bool,
    ) -> Result<Self, SolverError> {
        let node_count = mesh.nodes.len();
        let mut runs = Vec::with_capacity(parts.len());
        let mut used = vec![false; node_count];
        for part in parts {
            let block = mesh
                .blocks
                .get(part.block)
                .ok_or_else(|| SolverError::InvalidPart {
                    block: part.block,
                    reason: format!("the mesh has {} blocks", mesh.blocks.len()),
                })?;
            let kernel =
                BlockKernel::new(&mesh.nodes, block, part.technology).map_err(|source| {
                    SolverError::Element {
                        block: part.block,
                        cause: source,
                    }
                })?;
            if !kernel.has_consistent_tangent() {
                return Err(SolverError::NoConsistentTangent {
                    block: part.block,
                    technology: part.technology,
                });
            }
            for &id in &block.connectivity {
                used[id as usize] = true;
            }
            let material = part.material.as_ref();
            let chunks = chunk_ranges(block.len())
                .map(|range| {
                    ImplicitChunk::new(range, &kernel, block, material, mixed_pressure_tangent)
                })
                .collect();
            runs.push(PartRun {
                block: part.block,
                kernel,
                material,
                chunks,
                scatter: Vec::new(),
            });
        }
        loads.validate(node_count)?;
        let is_prescribed = loads.constrained_components(node_count);
        let mut equation = vec![PRESCRIBED; 3 * node_count];
        let mut free = 0u32;
        for (d, e) in equation.iter_mut().enumerate() {
            if is_prescribed[d] {
                continue;
            }
            if !used[d / 3] {
                return Err(SolverError::InvalidPart {
                    block: parts.first().map_or(0, |p| p.block),
                    reason: format!(
                        "node {} belongs to no element of any part and is not held: \
                         nothing resists its motion",
                        d / 3
                    ),
                });
            }
            *e = free;
            free += 1;
        }
        let free = free as usize;
        let reference: Vec<Vector3<f64>> =
            (0..node_count).map(|n| mesh.nodes.position(n)).collect();
        let mut model = Model {
            mesh,
            runs,
            equation,
            system: SparseSystem::new(&[], &[], 0, std::iter::empty(), &[], usize::MAX),
            force: vec![Vector3::zeros(); node_count],
            external: vec![Vector3::zeros(); node_count],
            residual: vec![0.0; free],
            lift: vec![0.0; free],
            symmetric: true,
            diagonal: Vec::new(),
            stiffness_scale: 0.0,
            position_scale: 0.0,
            times: EvaluationTimes::default(),
            inertia: None,
            mass_shift: false,
            mass_diagonal: Vec::new(),
            inertial: vec![Vector3::zeros(); node_count],
            reference,
            interactions,
            coupled_pairs: Vec::new(),
            parallel_factorization_unknowns,
            stiffness_due: false,
            stiffness_positions: Vec::new(),
            stiffness_delta: None,
            column_starts: Vec::new(),
            stiffness_work: Vec::new(),
            stiffness_failure: None,
        };
        model
            .build_system()
            .map_err(|reason| SolverError::InvalidPart {
                block: parts.first().map_or(0, |p| p.block),
                reason,
            })?;
        Ok(model)
    }

    /// (Re)builds the sparse pattern from the elements and [`Self::coupled_pairs`], with
    /// the scatter maps and diagonal positions; carries the solve statistics over.
    pub fn build_system(&mut self) -> Result<(), String> {
        let mesh = self.mesh;
        let mut system = SparseSystem::new(
            &self.reference,
            &self.equation,
            self.residual.len(),
            self.runs.iter().map(|r| &mesh.blocks[r.block]),
            &self.coupled_pairs,
            self.parallel_factorization_unknowns,
        );
        if system.entries() >= PRESCRIBED as usize {
            return Err(format!(
                "the stiffness would have {} entries, more than 2^32 - 1",
                system.entries()
            ));
        }
        system.continue_statistics(&self.system);
        for run in &mut self.runs {
            run.scatter = scatter_map(&mesh.blocks[run.block], &self.equation, &system);
        }
        self.diagonal = (0..self.residual.len())
            .map(|i| system.position(i, i))
            .collect();
        self.column_starts = system.column_starts().to_vec();
        self.system = system;
        Ok(())
    }

    /// Internal forces at `positions`, materials updated over the step of `dt` ending at
    /// `time`. With `with_stiffness` the materials' tangents are kept and the stiffness of
    /// the free degrees of freedom (with `delta`, also the lift K_fp Δū) at these positions
    /// becomes due: [`Self::ensure_stiffness`] builds it when a solve or a round-off test
    /// needs it, so that the evaluation at which Newton converges builds none. With
    /// interactions it is built at once (their search and forces go with it). Elements
    /// update in parallel chunks; everything is gathered serially in element order.
    ///
    /// The returned norms' round-off floor is that of the last stiffness built: call
    /// [`Self::ensure_stiffness`] and [`Self::norms`] before testing against it.
    pub fn evaluate(
        &mut self,
        positions: &[Vector3<f64>],
        time: f64,
        dt: f64,
        with_stiffness: bool,
        delta: Option<&[f64]>,
    ) -> Result<Norms, SolverError> {
        self.force.fill(Vector3::zeros());
        self.lift.fill(0.0);
        self.stiffness_due = false;
        // A failure belongs to the stiffness of the evaluation before; none is due now.
        self.stiffness_failure = None;
        let mesh = self.mesh;
        let start = Instant::now();
        let mut element_seconds = 0.0;
        for run in &mut self.runs {
            let update_start = Instant::now();
            let block = &mesh.blocks[run.block];
            let (kernel, material) = (&run.kernel, run.material);
            run.chunks
                .par_iter_mut()
                .try_for_each(|chunk| chunk.update(kernel, block, material, positions, time, dt))
                .map_err(|(element, source)| SolverError::Material {
                    time,
                    block: block.name.clone(),
                    element,
                    cause: source,
                })?;
            element_seconds += update_start.elapsed().as_secs_f64();
            let npe = kernel.nodes_per_element();
            for chunk in &run.chunks {
                for (local, element) in chunk.elements().enumerate() {
                    let ids = block.element_nodes(element);
                    for (&id, f) in ids
                        .iter()
                        .zip(&chunk.forces()[local * npe..(local + 1) * npe])
                    {
                        self.force[id as usize] += f;
                    }
                }
            }
        }
        self.times.element_seconds += element_seconds;
        self.times.assembly_seconds += start.elapsed().as_secs_f64() - element_seconds;
        if with_stiffness {
            self.stiffness_positions.clear();
            self.stiffness_positions.extend_from_slice(positions);
            self.stiffness_delta = delta.map(<[f64]>::to_vec);
            self.stiffness_due = true;
        }
        let start = Instant::now();
        if !self.interactions.is_empty() {
            if with_stiffness {
                self.scatter_element_stiffness()?;
            }
            if !self.add_interactions(positions, time, with_stiffness, delta)? {
                // New node pairs were coupled: evaluate again on the grown pattern.
                return self.evaluate(positions, time, dt, with_stiffness, delta);
            }
            if with_stiffness {
                self.finish_stiffness();
            }
        }
        if let Some(inertia) = &self.inertia {
            for (node, (f, (x, x0))) in self
                .inertial
                .iter_mut()
                .zip(positions.iter().zip(&self.reference))
                .enumerate()
            {
                *f = inertia.force(node, &(x - x0));
            }
        }
        for (d, &eq) in self.equation.iter().enumerate() {
            if eq != PRESCRIBED {
                self.residual[eq as usize] = self.force[d / 3][d % 3] + self.inertial[d / 3][d % 3]
                    - self.external[d / 3][d % 3];
            }
        }
        self.position_scale = positions.iter().fold(0.0, |m, x| m.max(x.amax()));
        self.times.evaluations += 1;
        self.times.assembly_seconds += start.elapsed().as_secs_f64();
        Ok(self.norms())
    }

    pub fn norms(&self) -> Norms {
        Norms {
            residual: self.residual.iter().map(|r| r * r).sum::<f64>().sqrt(),
            force: self
                .force
                .iter()
                .map(|f| f.norm_squared())
                .sum::<f64>()
                .max(self.external.iter().map(|f| f.norm_squared()).sum::<f64>())
                .max(self.inertial.iter().map(|f| f.norm_squared()).sum::<f64>())
                .sqrt(),
            floor: ROUND_OFF_FACTOR
                * f64::EPSILON
                * self.stiffness_scale
                * self.position_scale
                * (self.residual.len() as f64).sqrt(),
        }
    }

    /// A step starts (or restarts) from the last converged state.
    pub fn start_step(&mut self) {
        for run in &mut self.runs {
            run.chunks.iter_mut().for_each(ImplicitChunk::start_step);
        }
    }

    /// Solve K x = `rhs` with the stiffness last evaluated, in place; an iterative solve
    /// may stop at the relative residual `forcing` (Newton's forcing term, 0: the
    /// solver's own tolerance).
    pub fn solve(
        &mut self,
        rhs: &mut [f64],
        time: f64,
        settings: &ImplicitSettings,
        forcing: f64,
    ) -> Result<super::sparse::Factorization, SolverError> {
        self.ensure_stiffness();
        if let Some(failure) = self.stiffness_failure.take() {
            return Err(failure);
        }
        self.system.set_forcing(forcing);
        let size = self.residual.len();
        let iterative = match settings.linear_solver {
            LinearSolver::Direct => None,
            LinearSolver::AmgCg => Some(settings.amg_cg.clone()),
            LinearSolver::Auto => {
                (size >= settings.amg_cg.auto_unknowns).then(|| settings.amg_cg.clone())
            }
        };
        self.system.set_iterative(iterative);
        let reuse = settings.factor_reuse.as_ref();
        for run in &mut self.runs {
            run.chunks
                .iter_mut()
                .for_each(ImplicitChunk::stiffness_solved);
        }
        let mass_shift = (self.mass_shift && self.inertia.is_some())
            .then_some((self.diagonal.as_slice(), self.mass_diagonal.as_slice()));
        self.system
            .solve(rhs, self.symmetric, reuse, mass_shift)
            .map_err(|reason| SolverError::LinearSolve { time, reason })
    }

    /// u = base + α δu on the free degrees of freedom (prescribed ones unchanged).
    pub fn apply(
        &self,
        displacement: &mut [Vector3<f64>],
        base: &[Vector3<f64>],
        direction: &[f64],
        alpha: f64,
    ) {
        for (d, &eq) in self.equation.iter().enumerate() {
            if eq != PRESCRIBED {
                displacement[d / 3][d % 3] = base[d / 3][d % 3] + alpha * direction[eq as usize];
            }
        }
    }

    /// Per-element output fields of every part at the last accepted step, ending at
    /// `time` [s].
    pub fn fields(&self, time: f64) -> Result<Vec<PartFields>, SolverError> {
        self.runs
            .iter()
            .map(|run| {
                let points: Vec<AcceptedPoints> = run
                    .chunks
                    .iter()
                    .map(ImplicitChunk::accepted_points)
                    .collect();
                part_fields(self.mesh, run.block, run.material, time, &points)
            })
            .collect()
    }

    /// Forces the supports take on the prescribed components, f_int + M a − f_ext (zero on
    /// free components) [N].
    pub fn support_forces(&self) -> Vec<Vector3<f64>> {
        (0..self.force.len())
            .map(|n| {
                Vector3::from_fn(|k, _| {
                    if self.equation[3 * n + k] == PRESCRIBED {
                        self.force[n][k] + self.inertial[n][k] - self.external[n][k]
                    } else {
                        0.0
                    }
                })
            })
            .collect()
    }

    /// Nodal reactions f_int + M a − f_ext on the prescribed components (zero on free ones)
    /// [N], summed over each prescribed displacement's nodes in its direction, and the
    /// resultant of each rigid tie at time `time` and nodal `positions`.
    pub fn reactions(
        &self,
        loads: &Loads,
        time: f64,
        positions: &[Vector3<f64>],
    ) -> (Vec<f64>, Vec<RigidReaction>) {
        let reaction = self.support_forces();
        (
            loads.displacement_reactions(&reaction),
            loads.rigid_reactions(time, positions, &reaction),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::Norms;

    fn norms(residual: f64, floor: f64) -> Norms {
        Norms {
            residual,
            force: 1.0,
            floor,
        }
    }

    #[test]
    fn a_state_at_its_floor_is_at_round_off_while_the_floor_stays_near_the_starts() {
        let start = norms(10.0, 1.0);
        assert!(norms(0.9, 1.0).is_at_round_off(start));
        assert!(norms(1.9, 1.95).is_at_round_off(start));
        assert!(!norms(1.1, 1.0).is_at_round_off(start));
    }

    #[test]
    fn a_diverging_state_whose_floor_exploded_is_not_at_round_off() {
        // The coarse active squat: a trial near inversion, residual 1e18 N, floor above it.
        let start = norms(10.0, 1e-6);
        assert!(!norms(1e18, 1e19).is_at_round_off(start));
        assert!(!norms(3e-6, 1e-5).is_at_round_off(start));
    }
}

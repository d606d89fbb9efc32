//! Explicit central-difference time integration with lumped mass (the paper's method).
//!
//! With M the lumped (diagonal) mass, f the internal nodal forces and half-step velocities:
//! - v^{n+½} = v^{n−½} + Δt^n M⁻¹ (f_ext^n − f^n), Δt^n = ½ (Δt^{n−½} + Δt^{n+½});
//! - u^{n+1} = u^n + Δt^{n+½} v^{n+½};
//! - prescribed displacement components take v^{n+½} = (ū(t^{n+1}) − u^n)/Δt^{n+½}.
//!
//! The step is Δt = safety × min over elements of L₀ √(ρ₀/M): total Lagrangian, so the
//! reference characteristic length L₀ (Flanagan–Belytschko bound from the element's mean
//! shape-function gradients, h/√3 for a cube of side h) and density ρ₀ with the current
//! acoustic modulus M, the largest eigenvalue of the acoustic tensor
//! Q_ik = ∂P_iJ/∂F_kL n_J n_L over n = e_x, e_y, e_z at the element's first integration
//! point, refreshed from the material tangent every [`MODULUS_REFRESH_INTERVAL`] steps.
//! Stiffening in between is covered by the safety factor and, should it not suffice,
//! caught by the energy balance.
//!
//! Energies (trapezoidal rule over each step): internal W_int = Σ ½(f^{n−1} + f^n)·Δu,
//! external W_ext = Σ ½(R^{n−1} + R^n)·Δu over the prescribed components, whose force is
//! the reaction R = f + M a; kinetic K = ½ Σ m |v^n|², v^n = ½ (v^{n−½} + v^{n+½}).
//! The total W_int + K − W_ext must stay at its value after the first step within a
//! fraction of the largest energy reached so far, or within 10× the energies of the first
//! step (the start-up error of the half-step velocities is of that size, and matters while
//! the energies are still small); an instability grows past both quickly.
//!
//! The hourglass forces of the one-point hex8 are part of its internal forces, so their
//! work is in W_int (`BlockKernel::hourglass_energy` gives it per element; the history does
//! not report it separately yet).
//!
//! Not built yet: mass scaling, bulk viscosity, a separate hourglass energy in the
//! history, nodal loads, rigid bodies.

use nalgebra::Vector3;
use rayon::prelude::*;

use musclefem_materials::Material;

use super::assembly::NodeAdjacency;
use super::chunk::{ELEMENTS_PER_CHUNK, ElementChunk, chunk_ranges};
use super::hex8_one_point_chunk::OnePointHexChunk;
use super::nodal::{NODES_PER_TASK, advance_positions, deterministic_sum, update_velocities};
use super::{Part, PrescribedDisplacement, SolverError};
use crate::element::{BlockKernel, Technology};
use crate::mesh::{ElementShape, Mesh};

/// Settings of an explicit run.
#[derive(Debug, Clone, PartialEq)]
pub struct ExplicitSettings {
    /// End of the step [s] (the run starts at t = 0).
    pub end_time: f64,
    /// Fraction of the stable step taken (0 < safety ≤ 1), default 0.9.
    pub safety_factor: f64,
    /// A fixed step instead of the stable one [s]; refused if above the stable step.
    pub fixed_time_step: Option<f64>,
    /// A history row is recorded every this many seconds, and at the end.
    pub history_interval: f64,
    /// Largest allowed |W_int + K − W_ext| relative to the largest energy, default 0.01.
    pub energy_tolerance: f64,
}

impl ExplicitSettings {
    /// Defaults for a run to `end_time`: safety 0.9, 100 history rows, 1 % energy balance.
    pub fn new(end_time: f64) -> Self {
        ExplicitSettings {
            end_time,
            safety_factor: 0.9,
            fixed_time_step: None,
            history_interval: end_time / 100.0,
            energy_tolerance: 0.01,
        }
    }
}

/// One recorded instant of an explicit run.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryRow {
    /// Time [s].
    pub time: f64,
    /// Step taken to reach it [s].
    pub time_step: f64,
    /// Reaction force of each prescribed displacement, in its direction, summed over its
    /// nodes [N].
    pub reactions: Vec<f64>,
    /// Internal (strain) energy W_int [J].
    pub internal_energy: f64,
    /// Kinetic energy K [J].
    pub kinetic_energy: f64,
    /// External work W_ext [J].
    pub external_work: f64,
}

/// What an explicit run returns.
#[derive(Debug, Clone)]
pub struct ExplicitResult {
    pub history: Vec<HistoryRow>,
    /// Nodal displacements at the end [m].
    pub displacement: Vec<Vector3<f64>>,
    /// Time steps taken.
    pub steps: usize,
}

/// Steps between refreshes of the elements' acoustic moduli (stable step).
pub const MODULUS_REFRESH_INTERVAL: usize = 10;

/// One part during a run: its material, density, element chunks and node adjacency.
struct PartRun<'a> {
    block: usize,
    name: &'a str,
    material: &'a dyn Material,
    density: f64,
    elements: PartElements,
    /// Node → element force slots, for the assembly.
    adjacency: NodeAdjacency,
    /// Smallest stable step of the part [s] and its element, from the last refresh.
    stable: (f64, usize),
}

/// The element data of a part.
enum PartElements {
    /// Any technology: the general kernel and chunks (forces in the chunks).
    General {
        kernel: BlockKernel,
        chunks: Vec<ElementChunk>,
    },
    /// One-point hex8: the batched kernel, and the nodal forces of all elements, 8 per
    /// element, in element order [N].
    OnePointHex {
        chunks: Vec<OnePointHexChunk>,
        forces: Vec<Vector3<f64>>,
    },
}

/// Run the explicit solver on `mesh` with `parts` and `prescribed` displacements.
pub fn run_explicit(
    mesh: &Mesh,
    parts: &[Part],
    prescribed: &[PrescribedDisplacement],
    settings: &ExplicitSettings,
) -> Result<ExplicitResult, SolverError> {
    check_settings(settings)?;
    let node_count = mesh.nodes.len();
    let mut runs = Vec::with_capacity(parts.len());
    let mut mass = vec![0.0; node_count];
    for part in parts {
        runs.push(prepare_part(mesh, part, &mut mass)?);
    }
    for bc in prescribed {
        if bc.dof > 2 {
            return Err(SolverError::InvalidBoundaryCondition(format!(
                "component {} is not 0, 1 or 2",
                bc.dof
            )));
        }
        if let Some(&n) = bc.nodes.iter().find(|&&n| n as usize >= node_count) {
            return Err(SolverError::InvalidBoundaryCondition(format!(
                "node {n} does not exist (the mesh has {node_count})"
            )));
        }
    }
    if let Some(n) = mass.iter().position(|&m| m <= 0.0) {
        return Err(SolverError::InvalidPart {
            block: parts.first().map_or(0, |p| p.block),
            reason: format!("node {n} belongs to no element of any part: it has no mass"),
        });
    }

    let reference: Vec<Vector3<f64>> = (0..node_count).map(|i| mesh.nodes.position(i)).collect();
    let mut displacement = vec![Vector3::zeros(); node_count];
    let mut positions = reference.clone();
    let mut velocity = vec![Vector3::zeros(); node_count];
    let mut old_velocity = vec![Vector3::zeros(); node_count];
    let mut force = vec![Vector3::zeros(); node_count];
    let mut previous_force = vec![Vector3::zeros(); node_count];
    let mut previous_displacement = vec![Vector3::zeros(); node_count];
    let mut reactions = vec![0.0; prescribed.len()];
    let mut previous_reactions = vec![0.0; prescribed.len()];

    let mut time = 0.0;
    let (mut stable_step, mut critical) =
        internal_forces(mesh, &mut runs, &positions, time, 0.0, true, &mut force)?;
    let mut half_step = 0.0;
    let (mut internal_energy, mut external_work) = (0.0, 0.0);
    let mut initial_balance = None;
    let mut startup_energy = None;
    let mut largest_energy: f64 = 0.0;
    let mut history = Vec::new();
    let mut next_record = 0.0;
    let mut steps = 0;

    while time < settings.end_time * (1.0 - 1e-12) {
        let stable = stable_step;
        let mut dt = stable * settings.safety_factor;
        if let Some(fixed) = settings.fixed_time_step {
            if fixed > stable {
                return Err(SolverError::UnstableTimeStep {
                    requested: fixed,
                    stable,
                    block: critical.0.to_string(),
                    element: critical.1,
                });
            }
            dt = fixed;
        }
        dt = dt.min(settings.end_time - time);
        let average_step = 0.5 * (half_step + dt);

        // Velocities at n + ½: free components from the forces, prescribed from ū.
        update_velocities(
            &mut velocity,
            &mut old_velocity,
            &force,
            &mass,
            average_step,
        );
        for bc in prescribed {
            let target = bc.amplitude.value_at(time + dt);
            for &n in &bc.nodes {
                let n = n as usize;
                velocity[n][bc.dof] = (target - displacement[n][bc.dof]) / dt;
            }
        }
        // Reactions at n: R = f + m a on the prescribed components.
        for (r, bc) in reactions.iter_mut().zip(prescribed) {
            *r = bc
                .nodes
                .iter()
                .map(|&n| {
                    let n = n as usize;
                    let acceleration = if average_step > 0.0 {
                        (velocity[n][bc.dof] - old_velocity[n][bc.dof]) / average_step
                    } else {
                        0.0
                    };
                    force[n][bc.dof] + mass[n] * acceleration
                })
                .sum();
        }
        // Energies at n.
        internal_energy += deterministic_sum(node_count, |i| {
            0.5 * (previous_force[i] + force[i]).dot(&(displacement[i] - previous_displacement[i]))
        });
        external_work += prescribed
            .iter()
            .zip(reactions.iter().zip(&previous_reactions))
            .map(|(bc, (r, r_old))| {
                let moved = bc.amplitude.value_at(time) - bc.amplitude.value_at(time - half_step);
                0.5 * (r + r_old) * moved
            })
            .sum::<f64>();
        let kinetic_energy = deterministic_sum(node_count, |i| {
            0.5 * mass[i] * (0.5 * (old_velocity[i] + velocity[i])).norm_squared()
        });
        let total = internal_energy + kinetic_energy - external_work;
        let drift = total - *initial_balance.get_or_insert(total);
        largest_energy = largest_energy
            .max(internal_energy.abs())
            .max(kinetic_energy)
            .max(external_work.abs());
        let startup = *startup_energy.get_or_insert(largest_energy);
        if drift.abs() > (settings.energy_tolerance * largest_energy).max(10.0 * startup) {
            return Err(SolverError::EnergyBalance {
                time,
                error: drift,
                relative: 100.0 * drift.abs() / largest_energy,
                limit: 100.0 * settings.energy_tolerance,
            });
        }
        if time >= next_record {
            history.push(HistoryRow {
                time,
                time_step: half_step,
                reactions: reactions.clone(),
                internal_energy,
                kinetic_energy,
                external_work,
            });
            next_record += settings.history_interval;
        }
        // A non-finite velocity makes K non-finite: look for it only then.
        if !kinetic_energy.is_finite()
            && let Some(node) = velocity
                .iter()
                .position(|v| !v.iter().all(|x| x.is_finite()))
        {
            return Err(SolverError::Diverged { time, node });
        }

        // Positions at n + 1 and forces there.
        std::mem::swap(&mut previous_force, &mut force);
        previous_reactions.copy_from_slice(&reactions);
        advance_positions(
            &mut displacement,
            &mut previous_displacement,
            &mut positions,
            &reference,
            &velocity,
            dt,
        );
        time += dt;
        half_step = dt;
        steps += 1;
        let refresh = steps % MODULUS_REFRESH_INTERVAL == 0;
        (stable_step, critical) =
            internal_forces(mesh, &mut runs, &positions, time, dt, refresh, &mut force)?;
        runs.iter_mut().for_each(PartRun::commit);
    }
    history.push(HistoryRow {
        time,
        time_step: half_step,
        reactions: reactions.clone(),
        internal_energy,
        kinetic_energy: 0.5
            * (0..node_count)
                .map(|i| mass[i] * velocity[i].norm_squared())
                .sum::<f64>(),
        external_work,
    });
    Ok(ExplicitResult {
        history,
        displacement,
        steps,
    })
}

fn check_settings(settings: &ExplicitSettings) -> Result<(), SolverError> {
    let bad = |what: String| Err(SolverError::InvalidSettings(what));
    if !(settings.end_time.is_finite() && settings.end_time > 0.0) {
        return bad(format!("end time {} must be positive", settings.end_time));
    }
    if !(settings.safety_factor > 0.0 && settings.safety_factor <= 1.0) {
        return bad(format!(
            "safety factor {} must be in (0, 1]",
            settings.safety_factor
        ));
    }
    if !(settings.history_interval.is_finite() && settings.history_interval > 0.0) {
        return bad(format!(
            "history interval {} must be positive",
            settings.history_interval
        ));
    }
    Ok(())
}

/// Kernel, chunks, wave speed and lumped mass (ρ₀ V_e shared equally by the element's
/// nodes) of one part.
fn prepare_part<'a>(
    mesh: &'a Mesh,
    part: &'a Part,
    mass: &mut [f64],
) -> Result<PartRun<'a>, SolverError> {
    let block = mesh
        .blocks
        .get(part.block)
        .ok_or_else(|| SolverError::InvalidPart {
            block: part.block,
            reason: format!("the mesh has {} blocks", mesh.blocks.len()),
        })?;
    if !(part.density.is_finite() && part.density > 0.0) {
        return Err(SolverError::InvalidPart {
            block: part.block,
            reason: format!("density {} kg/m3 must be positive", part.density),
        });
    }
    let element_error = |source| SolverError::Element {
        block: part.block,
        source,
    };
    let material = part.material.as_ref();
    let elements = match part.technology {
        Technology::Hex8OnePoint { hourglass_modulus } if block.shape == ElementShape::Hex8 => {
            let chunks = chunk_ranges(block.len())
                .map(|range| {
                    OnePointHexChunk::new(range, &mesh.nodes, block, hourglass_modulus, material)
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(element_error)?;
            let volumes = chunks.iter().flat_map(OnePointHexChunk::volumes);
            for (ids, volume) in block.elements().zip(volumes) {
                let share = part.density * volume / 8.0;
                for &id in ids {
                    mass[id as usize] += share;
                }
            }
            PartElements::OnePointHex {
                chunks,
                forces: vec![Vector3::zeros(); block.connectivity.len()],
            }
        }
        technology => {
            let kernel = BlockKernel::new(&mesh.nodes, block, technology).map_err(element_error)?;
            let npe = kernel.nodes_per_element();
            for (element, ids) in block.elements().enumerate() {
                let share = part.density * kernel.reference_volume(element) / npe as f64;
                for &id in ids {
                    mass[id as usize] += share;
                }
            }
            let chunks = chunk_ranges(block.len())
                .map(|range| ElementChunk::new(range, &kernel, block, material))
                .collect();
            PartElements::General { kernel, chunks }
        }
    };
    Ok(PartRun {
        block: part.block,
        name: &block.name,
        material,
        density: part.density,
        elements,
        adjacency: NodeAdjacency::new(mass.len(), &block.connectivity),
        stable: (f64::INFINITY, 0),
    })
}

impl PartRun<'_> {
    /// Accept the step in every chunk.
    fn commit(&mut self) {
        match &mut self.elements {
            PartElements::General { chunks, .. } => {
                chunks.iter_mut().for_each(ElementChunk::commit)
            }
            PartElements::OnePointHex { chunks, .. } => {
                chunks.iter_mut().for_each(OnePointHexChunk::commit)
            }
        }
    }

    /// Add the part's element forces to the nodal forces `out` of the nodes from `first`
    /// on [N], each node's in ascending element order.
    fn add_node_forces(&self, first: usize, out: &mut [Vector3<f64>]) {
        match &self.elements {
            PartElements::OnePointHex { forces, .. } => {
                for (i, f) in out.iter_mut().enumerate() {
                    for &slot in self.adjacency.of(first + i) {
                        *f += forces[slot as usize];
                    }
                }
            }
            PartElements::General { kernel, chunks } => match kernel.nodes_per_element() {
                4 => add_chunk_forces::<4>(&self.adjacency, chunks, first, out),
                8 => add_chunk_forces::<8>(&self.adjacency, chunks, first, out),
                10 => add_chunk_forces::<10>(&self.adjacency, chunks, first, out),
                n => unreachable!("{n} nodes per element"),
            },
        }
    }
}

/// [`PartRun::add_node_forces`] for forces held in the chunks, `NPE` per element.
fn add_chunk_forces<const NPE: usize>(
    adjacency: &NodeAdjacency,
    chunks: &[ElementChunk],
    first: usize,
    out: &mut [Vector3<f64>],
) {
    let per_chunk = ELEMENTS_PER_CHUNK * NPE;
    for (i, f) in out.iter_mut().enumerate() {
        for &slot in adjacency.of(first + i) {
            let slot = slot as usize;
            *f += chunks[slot / per_chunk].forces[slot % per_chunk];
        }
    }
}

/// Internal nodal forces at `positions` after a step of `dt` ending at `time` (material
/// states updated but not committed). Elements are updated in parallel chunks, each
/// writing its own element forces; each node then sums its elements' forces in element
/// order, in parallel over nodes (`assembly.rs`), so the sum is the same, bit for bit, on
/// any number of threads. With `refresh`, the acoustic moduli and the stable steps are
/// recomputed too. Returns the stable step and its (block, element).
fn internal_forces<'a>(
    mesh: &Mesh,
    runs: &mut [PartRun<'a>],
    positions: &[Vector3<f64>],
    time: f64,
    dt: f64,
    refresh: bool,
    force: &mut [Vector3<f64>],
) -> Result<(f64, (&'a str, usize)), SolverError> {
    let first_smallest = |a: (f64, usize), b: (f64, usize)| if b.0 < a.0 { b } else { a };
    let mut stable = (f64::INFINITY, ("", 0));
    for run in runs.iter_mut() {
        let block = &mesh.blocks[run.block];
        let (material, density) = (run.material, run.density);
        let material_error = |(element, source)| SolverError::Material {
            time,
            block: block.name.clone(),
            element,
            source,
        };
        match &mut run.elements {
            PartElements::General { kernel, chunks } => {
                let kernel = &*kernel;
                chunks
                    .par_iter_mut()
                    .try_for_each(|chunk| {
                        chunk.update(kernel, block, material, positions, time, dt, false)?;
                        if refresh {
                            chunk.refresh_wave_moduli(kernel, material, time, dt)?;
                        }
                        Ok(())
                    })
                    .map_err(material_error)?;
                if refresh {
                    run.stable = chunks
                        .iter()
                        .map(|chunk| chunk.stable_step(density))
                        .fold((f64::INFINITY, 0), first_smallest);
                }
            }
            PartElements::OnePointHex { chunks, forces } => {
                let refresh_density = refresh.then_some(density);
                chunks
                    .par_iter_mut()
                    .zip(forces.par_chunks_mut(ELEMENTS_PER_CHUNK * 8))
                    .try_for_each(|(chunk, forces)| {
                        chunk.update(
                            block,
                            material,
                            positions,
                            time,
                            dt,
                            refresh_density,
                            forces,
                        )
                    })
                    .map_err(material_error)?;
                if refresh {
                    run.stable = chunks
                        .iter()
                        .map(OnePointHexChunk::stable_step)
                        .fold((f64::INFINITY, 0), first_smallest);
                }
            }
        }
        if run.stable.0 < stable.0 {
            stable = (run.stable.0, (run.name, run.stable.1));
        }
    }
    let runs = &*runs;
    force
        .par_chunks_mut(NODES_PER_TASK)
        .enumerate()
        .for_each(|(task, out)| {
            out.fill(Vector3::zeros());
            runs.iter()
                .for_each(|run| run.add_node_forces(task * NODES_PER_TASK, out));
        });
    Ok(stable)
}

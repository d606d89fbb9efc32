//! The parts of an explicit run: each block's element data (general chunks, the batched
//! one-point hex8, or the block-level passes of the nodally averaged tet4), lumped mass,
//! per-element density (raised by mass scaling), stable steps, bulk-viscosity state, the
//! internal-force evaluation and the deterministic parallel assembly.

use nalgebra::Vector3;
use rayon::prelude::*;

use musclefem_materials::Material;

use super::assembly::NodeAdjacency;
use super::bulk_viscosity::{Viscosities, ViscousBlock, chunk_forces};
use super::checkpoint::{CheckpointReader, CheckpointWriter};
use super::chunk::{ELEMENTS_PER_CHUNK, ElementChunk, chunk_ranges};
use super::element_fields::{AcceptedPoints, PartFields, part_fields};
use super::hex8_one_point_chunk::OnePointHexChunk;
use super::nodal::NODES_PER_TASK;
use super::nodal_average::NodalAveragePart;
use super::{Part, SolverError};
use crate::element::{BlockKernel, Technology};
use crate::mesh::{ElementShape, MAX_NODES_PER_ELEMENT, Mesh};

mod viscosity;
pub(super) use viscosity::{smallest_impedance_length, viscous_forces};

/// One part during a run.
pub(super) struct PartRun<'a> {
    pub block: usize,
    pub name: &'a str,
    material: &'a dyn Material,
    /// Density of each element, raised where mass scaling added mass [kg/m³].
    element_density: Vec<f64>,
    elements: PartElements,
    /// Node → element force slots, for the assembly.
    adjacency: NodeAdjacency,
    /// Bulk-viscosity state when it is on.
    viscous: Option<ViscousBlock>,
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
    /// [`Technology::Tet4NodalAverage`]: neighbouring elements are coupled through nodal
    /// averages, so the block is evaluated in passes over the whole block.
    NodalAverage {
        kernel: BlockKernel,
        averaged: NodalAveragePart,
    },
}

impl<'a> PartRun<'a> {
    /// Element data and lumped mass (ρ₀ V_e shared equally by the element's nodes, added
    /// into `mass`) of one part. The one-point hex8 takes the batched kernel unless an
    /// artificial viscosity is on (which needs the general kernel's volume gradients).
    pub fn new(
        mesh: &'a Mesh,
        part: &'a Part,
        mass: &mut [f64],
        viscosity: bool,
    ) -> Result<Self, SolverError> {
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
            cause: source,
        };
        let material = part.material.as_ref();
        let mut lump = |volumes: &mut dyn Iterator<Item = f64>| {
            let npe = block.shape.nodes_per_element();
            for (ids, volume) in block.elements().zip(volumes) {
                let share = part.density * volume / npe as f64;
                for &id in ids {
                    mass[id as usize] += share;
                }
            }
        };
        let elements = match part.technology {
            Technology::Hex8OnePoint { hourglass_modulus }
                if block.shape == ElementShape::Hex8 && !viscosity =>
            {
                let chunks = chunk_ranges(block.len())
                    .map(|range| {
                        OnePointHexChunk::new(
                            range,
                            &mesh.nodes,
                            block,
                            hourglass_modulus,
                            material,
                        )
                    })
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(element_error)?;
                lump(&mut chunks.iter().flat_map(OnePointHexChunk::volumes));
                PartElements::OnePointHex {
                    chunks,
                    forces: vec![Vector3::zeros(); block.connectivity.len()],
                }
            }
            technology => {
                let kernel =
                    BlockKernel::new(&mesh.nodes, block, technology).map_err(element_error)?;
                lump(&mut (0..block.len()).map(|e| kernel.reference_volume(e)));
                if technology == Technology::Tet4NodalAverage {
                    if viscosity {
                        return Err(SolverError::InvalidPart {
                            block: part.block,
                            reason: "bulk and shear viscosity are not available for \
                                     Tet4NodalAverage blocks yet (use Tet4 or Tet10, or run \
                                     without them)"
                                .to_string(),
                        });
                    }
                    let averaged = NodalAveragePart::new(&kernel, block, material);
                    PartElements::NodalAverage { kernel, averaged }
                } else {
                    let chunks = chunk_ranges(block.len())
                        .map(|range| {
                            let mut chunk = ElementChunk::new(range, &kernel, block, material);
                            if viscosity {
                                chunk.keep_volume_gradients(kernel.nodes_per_element());
                            }
                            chunk
                        })
                        .collect();
                    PartElements::General { kernel, chunks }
                }
            }
        };
        let viscous = match (&elements, viscosity) {
            (PartElements::General { kernel, .. }, true) => Some(ViscousBlock::new(kernel)),
            _ => None,
        };
        Ok(PartRun {
            block: part.block,
            name: &block.name,
            material,
            element_density: vec![part.density; block.len()],
            elements,
            adjacency: NodeAdjacency::new(mass.len(), &block.connectivity),
            viscous,
            stable: (f64::INFINITY, 0),
        })
    }

    /// Accept the step.
    pub fn commit(&mut self) {
        match &mut self.elements {
            PartElements::General { chunks, .. } => {
                chunks.iter_mut().for_each(ElementChunk::commit)
            }
            PartElements::OnePointHex { chunks, .. } => {
                chunks.iter_mut().for_each(OnePointHexChunk::commit)
            }
            PartElements::NodalAverage { averaged, .. } => averaged.commit(),
        }
    }

    /// Writes what evolves in the part's elements (see [`super::checkpoint`]), the
    /// bulk-viscosity volumes and the cached stable step.
    pub fn save_state(&self, out: &mut CheckpointWriter) {
        match &self.elements {
            PartElements::General { chunks, .. } => {
                chunks.iter().for_each(|chunk| chunk.save_state(out))
            }
            PartElements::OnePointHex { chunks, .. } => {
                chunks.iter().for_each(|chunk| chunk.save_state(out))
            }
            PartElements::NodalAverage { averaged, .. } => averaged.save_state(out),
        }
        if let Some(viscous) = &self.viscous {
            viscous.save_state(out);
        }
        out.f64(self.stable.0);
        out.u64(self.stable.1 as u64);
    }

    /// Reads what [`save_state`](Self::save_state) wrote.
    pub fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        match &mut self.elements {
            PartElements::General { chunks, .. } => {
                for chunk in chunks {
                    chunk.restore_state(input)?;
                }
            }
            PartElements::OnePointHex { chunks, .. } => {
                for chunk in chunks {
                    chunk.restore_state(input)?;
                }
            }
            PartElements::NodalAverage { averaged, .. } => averaged.restore_state(input)?,
        }
        if let Some(viscous) = &mut self.viscous {
            viscous.restore_state(input)?;
        }
        self.stable = (input.f64()?, input.index()?);
        Ok(())
    }

    /// The stable step L₀ √(ρ_e/M) of every element with its index, from the moduli of
    /// the last refresh.
    fn element_stable_steps(&self) -> Box<dyn Iterator<Item = (f64, usize)> + '_> {
        let density = &self.element_density;
        match &self.elements {
            PartElements::General { chunks, .. } => Box::new(
                chunks
                    .iter()
                    .flat_map(move |chunk| chunk.element_stable_steps(density)),
            ),
            PartElements::OnePointHex { chunks, .. } => Box::new(
                chunks
                    .iter()
                    .flat_map(move |chunk| chunk.element_stable_steps(density)),
            ),
            PartElements::NodalAverage { averaged, .. } => {
                Box::new(averaged.element_stable_steps(density))
            }
        }
    }

    /// Acoustic modulus M of each element at the last refresh [Pa], in element order.
    fn element_wave_moduli(&self) -> Box<dyn Iterator<Item = f64> + '_> {
        match &self.elements {
            PartElements::General { chunks, .. } => {
                Box::new(chunks.iter().flat_map(|c| c.wave_moduli().iter().copied()))
            }
            PartElements::OnePointHex { chunks, .. } => {
                Box::new(chunks.iter().flat_map(|c| c.wave_moduli().iter().copied()))
            }
            PartElements::NodalAverage { averaged, .. } => Box::new(averaged.wave_moduli()),
        }
    }

    /// Σ_e ½ M_e V_e ε² [J]: the strain energy of the part strained by `strain` everywhere
    /// under the acoustic moduli M_e of the last refresh (V_e the reference volumes): the
    /// energy scale below which an energy balance measures noise, not the solution.
    pub fn strain_energy_scale(&self, mesh: &Mesh, strain: f64) -> f64 {
        self.element_wave_moduli()
            .enumerate()
            .map(|(element, modulus)| {
                let volume = mesh
                    .element_volume(crate::mesh::ElementRef::new(
                        self.block as u32,
                        element as u32,
                    ))
                    .unwrap_or(0.0);
                0.5 * modulus * volume * strain * strain
            })
            .sum()
    }

    /// The part's per-element output fields at the last accepted step, ending at `time`.
    pub fn fields(&self, mesh: &Mesh, time: f64) -> Result<PartFields, SolverError> {
        let block = &mesh.blocks[self.block];
        let points: Vec<AcceptedPoints> = match &self.elements {
            PartElements::General { chunks, .. } => {
                chunks.iter().map(ElementChunk::accepted_points).collect()
            }
            PartElements::OnePointHex { chunks, .. } => chunks
                .iter()
                .map(|chunk| chunk.accepted_points(block))
                .collect(),
            PartElements::NodalAverage { averaged, .. } => averaged.accepted_points(),
        };
        part_fields(mesh, self.block, self.material, time, &points)
    }

    /// Recompute the cached smallest stable step of the part.
    fn refresh_stable_step(&mut self) {
        self.stable = self
            .element_stable_steps()
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
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
            // Added by its own passes in `internal_forces`.
            PartElements::NodalAverage { .. } => {}
        }
    }

    /// Add the part's element forces to the nodal forces `force` [N] slot by slot
    /// (element × nodes per element + local node, the order they are stored in), so each
    /// node's in ascending element order, as [`Self::add_node_forces`] adds them.
    fn scatter_node_forces(&self, connectivity: &[u32], force: &mut [Vector3<f64>]) {
        match &self.elements {
            PartElements::OnePointHex { forces, .. } => {
                scatter_slots(connectivity, forces.iter(), force);
            }
            PartElements::General { chunks, .. } => {
                scatter_slots(connectivity, chunks.iter().flat_map(|c| &c.forces), force);
            }
            // Added by its own passes in `internal_forces`.
            PartElements::NodalAverage { .. } => {}
        }
    }

    /// Hourglass energy Σ ½ k |q|² of the part's one-point hex8 elements at `positions`
    /// [J] (zero for other technologies). Chunks in parallel, summed in chunk order.
    fn hourglass_energy(&self, mesh: &Mesh, positions: &[Vector3<f64>]) -> f64 {
        let block = &mesh.blocks[self.block];
        let energies: Vec<f64> = match &self.elements {
            PartElements::OnePointHex { chunks, .. } => chunks
                .par_iter()
                .map(|chunk| chunk.hourglass_energy(block, positions))
                .collect(),
            PartElements::General { kernel, .. } if kernel.hourglass_vectors(0).is_some() => (0
                ..block.len())
                .into_par_iter()
                .map(|element| {
                    let mut local = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
                    let ids = block.element_nodes(element);
                    for (x, &id) in local.iter_mut().zip(ids) {
                        *x = positions[id as usize];
                    }
                    kernel.hourglass_energy(element, &local[..ids.len()])
                })
                .collect(),
            _ => Vec::new(),
        };
        energies.iter().sum()
    }
}

/// Add the force of each slot to its node, `connectivity[slot]`, in slot order.
fn scatter_slots<'f>(
    connectivity: &[u32],
    slots: impl Iterator<Item = &'f Vector3<f64>>,
    force: &mut [Vector3<f64>],
) {
    for (&node, f) in connectivity.iter().zip(slots) {
        force[node as usize] += f;
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
/// states updated but not committed), overwriting `force`. Elements are updated in
/// parallel chunks, each writing its own element forces; each node then sums its
/// elements' forces in element order, in parallel over nodes (`assembly.rs`), so the sum
/// is the same, bit for bit, on any number of threads. With `refresh`, the acoustic
/// moduli and the stable steps are recomputed too. Returns the stable step and its
/// (block, element).
#[allow(clippy::too_many_arguments)]
pub(super) fn internal_forces<'a>(
    mesh: &Mesh,
    runs: &mut [PartRun<'a>],
    positions: &[Vector3<f64>],
    time: f64,
    dt: f64,
    refresh: bool,
    viscous: Option<(&Viscosities, &[Vector3<f64>])>,
    force: &mut [Vector3<f64>],
) -> Result<(f64, (&'a str, usize)), SolverError> {
    for run in runs.iter_mut() {
        let block = &mesh.blocks[run.block];
        let material = run.material;
        let material_error = |(element, source)| SolverError::Material {
            time,
            block: block.name.clone(),
            element,
            cause: source,
        };
        match &mut run.elements {
            PartElements::General { kernel, chunks } => {
                let kernel = &*kernel;
                let update = |chunk: &mut ElementChunk| {
                    chunk.update(kernel, block, material, positions, time, dt)?;
                    if refresh {
                        chunk.refresh_wave_moduli(kernel, material, time, dt)?;
                    }
                    Ok(())
                };
                match (run.viscous.as_mut(), viscous) {
                    (Some(viscous_block), Some((viscosities, velocities))) => {
                        // The viscous forces with the element forces, chunk by chunk:
                        // they act through the volume gradients the update just made.
                        let density = &run.element_density;
                        let (volume_old, slices) =
                            viscous_block.chunk_slices(kernel.nodes_per_element());
                        chunks
                            .par_iter_mut()
                            .zip(slices)
                            .try_for_each(|(chunk, slices)| {
                                update(chunk)?;
                                chunk_forces(
                                    viscosities,
                                    chunk,
                                    block,
                                    density,
                                    velocities,
                                    dt,
                                    volume_old,
                                    slices,
                                );
                                Ok(())
                            })
                            .map_err(material_error)?;
                    }
                    _ => chunks
                        .par_iter_mut()
                        .try_for_each(update)
                        .map_err(material_error)?,
                }
            }
            PartElements::OnePointHex { chunks, forces } => {
                chunks
                    .par_iter_mut()
                    .zip(forces.par_chunks_mut(ELEMENTS_PER_CHUNK * 8))
                    .try_for_each(|(chunk, forces)| {
                        chunk.update(block, material, positions, time, dt, refresh, forces)
                    })
                    .map_err(material_error)?;
            }
            PartElements::NodalAverage { .. } => {}
        }
    }
    let parts = &*runs;
    if rayon::current_num_threads() == 1 {
        // One thread: the same additions in the same order as the gather below (each
        // node's forces part by part, in element order), but reading the element forces
        // in the order they are stored rather than node by node across the chunks.
        force.fill(Vector3::zeros());
        for run in parts {
            run.scatter_node_forces(&mesh.blocks[run.block].connectivity, force);
        }
    } else {
        force
            .par_chunks_mut(NODES_PER_TASK)
            .enumerate()
            .for_each(|(task, out)| {
                out.fill(Vector3::zeros());
                parts
                    .iter()
                    .for_each(|run| run.add_node_forces(task * NODES_PER_TASK, out));
            });
    }
    for run in runs.iter_mut() {
        let block = &mesh.blocks[run.block];
        if let PartElements::NodalAverage { kernel, averaged } = &mut run.elements {
            averaged
                .add_internal_forces(
                    kernel,
                    block,
                    run.material,
                    positions,
                    time,
                    dt,
                    refresh,
                    force,
                )
                .map_err(|(element, source)| SolverError::Material {
                    time,
                    block: block.name.clone(),
                    element,
                    cause: source,
                })?;
        }
        if refresh {
            run.refresh_stable_step();
        }
    }
    Ok(smallest_stable_step(runs))
}

/// The smallest cached stable step of all parts and its (block name, element).
pub(super) fn smallest_stable_step<'a>(runs: &[PartRun<'a>]) -> (f64, (&'a str, usize)) {
    let mut stable = (f64::INFINITY, ("", 0));
    for run in runs {
        if run.stable.0 < stable.0 {
            stable = (run.stable.0, (run.name, run.stable.1));
        }
    }
    stable
}

/// Mass scaling: raise the density of every element whose stable step is below `target`
/// [s] to ρ_e (target / Δt_e)² and lump the added mass ρ_e V_e / n onto its nodes.
/// Returns the added mass [kg].
pub(super) fn scale_masses(
    mesh: &Mesh,
    runs: &mut [PartRun],
    mass: &mut [f64],
    target: f64,
) -> f64 {
    let mut added = 0.0;
    for run in runs.iter_mut() {
        let block = &mesh.blocks[run.block];
        let npe = block.shape.nodes_per_element();
        let raised: Vec<(usize, f64)> = run
            .element_stable_steps()
            .filter(|(step, _)| *step < target)
            .map(|(step, element)| {
                (
                    element,
                    run.element_density[element] * (target / step).powi(2),
                )
            })
            .collect();
        for (element, density) in raised {
            let volume = mesh
                .element_volume(crate::mesh::ElementRef::new(
                    run.block as u32,
                    element as u32,
                ))
                .unwrap_or(0.0);
            let extra = (density - run.element_density[element]) * volume;
            run.element_density[element] = density;
            added += extra;
            for &id in block.element_nodes(element) {
                mass[id as usize] += extra / npe as f64;
            }
        }
        run.refresh_stable_step();
    }
    added
}

/// Hourglass energy of all parts at `positions` [J].
pub(super) fn hourglass_energy(mesh: &Mesh, runs: &[PartRun], positions: &[Vector3<f64>]) -> f64 {
    runs.iter()
        .map(|run| run.hourglass_energy(mesh, positions))
        .sum()
}

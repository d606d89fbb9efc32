//! [`FiberField`]: the result of the flow solve, one potential and one fiber direction
//! per element.

use std::time::Duration;

use musclefem_mesh::{ElementRef, Mesh, MeshError};
use nalgebra::Vector3;
use rayon::prelude::*;

use crate::boundary::{BoundaryKind, ClassifiedBoundary};
use crate::discretisation::coefficients::Coefficients;
use crate::discretisation::correction::boundary_flux;
use crate::error::{FiberError, Side};
use crate::fv_mesh::FvMesh;
use crate::solve::FlowSolution;

/// The flow through one named inlet or outlet region.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionFlux {
    /// The region's name (the surface or node set of the mesh).
    pub name: String,
    /// The end it belongs to.
    pub side: Side,
    /// Number of boundary faces of the region. A face selected by several regions of the
    /// same end counts for the first of them only, so the faces and fluxes of an end's
    /// regions add up to the end's.
    pub faces: usize,
    /// Flow through the region in the direction of the flow [m] (φ is dimensionless):
    /// in through an inlet region, ∫ ∇φ·n dA, and out through an outlet region,
    /// −∫ ∇φ·n dA, with n out of the mesh. Positive for a flow from inlet to outlet.
    pub flux: f64,
}

/// The potential flow through a muscle and the fiber direction it gives each element.
///
/// Per-element vectors run over all elements, block after block, element after element:
/// element `e` of block `b` is entry `block_offsets[b] + e`.
#[derive(Clone, Debug)]
pub struct FiberField {
    /// Potential φ of each element (dimensionless): 1 on the inlet, 0 on the outlet.
    pub potential: Vec<f64>,
    /// Unit fiber direction of each element: the unit flow velocity −∇φ/|∇φ|, pointing
    /// from the inlet (origin) to the outlet (insertion).
    pub direction: Vec<Vector3<f64>>,
    /// Index of the first element of each block, then the element count (blocks + 1).
    pub block_offsets: Vec<usize>,
    /// Flow in through the inlet, ∫_inlet ∇φ·n dA with n out of the mesh [m] (φ is
    /// dimensionless). Equal to `outlet_flux` to the solver tolerance.
    pub inlet_flux: f64,
    /// Flow out through the outlet, −∫_outlet ∇φ·n dA [m].
    pub outlet_flux: f64,
    /// Number of boundary faces with φ = 1.
    pub inlet_faces: usize,
    /// Number of boundary faces with φ = 0.
    pub outlet_faces: usize,
    /// The flux through each inlet region (in the order given), then through each outlet
    /// region. The inlet regions' fluxes add up to `inlet_flux`, the outlet regions' to
    /// `outlet_flux`.
    pub region_fluxes: Vec<RegionFlux>,
    /// CG solves: the orthogonal one, then one per non-orthogonal correction sweep.
    pub linear_solves: usize,
    /// CG iterations over all solves.
    pub linear_iterations: usize,
    /// Final relative residual ‖b + c(φ) − Aφ‖₂ / ‖b‖₂ (see [`crate::FlowSettings`]).
    pub residual: f64,
    /// Wall time of building the cells, faces, boundary and coefficients.
    pub setup_time: Duration,
    /// Wall time of the solve and the directions.
    pub solve_time: Duration,
}

impl FiberField {
    /// The field of a converged solution: directions from the gradients, fluxes from the
    /// fixed-potential faces. Errors if an element's gradient is zero or not finite.
    pub(crate) fn new(
        mesh: &Mesh,
        fv: &FvMesh,
        coefficients: &Coefficients,
        boundary: &ClassifiedBoundary,
        solution: FlowSolution,
    ) -> Result<Self, FiberError> {
        let direction: Vec<Vector3<f64>> = solution
            .gradient
            .par_iter()
            .map(|g| -g / g.norm())
            .collect();
        if let Some(cell) = direction
            .iter()
            .position(|d| !d.iter().all(|c| c.is_finite()))
        {
            let (block, element) = fv.name_of(mesh, cell);
            let g = solution.gradient[cell];
            return Err(FiberError::UndefinedDirection {
                block,
                element,
                gradient: [g.x, g.y, g.z],
            });
        }
        let mut region_fluxes: Vec<RegionFlux> = boundary
            .regions
            .iter()
            .map(|(side, name)| RegionFlux {
                name: name.clone(),
                side: *side,
                faces: 0,
                flux: 0.0,
            })
            .collect();
        let (mut inlet_flux, mut outlet_flux) = (0.0, 0.0);
        let (mut inlet_faces, mut outlet_faces) = (0, 0);
        for (b, kind) in boundary.kinds.iter().enumerate() {
            // ∫ ∇φ·n dA over the face, n out of the mesh.
            let outward = boundary_flux(
                fv,
                coefficients,
                &boundary.kinds,
                &solution.potential,
                &solution.gradient,
                b,
            );
            let along_flow = match kind {
                BoundaryKind::Inlet => {
                    inlet_flux += outward;
                    inlet_faces += 1;
                    outward
                }
                BoundaryKind::Outlet => {
                    outlet_flux -= outward;
                    outlet_faces += 1;
                    -outward
                }
                BoundaryKind::Wall => continue,
            };
            if let Some(region) = boundary.region_of_face[b] {
                region_fluxes[region].faces += 1;
                region_fluxes[region].flux += along_flow;
            }
        }
        Ok(Self {
            potential: solution.potential,
            direction,
            block_offsets: fv.block_offsets.clone(),
            inlet_flux,
            outlet_flux,
            inlet_faces,
            outlet_faces,
            region_fluxes,
            linear_solves: solution.linear_solves,
            linear_iterations: solution.linear_iterations,
            residual: solution.residual,
            setup_time: Duration::ZERO,
            solve_time: Duration::ZERO,
        })
    }

    /// The fiber directions of the elements of block `block` (empty if there is none).
    pub fn block_directions(&self, block: usize) -> &[Vector3<f64>] {
        self.block_range(block)
            .map_or(&[], |range| &self.direction[range])
    }

    /// The potentials of the elements of block `block` (empty if there is none).
    pub fn block_potentials(&self, block: usize) -> &[f64] {
        self.block_range(block)
            .map_or(&[], |range| &self.potential[range])
    }

    /// The fiber direction of one element, `None` if there is no such element.
    pub fn direction_of(&self, element: ElementRef) -> Option<Vector3<f64>> {
        self.block_directions(element.block as usize)
            .get(element.element as usize)
            .copied()
    }

    /// Writes the directions into the blocks' [`fiber_direction`] fields. Errors if the
    /// mesh's blocks do not have the sizes of the mesh the field was computed on.
    ///
    /// [`fiber_direction`]: musclefem_mesh::ElementBlock::fiber_direction
    pub fn assign_to(&self, mesh: &mut Mesh) -> Result<(), FiberError> {
        let blocks = self.block_offsets.len().saturating_sub(1);
        if mesh.blocks.len() != blocks {
            return Err(MeshError::BlockOutOfRange {
                block: blocks as u32,
                count: mesh.blocks.len(),
            }
            .into());
        }
        for (b, block) in mesh.blocks.iter_mut().enumerate() {
            let directions = self.block_directions(b);
            if directions.len() != block.len() {
                return Err(MeshError::FiberCount {
                    block: block.name.clone(),
                    elements: block.len(),
                    fibers: directions.len(),
                }
                .into());
            }
            block.fiber_direction.clear();
            block.fiber_direction.extend_from_slice(directions);
        }
        Ok(())
    }

    fn block_range(&self, block: usize) -> Option<std::ops::Range<usize>> {
        Some(*self.block_offsets.get(block)?..*self.block_offsets.get(block + 1)?)
    }
}

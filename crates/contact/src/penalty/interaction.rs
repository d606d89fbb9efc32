//! [`PenaltyContact`] as an [`Interaction`] of the solvers: search, forces, stiffness,
//! totals, per-node fields and checkpoints.

use nalgebra::{Matrix3, Vector3};

use musclefem_core::solver::{
    CheckpointReader, CheckpointWriter, Interaction, InteractionReport, NodalField, SolverError,
};

use super::{PenaltyContact, checkpoint};
use crate::main_side::MainSide;
use crate::surface::ContactTarget;

impl Interaction for PenaltyContact {
    fn name(&self) -> &str {
        &self.name
    }

    fn search(&mut self, time: f64, positions: &[Vector3<f64>]) -> Result<(), SolverError> {
        self.broadphase
            .search(&self.target, time, positions, &self.secondary.nodes);
        Ok(())
    }

    fn forces(
        &mut self,
        time: f64,
        positions: &[Vector3<f64>],
        _with_stiffness: bool,
        force: &mut [Vector3<f64>],
    ) -> Result<(), SolverError> {
        self.evaluate(time, positions);
        self.for_each_force(|node, f| force[node as usize] += f);
        // The resultant on the secondary nodes (the main side takes the opposite).
        let mut resultant = Vector3::zeros();
        let (mut active_points, mut active_area, mut stored_energy) = (0, 0.0, 0.0);
        for (i, area) in self.secondary.node_area.iter().enumerate() {
            let (gap, k, force) = match &self.smooth {
                Some(smooth) if smooth.contacts[i].active => {
                    let c = &smooth.contacts[i];
                    let k = self.node_penalty(i) * area * c.weight;
                    (c.gap, k, c.force(k))
                }
                None if self.contacts[i].active => {
                    let c = &self.contacts[i];
                    let k = self.node_penalty(i) * area * c.weight;
                    (c.gap, k, c.offset * k)
                }
                _ => continue,
            };
            resultant -= force;
            active_points += 1;
            active_area += area;
            stored_energy += 0.5 * k * gap * gap;
        }
        self.report.force = resultant;
        self.report.active_points = active_points;
        self.report.active_area = active_area;
        self.report.stored_energy = stored_energy;
        Ok(())
    }

    fn stiffness(&self, add: &mut dyn FnMut(u32, u32, &Matrix3<f64>)) {
        if let Some(smooth) = &self.smooth {
            for (i, c) in smooth.contacts.iter().enumerate() {
                if c.active {
                    let k = self.node_penalty(i) * self.secondary.node_area[i] * c.weight;
                    let corners = self.target.nodes(c.triangle as usize);
                    c.blocks(k, self.secondary.nodes[i], corners, add);
                }
            }
            return;
        }
        let rigid = matches!(self.target, ContactTarget::Rigid(_));
        for (i, c) in self.contacts.iter().enumerate() {
            if !c.active {
                continue;
            }
            let node = self.secondary.nodes[i];
            let k = self.node_penalty(i) * self.secondary.node_area[i] * c.weight;
            let vertices = match &self.target {
                ContactTarget::Deformable(main) => main.triangles[c.triangle as usize],
                ContactTarget::Rigid(_) => [node; 3],
            };
            let id = |l: usize| {
                if l == 0 {
                    node
                } else {
                    vertices[c.geometry.vertices[l - 1] as usize]
                }
            };
            c.geometry
                .blocks(k, &c.offset, rigid, |l, m, block| add(id(l), id(m), block));
        }
    }

    /// Symmetric at the closest point (the forces derive from the energy ½ ε g² A_s); not
    /// along the smooth normals (ν is not the gradient of d).
    fn symmetric_stiffness(&self) -> bool {
        self.smooth.is_none()
    }

    /// Frictionless contact keeps no history: nothing to accept.
    fn commit(&mut self) {}

    /// The closest features and the totals of the last evaluation (`penalty/checkpoint.rs`);
    /// the broadphase starts afresh from here.
    fn save_state(&mut self, out: &mut CheckpointWriter) -> Result<(), SolverError> {
        checkpoint::save_contacts(&self.contacts, out);
        if let Some(smooth) = &self.smooth {
            checkpoint::save_smooth_contacts(&smooth.contacts, out);
        }
        out.matrices(&[self.report.force]);
        out.u64(self.report.active_points as u64);
        out.f64(self.report.active_area);
        out.f64(self.report.stored_energy);
        self.broadphase.forget();
        Ok(())
    }

    fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        checkpoint::restore_contacts(&mut self.contacts, input)?;
        if let Some(smooth) = &mut self.smooth {
            checkpoint::restore_smooth_contacts(&mut smooth.contacts, input)?;
        }
        let mut force = [Vector3::zeros()];
        input.matrices_into("contact force", &mut force)?;
        self.report.force = force[0];
        self.report.active_points = input.index()?;
        self.report.active_area = input.f64()?;
        self.report.stored_energy = input.f64()?;
        self.broadphase.forget();
        Ok(())
    }

    fn report(&self) -> InteractionReport {
        self.report.clone()
    }

    /// `contact_pressure` t_n [Pa] and `contact_gap` g [m] at the secondary nodes (the gap
    /// d along the normal field with smooth normals; 0 where a node has no main triangle
    /// within the search distance), and `contact_force`,
    /// the force −f_c [N] the contact puts on every node (secondary and main).
    fn nodal_fields(&self, node_count: usize) -> Vec<NodalField> {
        let mut pressure = vec![0.0; node_count];
        let mut gap = vec![0.0; node_count];
        for (i, &node) in self.secondary.nodes.iter().enumerate() {
            let (g, active) = match &self.smooth {
                Some(smooth) => (smooth.contacts[i].gap, smooth.contacts[i].active),
                None => (self.contacts[i].gap, self.contacts[i].active),
            };
            gap[node as usize] = g;
            if active {
                pressure[node as usize] = -self.node_penalty(i) * g;
            }
        }
        let mut force = vec![0.0; 3 * node_count];
        self.for_each_force(|node, f| {
            for k in 0..3 {
                force[3 * node as usize + k] -= f[k];
            }
        });
        vec![
            NodalField {
                name: "contact_pressure".to_string(),
                components: 1,
                values: pressure,
            },
            NodalField {
                name: "contact_gap".to_string(),
                components: 1,
                values: gap,
            },
            NodalField {
                name: "contact_force".to_string(),
                components: 3,
                values: force,
            },
        ]
    }
}

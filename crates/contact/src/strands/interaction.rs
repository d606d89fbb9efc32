//! [`TendonStrands`] as an [`Interaction`] of the solvers: forces, stiffness, totals,
//! per-node fields and checkpoints.

use nalgebra::{Matrix3, Vector3};

use musclefem_core::solver::{
    CheckpointReader, CheckpointWriter, Interaction, InteractionReport, NodalField, SolverError,
};

use super::TendonStrands;

impl Interaction for TendonStrands {
    fn name(&self) -> &str {
        &self.name
    }

    /// Strands join fixed pairs of nodes: nothing to search.
    fn search(&mut self, _time: f64, _positions: &[Vector3<f64>]) -> Result<(), SolverError> {
        Ok(())
    }

    /// f_c,a = −f e and f_c,b = +f e for every taut strand.
    fn forces(
        &mut self,
        _time: f64,
        positions: &[Vector3<f64>],
        _with_stiffness: bool,
        force: &mut [Vector3<f64>],
    ) -> Result<(), SolverError> {
        self.evaluate(positions);
        for (strand, state) in self.strands.iter().zip(&self.states) {
            if state.is_taut() {
                let pull = state.pull_on_a();
                force[strand.node_a as usize] -= pull;
                force[strand.node_b as usize] += pull;
            }
        }
        Ok(())
    }

    /// K_aa = K_bb = K, K_ab = K_ba = −K for every taut strand (see the module docs).
    fn stiffness(&self, add: &mut dyn FnMut(u32, u32, &Matrix3<f64>)) {
        for (strand, state) in self.strands.iter().zip(&self.states) {
            if state.is_taut() {
                let k = state.stiffness();
                let (a, b) = (strand.node_a, strand.node_b);
                add(a, a, &k);
                add(b, b, &k);
                add(a, b, &-k);
                add(b, a, &-k);
            }
        }
    }

    /// Strands keep no history: nothing to accept.
    fn commit(&mut self) {}

    /// `force`: Σ f e, the pull on the a nodes [N] (the b nodes take the opposite);
    /// `active_points`: the taut strands; `stored_energy`: Σ ℓ₀ ∫ f dε [J]; no area. The
    /// scalar Σ f is [`TendonStrands::total_tension`].
    fn report(&self) -> InteractionReport {
        InteractionReport {
            name: self.name.clone(),
            force: self.states.iter().map(|s| s.pull_on_a()).sum(),
            active_points: self.taut_count(),
            active_area: 0.0,
            bonded_area: 0.0,
            stored_energy: self.states.iter().map(|s| s.energy).sum(),
        }
    }

    /// The separations x_b − x_a of the last evaluation; the states follow from them.
    fn save_state(&mut self, out: &mut CheckpointWriter) -> Result<(), SolverError> {
        let separations: Vec<Vector3<f64>> = self.states.iter().map(|s| s.separation).collect();
        out.matrices(&separations);
        Ok(())
    }

    fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        let mut separations = vec![Vector3::zeros(); self.strands.len()];
        input.matrices_into("strand separations", &mut separations)?;
        for ((state, strand), separation) in
            self.states.iter_mut().zip(&self.strands).zip(separations)
        {
            *state = strand.state(separation);
        }
        Ok(())
    }

    /// `strand_tension`: Σ f of the strands ending at a node [N]; `strand_force`: the
    /// force −f_c the strands put on a node [N].
    fn nodal_fields(&self, node_count: usize) -> Vec<NodalField> {
        let mut tension = vec![0.0; node_count];
        let mut force = vec![0.0; 3 * node_count];
        for (strand, state) in self.strands.iter().zip(&self.states) {
            let pull = state.pull_on_a();
            for (node, sign) in [(strand.node_a, 1.0), (strand.node_b, -1.0)] {
                let n = node as usize;
                tension[n] += state.tension;
                for k in 0..3 {
                    force[3 * n + k] += sign * pull[k];
                }
            }
        }
        vec![
            NodalField {
                name: "strand_tension".to_string(),
                components: 1,
                values: tension,
            },
            NodalField {
                name: "strand_force".to_string(),
                components: 3,
                values: force,
            },
        ]
    }
}

//! The observer of one squat: turns the solver's recorded instants into the muscles'
//! stress samples, the patella's pull and pose, the plausibility samples and the
//! caller's hook, and stops a run that no longer advances (a stall).

use std::collections::VecDeque;
use std::ops::ControlFlow;

use anyhow::Result;

use nalgebra::Vector3;

use musclefem_core::mesh::{ElementShape, Mesh};
use musclefem_core::solver::{
    InteractionReport, Observer, PoseFollower, Record, RigidReaction, Snapshot,
};

use super::super::anatomy::{KneeDimensions, Squat};
use super::patella::{LARGEST_TENDON_STRAIN, TendonPatella, TendonRow};
use super::patella_clearance::PatellaClearance;
use super::peak_stress::{ElementRegions, StressSample, percentile};
use super::plausibility::{PlausibilitySample, extensor_moment};

use super::checkpoint::{restore_study, save_study};
use super::interactions::KneeInteractions;
use super::model::{KneeGeometry, KneeModel};
use crate::run_directory::RunCompanion;

/// The solver's result, unless the recorder stopped it with an error of its own.
pub(super) fn finish<T>(result: Result<T>, recorder: &mut Recorder) -> Result<T> {
    match recorder.error.take() {
        Some(error) => Err(error),
        None => result,
    }
}

/// Turns the solvers' recorded instants into stress samples.
pub(super) struct Recorder<'a> {
    pub(super) mesh: &'a Mesh,
    /// Volume of every element in the reference configuration, block after block [m³].
    pub(super) reference_volumes: Vec<f64>,
    pub(super) regions: &'a [ElementRegions],
    pub(super) squat: &'a Squat,
    pub(super) samples: Vec<StressSample>,
    pub(super) error: Option<anyhow::Error>,
    /// Explicit: the largest energy and the largest balance error so far [J].
    pub(super) largest_energy: f64,
    pub(super) energy_error: f64,
    /// Implicit: stops a run that no longer advances.
    pub(super) stall: StallDetector,
    /// The patella, told the quadriceps' pull at every report.
    pub(super) patella: &'a TendonPatella,
    /// The knee's landmarks (the patellar tendon's attachments).
    pub(super) dimensions: KneeDimensions,
    pub(super) insertion_ties: &'a [usize],
    pub(super) tendon: Vec<TendonRow>,
    /// The muscles' nodes against the patella (which has no contact surface).
    pub(super) patella_clearance: PatellaClearance,
    /// Blocks `0..muscle_count` are the bellies; the tendon blocks with their muscle.
    pub(super) muscle_count: usize,
    pub(super) tendon_blocks: Vec<(usize, usize)>,
    /// (muscle, interaction) of the muscle–femur cohesive interfaces and contacts.
    pub(super) femur_interfaces: Vec<(usize, usize)>,
    pub(super) femur_contacts: Vec<(usize, usize)>,
    pub(super) plausibility: Vec<PlausibilitySample>,
}

/// Implicit increments over which a stall is judged.
const STALL_WINDOW: usize = 50;

/// A stall: the last [`STALL_WINDOW`] increments advanced the squat by less than this
/// fraction of its duration (on average 1/100 of the default 0.02 s increment at T = 2 s).
const STALL_FRACTION: f64 = 0.005;

/// The volume of every element of `mesh`, block after block [m³].
pub(super) fn reference_volumes(mesh: &Mesh) -> Vec<f64> {
    let zero = vec![Vector3::zeros(); mesh.node_count()];
    element_map(mesh, &zero, |shape, coords| shape.volume(coords))
}

/// `measure(shape, corner positions)` of every element at displacement `u`.
pub(super) fn element_map(
    mesh: &Mesh,
    u: &[Vector3<f64>],
    measure: impl Fn(ElementShape, &[Vector3<f64>]) -> f64 + Sync,
) -> Vec<f64> {
    mesh.blocks
        .iter()
        .flat_map(|block| {
            block
                .elements()
                .map(|nodes| {
                    // At most 10 nodes (tet10): no allocation per element.
                    let mut coords = [Vector3::zeros(); 10];
                    for (c, &n) in coords.iter_mut().zip(nodes) {
                        *c = mesh.nodes.position(n as usize) + u[n as usize];
                    }
                    measure(block.shape, &coords[..nodes.len()])
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

impl<'a> Recorder<'a> {
    /// The recorder of `geometry`'s squat on `model` with the interactions `built`, whose
    /// muscles' elements lie in `regions`.
    pub(super) fn new(
        geometry: &KneeGeometry,
        model: &'a KneeModel,
        built: &KneeInteractions,
        regions: &'a [ElementRegions],
        squat: &'a Squat,
    ) -> Result<Self> {
        Ok(Recorder {
            mesh: &model.mesh,
            reference_volumes: reference_volumes(&model.mesh),
            regions,
            squat,
            samples: Vec::new(),
            error: None,
            largest_energy: 0.0,
            energy_error: 0.0,
            stall: StallDetector::default(),
            patella: &model.patella,
            dimensions: geometry.dimensions,
            insertion_ties: &model.insertion_ties,
            tendon: Vec::new(),
            patella_clearance: PatellaClearance::new(geometry)?,
            muscle_count: geometry.muscles.len(),
            tendon_blocks: geometry.tendon_blocks().collect(),
            femur_interfaces: built.femur_interfaces.clone(),
            femur_contacts: built.femur_contacts.clone(),
            plausibility: Vec::new(),
        })
    }
}

impl Recorder<'_> {
    /// min over elements of min det J × reference-element volume / element volume.
    fn min_jacobian_ratio(&self, displacement: &[Vector3<f64>]) -> f64 {
        element_map(self.mesh, displacement, |shape, coords| {
            shape.min_jacobian_volume(coords)
        })
        .iter()
        .zip(&self.reference_volumes)
        .map(|(j, v)| j / v)
        .fold(f64::INFINITY, f64::min)
    }

    /// The quadriceps' pull at `time`, T = Σ |R| over the insertions' ties, which the
    /// solver has just reported to the patella ([`PoseFollower::observe`]): records the
    /// tendon's state the run had at that time (from the pull reported before) and starts
    /// the instant's plausibility sample; stops the run if the measured pull would stretch
    /// the tendon beyond the table.
    fn report_pull(
        &mut self,
        time: f64,
        reactions: &[RigidReaction],
        interactions: &[InteractionReport],
    ) -> ControlFlow<()> {
        let insertion_pull: Vec<f64> = self
            .insertion_ties
            .iter()
            .map(|&i| reactions[i].force.norm())
            .collect();
        let tension: f64 = insertion_pull.iter().sum();
        let applied = self.patella.state_at(time);
        let measured = self.patella.equilibrium(time, tension);
        self.tendon.push(TendonRow {
            time,
            measured_tension: tension,
            applied,
        });
        let per_muscle = |pairs: &[(usize, usize)]| {
            let mut forces = vec![0.0; self.muscle_count];
            for &(m, i) in pairs {
                forces[m] += interactions[i].force.norm();
            }
            forces
        };
        // The component along the muscle's pull: the direction of its insertion's reaction.
        let along_pull = |pairs: &[(usize, usize)]| {
            let mut forces = vec![0.0; self.muscle_count];
            for &(m, i) in pairs {
                let pull = reactions[self.insertion_ties[m]].force;
                if let Some(direction) = pull.try_normalize(0.0) {
                    forces[m] += interactions[i].force.dot(&direction);
                }
            }
            forces.iter().map(|f| f.abs()).collect::<Vec<_>>()
        };
        self.plausibility.push(PlausibilitySample {
            time,
            flexion: self.squat.flexion_at(time),
            insertion_pull,
            tendon_force: applied.tendon_force,
            extensor_moment: extensor_moment(&self.dimensions, &applied),
            fiber_stretch_median: 1.0,
            fiber_stretch_p95: 1.0,
            femur_interface_force: per_muscle(&self.femur_interfaces),
            femur_interface_along_pull: along_pull(&self.femur_interfaces),
            femur_contact_force: per_muscle(&self.femur_contacts),
            tendon_peak: vec![0.0; self.muscle_count],
        });
        if measured.beyond_table {
            self.error = Some(anyhow::anyhow!(
                "at t = {time:.4} s (knee flexion {:.1}°) the quadriceps pull the patella \
                 with {tension:.0} N, which would stretch the patellar tendon beyond {:.0} %",
                measured.knee_angle.to_degrees(),
                100.0 * LARGEST_TENDON_STRAIN
            ));
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    fn record(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        let fields = match snapshot.element_fields() {
            Ok(fields) => fields,
            Err(e) => {
                self.error = Some(anyhow::Error::from(e).context("the muscles' stresses"));
                return ControlFlow::Break(());
            }
        };
        let mut sample = StressSample {
            time: snapshot.time,
            flexion: self.squat.flexion_at(snapshot.time),
            vm95: Vec::with_capacity(fields.len()),
            location: Vec::with_capacity(fields.len()),
            min_jacobian_ratio: self.min_jacobian_ratio(snapshot.displacement),
        };
        let mut stretches = Vec::new();
        let mut tendon_peak = vec![0.0f64; self.muscle_count];
        for part in &fields {
            let von_mises = part.von_mises();
            if part.block < self.muscle_count {
                let vm95 = percentile(&von_mises, 0.95).unwrap_or(0.0);
                sample.vm95.push(vm95);
                sample
                    .location
                    .push(self.regions[part.block].locate(&von_mises, vm95));
                stretches.extend_from_slice(&part.fiber_stretch);
            } else if let Some(&(_, m)) = self.tendon_blocks.iter().find(|(b, _)| *b == part.block)
            {
                tendon_peak[m] = von_mises.iter().fold(tendon_peak[m], |a, &b| a.max(b));
            }
        }
        if let Some(last) = self.plausibility.last_mut()
            && last.time == snapshot.time
        {
            last.fiber_stretch_median = percentile(&stretches, 0.5).unwrap_or(1.0);
            last.fiber_stretch_p95 = percentile(&stretches, 0.95).unwrap_or(1.0);
            last.tendon_peak = tendon_peak;
        }
        let motion = self.patella.isometry_at(snapshot.time);
        let (mesh, u) = (self.mesh, snapshot.displacement);
        self.patella_clearance
            .check(snapshot.time, &motion, |n| mesh.nodes.position(n) + u[n]);
        self.samples.push(sample);
        ControlFlow::Continue(())
    }
}

/// Watches the end times of the implicit increments for a stall: the last
/// [`STALL_WINDOW`] increments advancing the squat by less than [`STALL_FRACTION`] of its
/// duration, after which the run would go on for hours.
#[derive(Debug, Default)]
pub(super) struct StallDetector {
    recent_times: VecDeque<f64>,
}

impl StallDetector {
    /// The end times of the increments it is judging [s] (for a checkpoint).
    pub(super) fn recent_times(&self) -> Vec<f64> {
        self.recent_times.iter().copied().collect()
    }

    /// A detector that has seen the increments ending at `times`.
    pub(super) fn with_recent_times(times: Vec<f64>) -> Self {
        Self {
            recent_times: times.into(),
        }
    }

    /// Notes a converged increment ending at `time` [s]; the error message on a stall.
    fn advance(&mut self, time: f64, squat: &Squat) -> Option<String> {
        self.recent_times.push_back(time);
        if self.recent_times.len() <= STALL_WINDOW {
            return None;
        }
        let first = self.recent_times.pop_front().unwrap_or(time);
        let advanced = time - first;
        if advanced >= STALL_FRACTION * squat.duration || time >= squat.duration {
            return None;
        }
        Some(format!(
            "the implicit solver stalled at t = {time:.4} s (knee flexion {:.1}°): its last \
             {STALL_WINDOW} increments advanced the squat by {:.2} ms, {:.2} % of it, and \
             the run would go on for hours. Newton's method follows the motion there only \
             in tiny increments. Measured cases: the quasi-static active squat at the onset \
             of activation, which the explicit solver (--solver explicit) runs through, and \
             the one-point hex8's passive squat at 43°, which F-bar hex8 runs through",
            squat.flexion_at(time).to_degrees(),
            1e3 * advanced,
            100.0 * advanced / squat.duration,
        ))
    }
}

/// The knee's observer beside the run's writer ([`crate::run_directory`]): it tells the
/// knee's patella the quadriceps' pull (the scene's solver tells the scene's own patella
/// the same: the same follower on the same table, so both take the same poses) and
/// records the squat's samples; the writer writes the frames, history and checkpoints.
impl Observer for Recorder<'_> {
    /// The implicit solver's initial state: a sample at t = 0.
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        self.record(snapshot)
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        if let Record::Explicit(row) = record {
            let energies = [
                row.internal_energy,
                row.kinetic_energy,
                row.external_work,
                row.viscous_energy,
                row.interaction_work.abs(),
            ];
            self.largest_energy = energies.iter().fold(self.largest_energy, |a, &b| a.max(b));
            let balance = row.internal_energy
                + row.viscous_energy
                + row.interaction_work
                + row.kinetic_energy
                - row.external_work;
            self.energy_error = self.energy_error.max(balance.abs());
        }
        self.patella
            .observe(record.time(), record.rigid_reactions());
        self.report_pull(
            record.time(),
            record.rigid_reactions(),
            record.interactions(),
        )?;
        self.record(snapshot)?;
        // Implicit increments are few: each is checked for a stall.
        if let Record::Implicit(row) = record
            && let Some(message) = self.stall.advance(row.time, self.squat)
        {
            self.error = Some(anyhow::anyhow!(message));
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

/// Beside a scene's run ([`crate::run_directory`]): its state (and the patella's) goes
/// into the run's checkpoints.
impl RunCompanion for Recorder<'_> {
    fn save_state(&mut self) -> Vec<u8> {
        save_study(self)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<()> {
        restore_study(self, state)
            .map_err(|e| anyhow::anyhow!("the knee's state in the checkpoint: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::simulation::run::DEFAULT_SQUAT_DURATION;

    /// The default squat's increments (20 ms, 8 cut to 10 ms) never look like a stall;
    /// 1e-4 s increments (those of the stalled active run) are one after 50 of them.
    #[test]
    fn a_run_that_no_longer_advances_is_a_stall() {
        let squat = Squat::to_ninety_degrees(DEFAULT_SQUAT_DURATION);
        let mut detector = StallDetector::default();
        let mut time = 0.0;
        for increment in 0..200 {
            time += if increment % 25 < 8 { 0.01 } else { 0.02 };
            assert_eq!(detector.advance(time, &squat), None, "at {time} s");
        }
        let mut detector = StallDetector::default();
        let mut time = 0.4292;
        for _ in 0..STALL_WINDOW {
            time += 1e-4;
            assert_eq!(detector.advance(time, &squat), None);
        }
        time += 1e-4;
        let message = detector.advance(time, &squat).expect("a stall");
        assert!(
            message.contains("stalled at t = 0.4343 s")
                && message.contains("advanced the squat by 5.00 ms")
                && message.contains("--solver explicit"),
            "{message}"
        );
    }
}

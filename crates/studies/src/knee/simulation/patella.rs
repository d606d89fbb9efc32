//! The patella in the finite-element squat. The patellar tendon holds it on its groove as
//! a nonlinear spring ([`TendonSpring`]) against the quadriceps' pull, and the run
//! itself measures that pull.
//!
//! **Equilibrium.** With the tendon at length ℓ, the kinematics ([`KneeKinematics`]) give
//! the patella's pose P(θ, ℓ) at knee flexion θ. They also give the least
//! tension-weighted path length W*(θ, ℓ) = min Σ ŵ_m L_m, with ŵ_m the muscles' volume
//! weights scaled to Σ ŵ = 1. The quadriceps pull with total tension T [N], the groove is
//! frictionless and the tendon stores E_t(ℓ). The patella then rests where
//! Π(ℓ) = T W*(θ, ℓ) + E_t(ℓ) is least:
//!
//! ```text
//! f_t(ℓ) = T r(θ, ℓ),   r = −∂W*/∂ℓ,
//! ```
//!
//! where r is the ratio of the tendon's force to the quadriceps' (≈ 1 near extension,
//! ≈ 0.5 at 90°). At T = 0 the tendon is at its slack length and the pose is the one of the
//! inextensible kinematics, in which the muscles are meshed.
//!
//! **Table.** P and W* are tabulated once, in parallel, on a grid of θ (1°) and tendon
//! strain (1 %, up to [`LARGEST_TENDON_STRAIN`]). r comes from central differences of W*
//! in ℓ. A pose is then a bisection on ℓ between bilinear interpolations (microseconds).
//!
//! **Coupling.** T = Σ_m |R_m|, the magnitudes of the reaction forces of the insertions'
//! rigid ties. The run reports them at every implicit increment (at every recorded
//! instant with the explicit solver). The pull that poses the patella follows the last
//! one measured through two first-order stages of time constant [`PULL_RELAXATION_TIME`],
//! so the pose and its speed change smoothly (the explicit solver's steps see no jumps)
//! and the staggered coupling stays stable; it lags the measured pull by about 2τ dT/dt.

use std::sync::{Arc, Mutex, OnceLock};

use anyhow::{Result, bail};
use nalgebra::{Isometry3, Vector3};
use rayon::prelude::*;

use musclefem_core::solver::{
    CheckpointReader, CheckpointWriter, PoseFollower, RigidReaction, SolverError,
};

use crate::knee::anatomy::{ClosedChain, KneeKinematics, PatellaPose, Squat, TendonSpring};

mod checkpoint;
mod table_csv;
mod tendon_csv;

pub use table_csv::PATELLA_TABLE_CSV_HEADER;

pub use tendon_csv::{
    TENDON_CSV_HEADER, TendonRow, tendon_summary, tendon_values, write_tendon_csv,
};

/// Largest tendon strain the table covers; a pull that would stretch the tendon further
/// stops the run.
pub const LARGEST_TENDON_STRAIN: f64 = 0.30;
/// Spacing of the table in knee flexion [rad] (1°).
const ANGLE_STEP: f64 = std::f64::consts::PI / 180.0;
/// Spacing of the table in tendon strain.
const STRAIN_STEP: f64 = 0.01;

/// The patella's equilibrium with the tendon at one knee angle and quadriceps tension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TendonState {
    /// Knee flexion θ [rad].
    pub knee_angle: f64,
    /// Total quadriceps tension T [N].
    pub quadriceps_tension: f64,
    /// Tendon tension f_t [N].
    pub tendon_force: f64,
    /// Tendon length ℓ [m].
    pub tendon_length: f64,
    /// Tendon strain ℓ/ℓ₀ − 1.
    pub tendon_strain: f64,
    /// r = f_t / T, the tendon's share of the quadriceps' pull.
    pub force_ratio: f64,
    /// The patella's pose.
    pub pose: PatellaPose,
    /// Whether the pull would stretch the tendon beyond [`LARGEST_TENDON_STRAIN`].
    pub beyond_table: bool,
}

/// P(θ, ℓ) and r(θ, ℓ) on a grid (see the module documentation).
#[derive(Debug)]
pub struct PatellaTable {
    tendon: TendonSpring,
    angle_count: usize,
    strain_count: usize,
    /// Centroid (x, y), flexion φ and groove coordinate u at each (angle, strain),
    /// angle-major.
    poses: Vec<[f64; 4]>,
    /// r = −∂W*/∂ℓ at each (angle, strain).
    ratios: Vec<f64>,
    /// The pose at 0° with a slack tendon: the muscles' mesh is in it.
    reference: PatellaPose,
}

impl PatellaTable {
    /// The table of `kinematics` with `tendon`, for knee flexion 0 to `peak_flexion` [rad].
    /// Errors if the patella has no pose somewhere on the grid.
    pub fn new(
        kinematics: &KneeKinematics,
        tendon: TendonSpring,
        peak_flexion: f64,
    ) -> Result<Self> {
        if !(peak_flexion.is_finite() && peak_flexion >= 0.0) {
            bail!("the patella's table needs a finite peak flexion ≥ 0, not {peak_flexion}");
        }
        let angle_count = (peak_flexion / ANGLE_STEP).ceil() as usize + 2;
        let strain_count = (LARGEST_TENDON_STRAIN / STRAIN_STEP).round() as usize + 1;
        let total_weight: f64 = kinematics.pulls.iter().map(|p| p.weight).sum();
        let entries: Vec<(PatellaPose, f64)> = (0..angle_count * strain_count)
            .into_par_iter()
            .map(|index| {
                let (a, s) = (index / strain_count, index % strain_count);
                let length = tendon.slack_length * (1.0 + s as f64 * STRAIN_STEP);
                let knee = kinematics.with_tendon_length(length);
                let pose = knee.patella_pose(a as f64 * ANGLE_STEP)?;
                Ok((pose, knee.weighted_length(&pose) / total_weight))
            })
            .collect::<Result<_>>()?;
        let length_step = tendon.slack_length * STRAIN_STEP;
        let ratios = (0..entries.len())
            .map(|index| {
                let s = index % strain_count;
                let (low, high) = (s.saturating_sub(1), (s + 1).min(strain_count - 1));
                let row = index - s;
                -(entries[row + high].1 - entries[row + low].1)
                    / ((high - low) as f64 * length_step)
            })
            .collect();
        Ok(Self {
            tendon,
            angle_count,
            strain_count,
            poses: entries
                .iter()
                .map(|(p, _)| [p.centre.x, p.centre.y, p.flexion, p.groove_coordinate])
                .collect(),
            ratios,
            reference: entries[0].0,
        })
    }

    /// The tendon the table was built with.
    pub fn tendon(&self) -> &TendonSpring {
        &self.tendon
    }

    /// Bilinear interpolation of `value(index)` at knee flexion `angle` [rad] and tendon
    /// strain `strain` (both clamped to the table).
    fn interpolate(&self, angle: f64, strain: f64, value: impl Fn(usize) -> f64) -> f64 {
        let locate = |x: f64, count: usize| {
            let x = x.clamp(0.0, (count - 1) as f64);
            let i = (x.floor() as usize).min(count - 2);
            (i, x - i as f64)
        };
        let (a, wa) = locate(angle / ANGLE_STEP, self.angle_count);
        let (s, ws) = locate(strain / STRAIN_STEP, self.strain_count);
        let at = |a: usize, s: usize| value(a * self.strain_count + s);
        (1.0 - wa) * ((1.0 - ws) * at(a, s) + ws * at(a, s + 1))
            + wa * ((1.0 - ws) * at(a + 1, s) + ws * at(a + 1, s + 1))
    }

    /// r(θ, ℓ) at knee flexion `angle` [rad] and tendon strain `strain`.
    fn force_ratio(&self, angle: f64, strain: f64) -> f64 {
        self.interpolate(angle, strain, |i| self.ratios[i])
    }

    /// The patella's pose at knee flexion `angle` [rad] with the tendon at `strain`.
    pub fn pose(&self, angle: f64, strain: f64) -> PatellaPose {
        let component = |k: usize| self.interpolate(angle, strain, |i| self.poses[i][k]);
        PatellaPose {
            centre: Vector3::new(component(0), component(1), self.reference.centre.z),
            flexion: component(2),
            groove_coordinate: component(3),
        }
    }

    /// The equilibrium at knee flexion `angle` [rad] under quadriceps tension `tension`
    /// [N]: the root of f_t(ℓ) − T r(θ, ℓ) by bisection on the table's strains.
    pub fn equilibrium(&self, angle: f64, tension: f64) -> TendonState {
        let tension = tension.max(0.0);
        let l0 = self.tendon.slack_length;
        let excess = |strain: f64| {
            self.tendon.force(l0 * (1.0 + strain)) - tension * self.force_ratio(angle, strain)
        };
        let largest = (self.strain_count - 1) as f64 * STRAIN_STEP;
        let beyond_table = excess(largest) < 0.0;
        let strain = if tension == 0.0 {
            0.0
        } else if beyond_table {
            largest
        } else {
            let (mut low, mut high) = (0.0, largest);
            for _ in 0..50 {
                let mid = 0.5 * (low + high);
                if excess(mid) < 0.0 {
                    low = mid;
                } else {
                    high = mid;
                }
            }
            0.5 * (low + high)
        };
        let tendon_length = l0 * (1.0 + strain);
        TendonState {
            knee_angle: angle,
            quadriceps_tension: tension,
            tendon_force: self.tendon.force(tendon_length),
            tendon_length,
            tendon_strain: strain,
            force_ratio: self.force_ratio(angle, strain),
            pose: self.pose(angle, strain),
            beyond_table,
        }
    }
}

/// The patella of one run: the table, the squat's θ(t), the leg's closed chain (which
/// places the femur, and with it the groove) and the pull reported so far.
#[derive(Debug)]
pub struct TendonPatella {
    table: Arc<PatellaTable>,
    squat: Squat,
    chain: ClosedChain,
    reports: Mutex<Reports>,
    /// The rigid ties (indices in the problem's `Loads::rigid_ties`) whose reactions are
    /// the quadriceps' pull: the insertions ([`TendonPatella::pulled_by`]).
    pulling_ties: OnceLock<Vec<usize>>,
}

#[derive(Debug, Default)]
struct Reports {
    /// The latest report: (time [s], measured tension [N]).
    latest: Option<(f64, f64)>,
    /// The two filter stages (T₁, T_a) at the latest report's time [N].
    stages_at_latest: [f64; 2],
    /// The last pose asked for: (time, isometry), the solvers ask many times per time.
    cached: Option<(f64, Isometry3<f64>)>,
}

impl Reports {
    /// The tension the patella is posed with at `time` [s]: the second stage, never
    /// negative (0 before any report).
    fn applied_tension(&self, time: f64) -> f64 {
        self.stages(time)[1].max(0.0)
    }

    /// The two filter stages (T₁, T_a) at `time` [s] (see [`PULL_RELAXATION_TIME`]).
    fn stages(&self, time: f64) -> [f64; 2] {
        match self.latest {
            None => [0.0; 2],
            // At the report's own time the stages are those it found (bit for bit: the
            // formula below gives m + (T − m), which may differ in the last digit).
            Some((t, _)) if time <= t => self.stages_at_latest,
            Some((t, measured)) => {
                let s = (time - t).max(0.0) / PULL_RELAXATION_TIME;
                let decay = (-s).exp();
                let [first, applied] = self.stages_at_latest.map(|x| x - measured);
                [
                    measured + first * decay,
                    measured + (applied + first * s) * decay,
                ]
            }
        }
    }
}

/// Time constant τ of each of the two stages through which the pull that poses the
/// patella follows the last measured one [s]: dT₁/dt = (T_m − T₁)/τ, dT_a/dt = (T₁ − T_a)/τ
/// (solved exactly between reports), so T_a lags T_m by about 2τ.
///
/// **Why not the measured pull itself.** The staggered coupling is stable only if the
/// muscles' answer to a move of the patella is smaller than the tendon's. Moving the
/// patella within one increment Δt makes the active muscles answer with their stiffness
/// and, above all, their force–velocity relation (a damping c) and inertia. Measured on
/// the active squat (2026-11-23):
/// - with the measured pull used at once, Newton failed at the onset of activation (3e-5 s
///   increments);
/// - through one stage of τ = 20 ms the pull oscillated from increment to increment by
///   ±2 kN from t ≈ 1 s on and the run stopped at 1.45 s (c/K ≈ 19 ms, K the tendon's
///   stiffness);
/// - through one stage of 60 ms the run finished, but the measured pull still alternated
///   by up to 1 kN between increments from 1.5 s on (the concentric extension), through
///   the jumps of the patella's speed at each report.
///
/// Two stages make the patella's speed continuous and damp an alternation from
/// increment to increment by a further Δt/τ. With τ = 30 ms both runs finish without
/// alternation; with τ = 15 ms the lag halved in the passive run, but the active one
/// stalled in the last extension (t = 1.86 s). The price is the lag, about 2τ dT/dt, which
/// `tendon.csv` records (measured against applied pull).
pub const PULL_RELAXATION_TIME: f64 = 0.03;

impl TendonPatella {
    /// A patella on `table`, the knee flexing as `squat` says with the femur placed by
    /// `chain`, no pull reported yet.
    pub fn new(table: Arc<PatellaTable>, squat: Squat, chain: ClosedChain) -> Self {
        Self {
            table,
            squat,
            chain,
            reports: Mutex::new(Reports::default()),
            pulling_ties: OnceLock::new(),
        }
    }

    /// The rigid ties (indices in the problem's ties) whose reactions pull the patella:
    /// the solver reports T = Σ |R| over them at every recorded instant
    /// ([`PoseFollower::observe`]). Set once, when the ties are built.
    pub fn pulled_by(&self, ties: Vec<usize>) {
        let _ = self.pulling_ties.set(ties);
    }

    /// The pull T = Σ |R| [N] of the pulling ties among `tie_reactions`.
    pub fn pull(&self, tie_reactions: &[RigidReaction]) -> f64 {
        self.pulling_ties.get().map_or(0.0, |ties| {
            ties.iter().map(|&i| tie_reactions[i].force.norm()).sum()
        })
    }

    fn reports(&self) -> std::sync::MutexGuard<'_, Reports> {
        // A panic elsewhere cannot leave the reports half-written: recover them.
        self.reports.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The run measured quadriceps tension `tension` [N] at `time` [s]. A second report
    /// at the same time replaces the first.
    pub fn report(&self, time: f64, tension: f64) {
        let mut reports = self.reports();
        match reports.latest {
            Some((t, _)) if time <= t => reports.latest = Some((t, tension)),
            _ => {
                reports.stages_at_latest = reports.stages(time);
                reports.latest = Some((time, tension));
            }
        }
        reports.cached = None;
    }

    /// The tension the patella is posed with at `time` [s] (0 before any report).
    pub fn tension_at(&self, time: f64) -> f64 {
        self.reports().applied_tension(time)
    }

    /// The equilibrium at `time` [s], posed with the applied pull.
    pub fn state_at(&self, time: f64) -> TendonState {
        self.equilibrium(time, self.tension_at(time))
    }

    /// The equilibrium at `time` [s] under the pull `tension` [N].
    pub fn equilibrium(&self, time: f64, tension: f64) -> TendonState {
        self.table.equilibrium(self.squat.flexion_at(time), tension)
    }
}

impl PoseFollower for TendonPatella {
    fn isometry_at(&self, time: f64) -> Isometry3<f64> {
        // One lock for the lookup and the update: a report cannot slip in between.
        let mut reports = self.reports();
        if let Some((t, iso)) = reports.cached
            && t == time
        {
            return iso;
        }
        let tension = reports.applied_tension(time);
        let flexion = self.squat.flexion_at(time);
        let pose = self.table.equilibrium(flexion, tension).pose;
        // The pose in the femur's frame, placed with the femur.
        let iso = self.chain.pose(flexion).femur
            * pose.isometry()
            * self.table.reference.isometry().inverse();
        reports.cached = Some((time, iso));
        iso
    }

    fn reference_point(&self) -> Vector3<f64> {
        self.table.reference.centre
    }

    /// The quadriceps' pull measured at a recorded instant poses the patella from then on.
    fn observe(&self, time: f64, tie_reactions: &[RigidReaction]) {
        self.report(time, self.pull(tie_reactions));
    }

    fn save_state(&self, out: &mut CheckpointWriter) {
        self.save_reports(out);
    }

    fn restore_state(&self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        self.restore_reports(input)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::OnceLock;

    use super::*;
    use crate::knee::anatomy::Quadriceps;

    fn kinematics() -> KneeKinematics {
        KneeKinematics::new(Quadriceps::ALL.iter().map(|m| m.pull()).collect())
    }

    fn table() -> &'static Arc<PatellaTable> {
        static TABLE: OnceLock<Arc<PatellaTable>> = OnceLock::new();
        TABLE.get_or_init(|| {
            Arc::new(
                PatellaTable::new(
                    &kinematics(),
                    TendonSpring::procedural_knee(),
                    std::f64::consts::FRAC_PI_2,
                )
                .unwrap(),
            )
        })
    }

    /// Π(ℓ) = T W*(θ, ℓ) + E_t(ℓ) from the kinematics themselves (no table).
    fn potential(kinematics: &KneeKinematics, angle: f64, tension: f64, length: f64) -> f64 {
        let tendon = TendonSpring::procedural_knee();
        let knee = kinematics.with_tendon_length(length);
        let total: f64 = knee.pulls.iter().map(|p| p.weight).sum();
        let pose = knee.patella_pose(angle).unwrap();
        tension * knee.weighted_length(&pose) / total + tendon.energy(length)
    }

    #[test]
    fn the_tables_equilibrium_minimises_the_potential_of_the_pull_and_the_tendon() {
        let kinematics = kinematics();
        let l0 = TendonSpring::procedural_knee().slack_length;
        for degrees in [20.0, 60.0, 90.0] {
            let angle = f64::to_radians(degrees);
            for tension in [500.0, 3000.0, 8000.0] {
                let state = table().equilibrium(angle, tension);
                assert!(!state.beyond_table);
                // The least Π by golden-section search on ℓ, every Π from the kinematics.
                let golden = 0.5 * (5f64.sqrt() - 1.0);
                let (mut a, mut b) = (l0, l0 * 1.25);
                for _ in 0..40 {
                    let (c, d) = (b - golden * (b - a), a + golden * (b - a));
                    if potential(&kinematics, angle, tension, c)
                        < potential(&kinematics, angle, tension, d)
                    {
                        b = d;
                    } else {
                        a = c;
                    }
                }
                let least = 0.5 * (a + b);
                let stretch = least - l0;
                assert!(
                    (state.tendon_length - least).abs() < 0.01 * stretch + 2e-6,
                    "{degrees}° {tension} N: table ℓ − ℓ₀ = {:.4} mm, least Π at {:.4} mm",
                    1e3 * (state.tendon_length - l0),
                    1e3 * stretch
                );
                // The interpolated pose is the kinematics' at that length.
                let exact = kinematics
                    .with_tendon_length(state.tendon_length)
                    .patella_pose(angle)
                    .unwrap();
                assert!(
                    (state.pose.centre - exact.centre).norm() < 5e-6,
                    "{degrees}° {tension} N: {:?} {:?}",
                    state.pose.centre,
                    exact.centre
                );
                assert!((state.pose.flexion - exact.flexion).abs() < 1e-3);
                // The tendon carries r T.
                let share = state.tendon_force / tension;
                assert!((share - state.force_ratio).abs() < 1e-6 * share, "{share}");
            }
        }
    }

    #[test]
    fn the_tendon_takes_all_the_pull_near_extension_and_about_half_at_ninety_degrees() {
        // r = −∂W*/∂ℓ is the tendon's share of the pull, by virtual work: about 1 at small
        // flexion and ≈ 0.54 at 90° with a slack tendon (see `kinematics`).
        let near_extension = table().equilibrium(0.1, 1.0).force_ratio;
        let flexed = table()
            .equilibrium(std::f64::consts::FRAC_PI_2, 1.0)
            .force_ratio;
        assert!((0.9..1.1).contains(&near_extension), "{near_extension}");
        assert!((0.45..0.65).contains(&flexed), "{flexed}");
    }

    #[test]
    fn without_a_pull_the_patella_stays_where_the_muscles_were_meshed() {
        let patella = TendonPatella::new(
            table().clone(),
            Squat::to_ninety_degrees(2.0),
            ClosedChain::procedural_knee(),
        );
        let iso = patella.isometry_at(0.0);
        assert!(iso.translation.vector.norm() < 1e-15);
        assert!(iso.rotation.angle() < 1e-15);
        let reference = kinematics().patella_pose(0.0).unwrap();
        assert!((patella.reference_point() - reference.centre).norm() < 1e-15);
        // With a pull the patella rises along the groove: the tendon lengthens.
        patella.report(0.0, 2000.0);
        let state = patella.state_at(0.2);
        assert!(state.tendon_length > table().tendon().slack_length);
        let slack = table().pose(state.knee_angle, 0.0);
        assert!(state.pose.centre.y > slack.centre.y + 1e-3);
    }

    #[test]
    fn the_applied_pull_follows_the_measured_one_through_two_stages_without_jumps() {
        let patella = TendonPatella::new(
            table().clone(),
            Squat::to_ninety_degrees(2.0),
            ClosedChain::procedural_knee(),
        );
        assert_eq!(patella.tension_at(0.3), 0.0);
        let tau = PULL_RELAXATION_TIME;
        patella.report(0.1, 1000.0);
        // Two stages from rest towards a step of 1000 N: 1000 (1 − (1 + s) e^{−s}), s = t/τ.
        assert_eq!(patella.tension_at(0.1), 0.0);
        let step = |s: f64| 1000.0 * (1.0 - (1.0 + s) * (-s).exp());
        let later = patella.tension_at(0.1 + tau);
        assert!((later - step(1.0)).abs() < 1e-9, "{later}");
        // Integrating the two stages' equations with small explicit steps gives the same.
        let (mut first, mut applied, dt) = (0.0, 0.0, 1e-6 * tau);
        for _ in 0..1_000_000 {
            let rate = (first - applied) / tau;
            first += dt * (1000.0 - first) / tau;
            applied += dt * rate;
        }
        assert!((applied - later).abs() < 1e-3, "{applied} {later}");
        // A new report starts from where both stages had got to: T_a and its slope are
        // continuous.
        let slope = |t: f64| (patella.tension_at(t + 1e-7) - patella.tension_at(t)) / 1e-7;
        let slope_before = slope(0.1 + tau - 2e-7);
        patella.report(0.1 + tau, 3000.0);
        assert!((patella.tension_at(0.1 + tau) - later).abs() < 1e-9);
        assert!((slope(0.1 + tau) - slope_before).abs() < 1e-3 * slope_before);
        assert!(patella.tension_at(0.1 + 30.0 * tau) > 2999.0);
        // A second report at the same time replaces the measured pull only.
        patella.report(0.1 + tau, 0.0);
        assert!((patella.tension_at(0.1 + tau) - later).abs() < 1e-9);
        assert!(patella.tension_at(0.1 + 30.0 * tau) < 1e-3);
        // The cached pose follows a new report.
        let before = patella.isometry_at(0.5);
        patella.report(0.3, 5000.0);
        let after = patella.isometry_at(0.5);
        assert!((after.translation.vector - before.translation.vector).norm() > 1e-3);
    }

    #[test]
    fn a_pull_beyond_the_tables_strain_is_flagged() {
        let state = table().equilibrium(0.5, 1e6);
        assert!(state.beyond_table);
        assert!((state.tendon_strain - LARGEST_TENDON_STRAIN).abs() < 1e-12);
    }
}

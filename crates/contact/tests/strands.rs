//! Tendon strands pulling a block through a node in no element, carried by a rigid tie
//! (the quadriceps' strands and the patella, in small).
//!
//! A column of 1 × 1 × 4 hex8 (side A, length L) stands on z = 0 (held along z), every
//! node of it held laterally (uniaxial strain, so that the state stays homogeneous
//! whatever the strands' slant). Its four top corners are each joined by a strand to one
//! extra node P, on the column's axis at D above it, belonging to no element and carried
//! by a rigid tie up by δ. Each strand's slack length is its initial length.
//!
//! - The tie's reaction is the strands' pull Σ f_i e_i, from the final positions.
//! - The stretch λ of the column solves the springs in series with the block: with the
//!   corners at r = A/√2 from the axis and v = L + D + δ − λL below P, ℓ = √(r² + v²),
//!   4 f(ℓ) v/ℓ = σ_zz(λ) A², σ_zz = μ λ^(−5/3) (2/3)(λ² − 1) + K (λ − 1) the neo-Hookean
//!   Cauchy stress in uniaxial strain (`musclefem_materials::neo_hookean`).
//! - A run resumed from a checkpoint records what the uninterrupted one does, bit for bit.

mod common;

use std::ops::ControlFlow;

use nalgebra::Vector3;

use musclefem_contact::{Strand, TendonStrands};
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit_with};
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_with};
use musclefem_core::solver::observer::{NoObserver, Observer, Record, Snapshot};
use musclefem_core::solver::{
    Analysis, Checkpoint, Interaction, InteractionReport, Loads, Problem, RigidMotion,
    RigidReaction, RigidTie, SolverError, resume, run,
};
use musclefem_materials::Amplitude;

use common::*;

const A: f64 = 0.01;
const L: f64 = 0.02;
/// Height of P above the top face [m].
const D: f64 = 0.05;
/// Rise of P [m].
const DELTA: f64 = 0.008;
/// k = E A [N] and ε_l of every strand.
const STRAIN_STIFFNESS: f64 = 5.0;
const TOE_STRAIN: f64 = 0.03;

/// The column and P (the last node), and the strands from its top corners to P.
fn column() -> (Mesh, Vec<Strand>) {
    let mut mesh = box_of_hexes([A, A, L], [1, 1, 4]).unwrap();
    let p = mesh.node_count() as u32;
    let top = Vector3::new(0.5 * A, 0.5 * A, L + D);
    mesh.nodes.push(top);
    let strands = mesh
        .node_set("z1")
        .unwrap()
        .iter()
        .map(|&corner| Strand {
            node_a: corner,
            node_b: p,
            slack_length: (top - mesh.nodes.position(corner as usize)).norm(),
            strain_stiffness: STRAIN_STIFFNESS,
            toe_strain: TOE_STRAIN,
        })
        .collect();
    (mesh, strands)
}

/// z0 held along z, every column node held laterally, P carried up by `rise` by the
/// rigid tie `patella`.
fn loads(mesh: &Mesh, rise: Amplitude) -> Loads {
    let block: Vec<u32> = (0..mesh.node_count() as u32 - 1).collect();
    Loads {
        displacements: vec![
            held(mesh.node_set("z0").unwrap(), 2),
            held(&block, 0),
            held(&block, 1),
        ],
        rigid_ties: vec![RigidTie {
            name: "patella".to_string(),
            nodes: vec![mesh.node_count() as u32 - 1],
            motion: RigidMotion {
                translation: [None, None, Some(rise)],
                ..RigidMotion::default()
            },
        }],
        ..Loads::default()
    }
}

fn interactions(mesh: &Mesh, strands: Vec<Strand>) -> Vec<Box<dyn Interaction>> {
    let strands = TendonStrands::new("quadriceps", strands, Some(mesh.node_count())).unwrap();
    vec![Box::new(strands)]
}

/// The stretch λ of the column in series with the strands (module documentation), by
/// bisection on [1, 1 + δ/L].
fn closed_form_stretch() -> f64 {
    let law = musclefem_contact::ToeLinearLaw {
        strain_stiffness: STRAIN_STIFFNESS,
        toe_strain: TOE_STRAIN,
    };
    let r = A / 2f64.sqrt();
    let slack = (r * r + D * D).sqrt();
    let imbalance = |stretch: f64| {
        let v = L + D + DELTA - stretch * L;
        let length = (r * r + v * v).sqrt();
        let pull = 4.0 * law.force(length / slack - 1.0) * v / length;
        let stress = MU * stretch.powf(-5.0 / 3.0) * (2.0 / 3.0) * (stretch * stretch - 1.0)
            + BULK * (stretch - 1.0);
        pull - stress * A * A
    };
    let (mut low, mut high) = (1.0, 1.0 + DELTA / L);
    assert!(imbalance(low) > 0.0 && imbalance(high) < 0.0);
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if imbalance(middle) > 0.0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// Σ f_i e_i, the strands' pull on their top corners at the final `displacement`, from
/// the law itself; and Σ f_i cos θ_i, θ_i the slant of strand i from the axis.
fn pull_of_the_strands(
    mesh: &Mesh,
    strands: &[Strand],
    displacement: &[Vector3<f64>],
) -> (Vector3<f64>, f64) {
    let position = |n: u32| mesh.nodes.position(n as usize) + displacement[n as usize];
    let mut pull = Vector3::zeros();
    let mut axial_tension = 0.0;
    for strand in strands {
        let state = strand.state(position(strand.node_b) - position(strand.node_a));
        assert!(state.is_taut());
        pull += state.pull_on_a();
        axial_tension += state.tension * state.separation.z / state.length;
    }
    (pull, axial_tension)
}

/// The column's stretch: every top corner's rise over L (they must agree).
fn stretch(mesh: &Mesh, displacement: &[Vector3<f64>]) -> f64 {
    let rises: Vec<f64> = mesh
        .node_set("z1")
        .unwrap()
        .iter()
        .map(|&n| displacement[n as usize].z)
        .collect();
    for rise in &rises {
        assert!((rise - rises[0]).abs() < 1e-12 * rises[0], "{rises:?}");
    }
    1.0 + rises[0] / L
}

/// The tie's reaction is Σ f_i e_i to `tolerance`: along the axis Σ f_i cos θ_i, across
/// it nothing (the strands' slants cancel).
fn check_the_tie(tie: &RigidReaction, pull: Vector3<f64>, axial_tension: f64, tolerance: f64) {
    let error = (tie.force - pull).norm() / pull.norm();
    println!(
        "tie reaction {:?} N, Σ f e {:?} N (relative {error:.1e}), Σ f cos θ {axial_tension:.9e} N",
        tie.force, pull
    );
    assert!(error < tolerance, "relative difference {error:.2e}");
    assert!((tie.force.z - axial_tension).abs() < tolerance * axial_tension);
    assert!(tie.force.xy().norm() < tolerance * axial_tension);
}

#[test]
fn implicit_the_ties_reaction_is_the_strands_pull_and_the_stretch_is_in_series() {
    let (mesh, strands) = column();
    let loads = loads(&mesh, Amplitude::ramp(1.0, DELTA).unwrap());
    let mut interactions = interactions(&mesh, strands.clone());
    let result = run_implicit_with(
        &mesh,
        &parts(&mesh),
        &loads,
        &mut interactions,
        &ImplicitSettings::new(1.0, 8),
        &mut NoObserver,
    )
    .expect("the pulled column converges");
    let last = result.history.last().unwrap();
    let (pull, axial_tension) = pull_of_the_strands(&mesh, &strands, &result.displacement);
    let tie = &last.rigid_reactions[0];
    check_the_tie(tie, pull, axial_tension, 1e-9);
    let report = &last.interactions[0];
    assert_eq!(report.active_points, 4);
    assert!((report.force - pull).norm() < 1e-12 * pull.norm());
    // The base carries the pull: its reaction balances the tie's to the Newton tolerance.
    let base = last.reactions[0];
    assert!(
        (base + tie.force.z).abs() < 1e-8 * tie.force.z,
        "base {base} N"
    );

    let (fe, exact) = (stretch(&mesh, &result.displacement), closed_form_stretch());
    let error = (fe - exact).abs() / (exact - 1.0);
    println!(
        "implicit: λ = {fe:.12} (closed form {exact:.12}, {error:.1e} of the strain), \
         strand strain {:.4}, iterations {:?}",
        pull_strain(&mesh, &strands, &result.displacement),
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    );
    assert!(error < 1e-10, "stretch {fe} against {exact}");
}

/// The strain of the strands at the end (all equal).
fn pull_strain(mesh: &Mesh, strands: &[Strand], displacement: &[Vector3<f64>]) -> f64 {
    let s = &strands[0];
    let x = |n: u32| mesh.nodes.position(n as usize) + displacement[n as usize];
    (x(s.node_b) - x(s.node_a)).norm() / s.slack_length - 1.0
}

/// 0 → `value` over [0, `time`] along 3s² − 2s³, at 1025 knots: the explicit run starts
/// and ends the rise without a jolt.
fn smooth_rise(time: f64, value: f64) -> Amplitude {
    let knots = (0..=1024)
        .map(|i| {
            let s = i as f64 / 1024.0;
            (s * time, value * s * s * (3.0 - 2.0 * s))
        })
        .collect();
    Amplitude::new(knots).unwrap()
}

/// The same column in the explicit solver, P rising over 0.5 s (~70 periods of the
/// column's axial mode): the tie's reaction is still the strands' pull (P has no mass),
/// and the stretch is the static one to the dynamics' small remainder.
#[test]
fn explicit_the_ties_reaction_is_the_strands_pull_and_the_stretch_is_in_series() {
    let (mesh, strands) = column();
    let end = 0.5;
    let loads = loads(&mesh, smooth_rise(end, DELTA));
    let mut interactions = interactions(&mesh, strands.clone());
    let result = run_explicit_with(
        &mesh,
        &parts(&mesh),
        &loads,
        &mut interactions,
        &ExplicitSettings::new(end),
        &mut NoObserver,
    )
    .expect("the pulled column runs");
    let last = result.history.last().unwrap();
    let (pull, axial_tension) = pull_of_the_strands(&mesh, &strands, &result.displacement);
    check_the_tie(&last.rigid_reactions[0], pull, axial_tension, 1e-9);
    let (fe, exact) = (stretch(&mesh, &result.displacement), closed_form_stretch());
    let error = (fe - exact).abs() / (exact - 1.0);
    println!(
        "explicit: λ = {fe:.8} (closed form {exact:.8}, {error:.1e} of the strain), {} steps",
        result.steps
    );
    assert!(error < 1e-4, "stretch {fe} against {exact}");
}

/// Keeps every recorded instant's strand totals and tie reaction, the last strand nodal
/// fields, and the checkpoint taken at the `checkpoint_at`-th instant.
struct Recorder {
    checkpoint_at: usize,
    instants: usize,
    rows: Vec<(f64, InteractionReport, RigidReaction)>,
    checkpoint: Option<Checkpoint>,
    fields: Vec<musclefem_core::solver::NodalField>,
}

impl Recorder {
    fn new(checkpoint_at: usize) -> Self {
        Self {
            checkpoint_at,
            instants: 0,
            rows: Vec::new(),
            checkpoint: None,
            fields: Vec::new(),
        }
    }
}

impl Observer for Recorder {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        self.instants += 1;
        let row = (
            record.time(),
            record.interactions()[0].clone(),
            record.rigid_reactions()[0],
        );
        self.rows.push(row);
        self.fields = snapshot.nodal_fields();
        ControlFlow::Continue(())
    }
    fn wants_checkpoint(&mut self) -> bool {
        self.instants == self.checkpoint_at
    }
    fn checkpoint(&mut self, checkpoint: Result<Checkpoint, SolverError>) -> ControlFlow<()> {
        self.checkpoint = Some(checkpoint.unwrap());
        ControlFlow::Continue(())
    }
}

/// A run resumed from a checkpoint, with strands built afresh, records the same strand
/// totals, tie reactions and strand fields as the uninterrupted run, bit for bit.
#[test]
fn implicit_a_run_with_strands_resumes_bit_for_bit() {
    let (mesh, strands) = column();
    let loads = loads(&mesh, Amplitude::ramp(1.0, DELTA).unwrap());
    let parts = parts(&mesh);
    let analysis = Analysis::Implicit(ImplicitSettings::new(1.0, 8));
    let mut whole = Recorder::new(4);
    let mut fresh = interactions(&mesh, strands.clone());
    let problem = Problem {
        mesh: &mesh,
        parts: &parts,
        loads: &loads,
        interactions: &mut fresh,
    };
    let uninterrupted = run(problem, &analysis, &mut whole).unwrap();
    let mut resumed = Recorder::new(usize::MAX);
    let mut rebuilt = interactions(&mesh, strands);
    let problem = Problem {
        mesh: &mesh,
        parts: &parts,
        loads: &loads,
        interactions: &mut rebuilt,
    };
    let checkpoint = whole
        .checkpoint
        .as_ref()
        .expect("a checkpoint at instant 4");
    let outcome = resume(problem, &analysis, checkpoint, &mut resumed).unwrap();
    assert_eq!(
        resumed.rows[..],
        whole.rows[whole.rows.len() - resumed.rows.len()..]
    );
    assert!(resumed.rows.len() >= 4 && resumed.rows.last().unwrap().1.active_points == 4);
    assert_eq!(resumed.fields, whole.fields);
    let field = |name: &str| whole.fields.iter().any(|f| f.name.ends_with(name));
    assert!(field("strand_tension") && field("strand_force"));
    assert_eq!(outcome.displacement(), uninterrupted.displacement());
}

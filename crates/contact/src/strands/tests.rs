//! The strands' law, forces, consistent tangent, totals, checkpoint and refusals.

use musclefem_core::solver::{CheckpointReader, CheckpointWriter, Interaction};
use nalgebra::{DMatrix, Vector3};

use super::*;

/// k = E A [N] and ε_l of the test strands.
const K: f64 = 250.0;
const TOE: f64 = 0.03;
const SLACK: f64 = 0.04;

fn strand(node_a: u32, node_b: u32) -> Strand {
    Strand {
        node_a,
        node_b,
        slack_length: SLACK,
        strain_stiffness: K,
        toe_strain: TOE,
    }
}

/// Node 0 at a fixed point, node 1 along a skew direction at `strain` from it.
fn pair_at(strain: f64) -> Vec<Vector3<f64>> {
    let a = Vector3::new(0.013, -0.021, 0.034);
    let e = Vector3::new(0.3, -0.5, 0.81).normalize();
    vec![a, a + e * SLACK * (1.0 + strain)]
}

/// The forces of `strands` at `positions`, flattened.
fn forces(strands: &mut TendonStrands, positions: &[Vector3<f64>]) -> Vec<f64> {
    let mut force = vec![Vector3::zeros(); positions.len()];
    strands.forces(0.0, positions, true, &mut force).unwrap();
    force.iter().flat_map(|f| f.iter().copied()).collect()
}

/// The assembled stiffness ∂f_c/∂x of `strands` at `positions` (3n × 3n).
fn stiffness(strands: &mut TendonStrands, positions: &[Vector3<f64>]) -> DMatrix<f64> {
    forces(strands, positions);
    let n = 3 * positions.len();
    let mut k = DMatrix::zeros(n, n);
    strands.stiffness(&mut |a, b, block| {
        let (a, b) = (3 * a as usize, 3 * b as usize);
        let mut view = k.view_mut((a, b), (3, 3));
        view += block;
    });
    k
}

#[test]
fn the_tension_is_the_toe_then_linear_law_of_the_strain() {
    let mut strands = TendonStrands::new("tendon", vec![strand(0, 1)], Some(2)).unwrap();
    // Slack, toe (k ε²/(4 ε_l) = 250 · 0.02² / 0.12), joint (k ε_l), linear (k (ε − ε_l)).
    for (strain, tension) in [
        (-0.1, 0.0),
        (0.0, 0.0),
        (0.02, 250.0 * 0.0004 / 0.12),
        (0.06, 7.5),
        (0.15, 30.0),
    ] {
        forces(&mut strands, &pair_at(strain));
        let got = strands.states()[0].tension;
        assert!(
            (got - tension).abs() <= 1e-12 * tension.max(1.0),
            "ε = {strain}: {got} N, expected {tension} N"
        );
    }
}

#[test]
fn the_stiffness_is_the_central_difference_of_the_forces_slack_toe_and_linear() {
    for strain in [-0.05, 0.02, 0.045, 0.15] {
        let mut strands = TendonStrands::new("tendon", vec![strand(0, 1)], Some(2)).unwrap();
        let positions = pair_at(strain);
        let tangent = stiffness(&mut strands, &positions);
        let h = 1e-6 * SLACK;
        let mut difference = DMatrix::zeros(6, 6);
        for j in 0..6 {
            let moved = |sign: f64| {
                let mut p = positions.clone();
                p[j / 3][j % 3] += sign * h;
                p
            };
            let plus = forces(&mut strands, &moved(1.0));
            let minus = forces(&mut strands, &moved(-1.0));
            for i in 0..6 {
                difference[(i, j)] = (plus[i] - minus[i]) / (2.0 * h);
            }
        }
        let scale = tangent.amax();
        if strain < 0.0 {
            assert_eq!(scale, 0.0, "a slack strand has no stiffness");
            assert_eq!(difference.amax(), 0.0);
            continue;
        }
        let error = (&difference - &tangent).amax() / scale;
        println!("ε = {strain}: |K_fd − K| / |K| = {error:.1e}");
        assert!(error < 1e-6, "ε = {strain}: relative error {error:.2e}");
        assert_eq!(tangent, tangent.transpose(), "ε = {strain}: not symmetric");
    }
}

#[test]
fn a_compressed_strand_pushes_nothing_and_a_taut_one_pulls_its_ends_together() {
    let mut strands = TendonStrands::new("tendon", vec![strand(0, 1)], Some(2)).unwrap();
    let compressed = pair_at(-0.3);
    assert!(forces(&mut strands, &compressed).iter().all(|&f| f == 0.0));
    assert!(
        stiffness(&mut strands, &compressed)
            .iter()
            .all(|&k| k == 0.0)
    );
    assert_eq!(strands.taut_count(), 0);
    assert_eq!(strands.report().force, Vector3::zeros());

    let stretched = pair_at(0.1);
    let f = forces(&mut strands, &stretched);
    let e = (stretched[1] - stretched[0]).normalize();
    let tension = K * (0.1 - TOE);
    // f_c,a = −f e (node a pulled towards b), f_c,b = +f e.
    for k in 0..3 {
        assert!((f[k] + tension * e[k]).abs() < 1e-12 * tension);
        assert!((f[3 + k] - tension * e[k]).abs() < 1e-12 * tension);
    }
}

#[test]
fn the_report_sums_the_pulls_counts_the_taut_strands_and_the_energy() {
    // A fan: nodes 1, 2, 3 each tied to node 0; strand 2 slack.
    let b = Vector3::new(0.0, 0.0, 0.1);
    let ends = [
        Vector3::new(0.01, 0.0, 0.0),
        Vector3::new(0.0, 0.02, 0.0),
        Vector3::new(-0.01, -0.01, 0.09),
    ];
    let list: Vec<Strand> = (1..=3)
        .map(|a| Strand {
            slack_length: 0.09,
            ..strand(a, 0)
        })
        .collect();
    let mut strands = TendonStrands::new("fan", list, Some(4)).unwrap();
    let positions = [vec![b], ends.to_vec()].concat();
    forces(&mut strands, &positions);
    let states = strands.states();
    assert!(states[0].is_taut() && states[1].is_taut() && !states[2].is_taut());
    let report = strands.report();
    assert_eq!(report.name, "fan");
    assert_eq!(report.active_points, 2);
    assert_eq!(strands.taut_count(), 2);
    let pulls: Vector3<f64> = (0..2)
        .map(|i| (b - ends[i]).normalize() * states[i].tension)
        .sum();
    assert!((report.force - pulls).norm() < 1e-12 * pulls.norm());
    let tension = states[0].tension + states[1].tension;
    assert!((strands.total_tension() - tension).abs() < 1e-15 * tension);
    let energy: f64 = (0..2)
        .map(|i| {
            let strain = states[i].length / 0.09 - 1.0;
            0.09 * ToeLinearLaw {
                strain_stiffness: K,
                toe_strain: TOE,
            }
            .energy_per_slack_length(strain)
        })
        .sum();
    assert!((report.stored_energy - energy).abs() < 1e-15 * energy);
    // Per node: node 0 holds both taut strands, and takes the opposite of their pulls.
    let fields = strands.nodal_fields(4);
    assert_eq!(fields[0].name, "strand_tension");
    assert!((fields[0].values[0] - tension).abs() < 1e-15 * tension);
    assert_eq!(fields[0].values[1], states[0].tension);
    assert_eq!(fields[0].values[3], 0.0);
    assert_eq!(fields[1].name, "strand_force");
    for k in 0..3 {
        assert!((fields[1].values[k] + pulls[k]).abs() < 1e-12 * pulls.norm());
    }
}

#[test]
fn a_checkpoint_restores_the_last_evaluation_bit_for_bit() {
    let list = vec![strand(0, 1), strand(2, 1)];
    let mut strands = TendonStrands::new("tendon", list, Some(3)).unwrap();
    let mut positions = pair_at(0.08);
    positions.push(positions[0] + Vector3::new(0.0, 0.001, -0.002));
    forces(&mut strands, &positions);
    let mut out = CheckpointWriter::new();
    strands.save_state(&mut out).unwrap();
    let bytes = out.into_bytes();

    let mut resumed = TendonStrands::new("tendon", strands.strands().to_vec(), Some(3)).unwrap();
    let mut input = CheckpointReader::new(&bytes);
    resumed.restore_state(&mut input).unwrap();
    input.finish().unwrap();
    assert_eq!(resumed.states(), strands.states());
    assert_eq!(resumed.report(), strands.report());
    assert_eq!(resumed.nodal_fields(3), strands.nodal_fields(3));
    // A checkpoint of other strands is refused.
    let mut other = TendonStrands::new("tendon", vec![strand(0, 1)], Some(3)).unwrap();
    assert!(
        other
            .restore_state(&mut CheckpointReader::new(&bytes))
            .is_err()
    );
}

#[test]
fn a_bad_strand_is_refused_by_its_index() {
    let build = |bad: Strand, node_count| {
        TendonStrands::new(
            "quadriceps",
            vec![strand(0, 1), strand(2, 1), bad],
            node_count,
        )
        .unwrap_err()
    };
    let cases = [
        (
            Strand {
                slack_length: 0.0,
                ..strand(0, 1)
            },
            "strand 2: slack length 0 m must be positive",
        ),
        (
            Strand {
                strain_stiffness: -1.0,
                ..strand(0, 1)
            },
            "strand 2: strain stiffness -1 N must be positive",
        ),
        (
            Strand {
                toe_strain: f64::NAN,
                ..strand(0, 1)
            },
            "strand 2: toe strain NaN must be zero or positive",
        ),
        (strand(4, 4), "strand 2 joins node 4 to itself"),
        (
            strand(0, 9),
            "strand 2: node 9 does not exist (the mesh has 5)",
        ),
    ];
    for (bad, message) in cases {
        let error = build(bad, Some(5)).to_string();
        assert!(
            error.starts_with("tendon strands 'quadriceps': ") && error.contains(message),
            "{error}"
        );
    }
    // Without a node count, node ids are not checked.
    assert!(TendonStrands::new("quadriceps", vec![strand(0, 9)], None).is_ok());
    assert!(matches!(
        TendonStrands::new("quadriceps", Vec::new(), None),
        Err(StrandError::Empty { .. })
    ));
    // A zero toe strain is a linear law.
    assert!(
        TendonStrands::new(
            "quadriceps",
            vec![Strand {
                toe_strain: 0.0,
                ..strand(0, 1)
            }],
            Some(2)
        )
        .is_ok()
    );
}

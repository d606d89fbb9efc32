//! The Visible Human knee's mechanism (its patella on the fitted landmarks, each muscle's
//! line of action from its release point to its attachment) against the
//! Rajagopal–Lai–Uhlrich 2023 OpenSim model (`../shared/data/knee_reference/`): the
//! musculotendon excursion L(θ) − L(0°) that the squat imposes on each quadriceps.
//!
//! The excursion is what stretches the muscles, so it is what the squat's stresses
//! depend on. The moment arms r = dL/dθ, its slope, are printed beside it. With a fixed
//! flexion axis they were within 20 % of OpenSim's at 30° and 90° but not at 0° (VL, VM,
//! RF: +26 to +44 %) or 60° (all four: −26 to −33 %), where the mechanism's moment arm
//! falls monotonically with flexion and OpenSim's peaks at 30–45° (`docs/knee-model.md`,
//! "The Visible Human knee assembled"). The squat's mechanism now has the femur roll back
//! over the tibia in early flexion (`mechanism::rolling`), which brings the worst entry to
//! about 27 %; the test checks that it is closer than the fixed axis. Issue #35 asks for
//! the moment arms within 20 %; this test does not assert that, because it does not hold
//! yet.

use std::path::PathBuf;

use musclefem_studies::knee::anatomy::rollback::Rollback;
use musclefem_studies::knee::anatomy::visible_human::mechanism::{
    kinematics, lengths, moment_arms_at,
};
use musclefem_studies::knee::anatomy::visible_human::tracking::PatellaTracking;
use musclefem_studies::knee::anatomy::visible_human::{MeshResolution, VisibleHumanKnee};
use musclefem_studies::knee::anatomy::{KneeDimensions, KneeKinematics, Quadriceps};

/// The Rajagopal–Lai–Uhlrich table: (knee flexion [°], then per muscle in
/// [`Quadriceps::ALL`] order its musculotendon length [m] and moment arm [m]).
fn rajagopal() -> Vec<(f64, Vec<(f64, f64)>)> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(
        "../../../shared/data/knee_reference/rajagopal_lai_uhlrich2023_quadriceps_vs_knee.csv",
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "reference data {} is missing ({e}); it lives in ../shared/data beside the checkout",
            path.display()
        )
    });
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let prefix = |muscle: Quadriceps| match muscle {
        Quadriceps::VastusIntermedius => "vasint_r",
        Quadriceps::VastusLateralis => "vaslat_r",
        Quadriceps::VastusMedialis => "vasmed_r",
        Quadriceps::RectusFemoris => "recfem_r",
    };
    lines
        .map(|line| {
            let fields: Vec<f64> = line.split(',').map(|f| f.trim().parse().unwrap()).collect();
            let muscles = Quadriceps::ALL
                .iter()
                .map(|&m| {
                    (
                        fields[column(&format!("{}_mtu_length_m", prefix(m)))],
                        fields[column(&format!("{}_knee_extensor_moment_arm_m", prefix(m)))],
                    )
                })
                .collect();
            (fields[column("knee_flexion_deg")], muscles)
        })
        .collect()
}

/// Prints the excursions and moment arms of `kinematics` against the reference and
/// returns the largest |difference| of the excursions (30°, 60°, 90°) and of the moment
/// arms (0°, 30°, 60°, 90°), as fractions.
fn compare(kinematics: &KneeKinematics, reference: &[(f64, Vec<(f64, f64)>)]) -> (f64, f64) {
    let length_at = |degrees: f64| {
        lengths(
            kinematics,
            &kinematics.patella_pose(degrees.to_radians()).unwrap(),
        )
    };
    let reference_at = |degrees: f64| {
        &reference
            .iter()
            .find(|(angle, _)| *angle == degrees)
            .unwrap_or_else(|| panic!("no row at {degrees}° in the reference"))
            .1
    };
    let extended = length_at(0.0);
    let reference_extended = reference_at(0.0);
    println!("excursion L(θ) − L(0°) [mm] and moment arm [mm]: ours / Rajagopal–Lai–Uhlrich");
    let (mut worst_excursion, mut worst_arm): (f64, f64) = (0.0, 0.0);
    for degrees in [0.0, 30.0, 60.0, 90.0] {
        let ours = length_at(degrees);
        let arms = moment_arms_at(kinematics, degrees.to_radians()).unwrap();
        let theirs = reference_at(degrees);
        for (m, muscle) in Quadriceps::ALL.iter().enumerate() {
            let excursion = ours[m] - extended[m];
            let reference_excursion = theirs[m].0 - reference_extended[m].0;
            let arm_difference = arms[m] / theirs[m].1 - 1.0;
            worst_arm = worst_arm.max(arm_difference.abs());
            let mut line = format!(
                "{degrees:>3}° {:<20} moment arm {:>5.1} / {:>5.1} ({:+5.1} %)",
                format!("{muscle:?}"),
                arms[m] * 1e3,
                theirs[m].1 * 1e3,
                100.0 * arm_difference
            );
            if degrees > 0.0 {
                let difference = excursion / reference_excursion - 1.0;
                worst_excursion = worst_excursion.max(difference.abs());
                line += &format!(
                    ", excursion {:>5.1} / {:>5.1} ({:+5.1} %)",
                    excursion * 1e3,
                    reference_excursion * 1e3,
                    100.0 * difference
                );
            }
            println!("{line}");
        }
    }
    println!(
        "largest difference: excursion {:.1} %, moment arm {:.1} %",
        100.0 * worst_excursion,
        100.0 * worst_arm
    );
    (worst_excursion, worst_arm)
}

/// `kinematics` with the femur turning about a fixed flexion axis instead of rolling back.
fn fixed_axis(kinematics: &KneeKinematics) -> KneeKinematics {
    let dimensions = KneeDimensions {
        rollback: Rollback::FIXED_AXIS,
        ..kinematics.dimensions
    };
    KneeKinematics::from_dimensions(dimensions, kinematics.pulls.clone())
}

#[test]
fn the_visible_human_knees_excursions_are_within_twenty_percent_of_opensims() {
    let knee = VisibleHumanKnee::load(MeshResolution::Coarse).unwrap();
    let reference = rajagopal();
    let rolling = kinematics(&knee).unwrap();
    println!(
        "the squat's mechanism, the femur rolling back over the tibia ({:?}):",
        rolling.dimensions.rollback
    );
    let (excursion, rolling_arm) = compare(&rolling, &reference);
    // Issue #35's tolerance for the mechanism (20 %), on the length change it imposes.
    assert!(
        excursion <= 0.20,
        "an excursion differs by {:.1} %",
        100.0 * excursion
    );
    // The same mechanism on a fixed flexion axis: further from OpenSim's moment arms at
    // the worst entry, its excursions within 20 % too.
    println!("on a fixed flexion axis:");
    let fixed = fixed_axis(&rolling);
    let (excursion, fixed_arm) = compare(&fixed, &reference);
    assert!(
        excursion <= 0.20,
        "on a fixed axis, an excursion differs by {:.1} %",
        100.0 * excursion
    );
    assert!(
        rolling_arm < fixed_arm - 0.1,
        "the rollback's worst moment arm is {:.1} % off, the fixed axis's {:.1} %",
        100.0 * rolling_arm,
        100.0 * fixed_arm
    );
}

/// Issue #35's patellar tracking: the mechanism's patella is planar (it keeps its
/// mediolateral position and tilt), so what can be checked is that it stays in the
/// trochlear groove of the Visible Human's distal femoral cartilage: above the trochlea in
/// extension, and from 15° on never further from the groove's floor than half the way to
/// the nearer facet crest, with and without the femur's rollback.
#[test]
fn the_planar_patella_stays_in_the_trochlear_groove() {
    let knee = VisibleHumanKnee::load(MeshResolution::Coarse).unwrap();
    let rolling = kinematics(&knee).unwrap();
    let fixed = fixed_axis(&rolling);
    for (name, kinematics) in [("fixed axis", &fixed), ("rollback", &rolling)] {
        let tracking =
            PatellaTracking::of_visible_human(&knee, kinematics, 90f64.to_radians()).unwrap();
        println!("{name}:\n{}{}", tracking.csv(), tracking.summary());
        assert!(
            tracking.rows[0].1.is_none(),
            "{name}: in extension the patella lies above the trochlea"
        );
        for (angle, section) in &tracking.rows {
            let degrees = angle.to_degrees();
            if degrees < 15.0 {
                continue;
            }
            let section = section
                .unwrap_or_else(|| panic!("{name}: no groove under the patella at {degrees}°"));
            let off_floor = tracking.ridge - section.floor;
            let room = (section.floor - section.crests[0]).min(section.crests[1] - section.floor);
            assert!(
                off_floor.abs() < 0.5 * room,
                "{name}, {degrees}°: the ridge is {:.1} mm off the floor, the nearer crest {:.1} mm",
                off_floor * 1e3,
                room * 1e3
            );
        }
    }
}

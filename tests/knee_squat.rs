//! The procedural knee's squat pipeline through the library, on the coarse mesh: a shallow
//! passive squat run as its scene (as `musclefem knee` runs it) with loads a relaxed
//! quadriceps can have, and the interactions bonded stress-free at 0°. (The whole squat
//! through the command line, and the command's arguments, are tested in
//! `crates/cli/tests/knee_squat.rs`.)

use std::path::{Path, PathBuf};

use musclefem_studies::elongation::Solver;
use musclefem_studies::knee::simulation::interactions::{InterfaceLaw, knee_interactions};
use musclefem_studies::knee::simulation::{
    Activation, KneeGeometry, KneeModel, SquatSettings, run_squat_in,
};
use musclefem_studies::knee::{Anatomy, Resolution, Squat};
use nalgebra::Vector3;

fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("knee_squat")
        .join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The whole pipeline of the procedural knee (closed chain, fibers, tendons, sliding
/// interfaces, contact, the patella on its tendon, implicit Newmark) on a squat small
/// enough for every test run (~160 s in release on 2 cores: 117 increments of 2–15 ms):
/// coarse, passive, 0° → 30° → 0° in 0.6 s (about as fast at 30° as the 2 s squat to
/// 90°). It converges to the end with no inverted element; at 30° the loads stay within
/// the bounds below, which a relaxed quadriceps must meet (tens of kPa, tens of newtons:
/// a knee bent 30° needs no force). Measured 2026-11-26: vm95 8.0 / 5.7 / 11.0 / 2.7 kPa
/// (VI / VL / VM / RF), pull 31 N, fiber stretch 95th percentile 1.118, and 1.014 back
/// at 0° (the whole squat at 30°: 8.0 / 6.1 / 6.7 / 2.1 kPa, 39 N, 1.107).
#[test]
fn a_shallow_passive_squat_runs_the_whole_pipeline_with_plausible_loads() {
    let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
    let mut settings = SquatSettings::recommended(Solver::Implicit);
    settings.squat = Squat {
        duration: 0.6,
        peak_flexion: 30f64.to_radians(),
    };
    let geometry = KneeGeometry::procedural_knee(&anatomy, &settings.squat).unwrap();
    let fibers = geometry.fibers().unwrap();
    // Run as its scene, as `musclefem knee` runs it.
    let out = test_dir("shallow");
    let run = run_squat_in(&geometry, &fibers, Activation::Passive, &settings, &out).unwrap();
    for file in ["scene.toml", "history.csv", "run.log"] {
        assert!(out.join(file).is_file(), "the run wrote no {file}");
    }
    eprintln!(
        "shallow squat: {} increments, {:?} iterations, {:?} cuts, {:.1} s",
        run.steps,
        run.newton_iterations,
        run.cuts,
        run.solve_time.as_secs_f64()
    );
    let last = run.samples.last().unwrap();
    assert!((last.time - 0.6).abs() < 1e-9, "ended at {} s", last.time);
    assert!(
        run.samples.iter().all(|s| s.min_jacobian_ratio > 0.0),
        "an element inverted"
    );
    // At the deepest point.
    let peak = run
        .samples
        .iter()
        .min_by(|a, b| (a.time - 0.3).abs().total_cmp(&(b.time - 0.3).abs()))
        .unwrap();
    assert!((peak.flexion.to_degrees() - 30.0).abs() < 1.0);
    for (m, vm95) in peak.vm95.iter().enumerate() {
        assert!(
            *vm95 > 100.0 && *vm95 < 30e3,
            "muscle {m}: vm95 {vm95} Pa at 30°"
        );
    }
    let plausibility = run
        .plausibility
        .iter()
        .min_by(|a, b| (a.time - 0.3).abs().total_cmp(&(b.time - 0.3).abs()))
        .unwrap();
    let pull = plausibility.total_pull();
    assert!(pull > 5.0 && pull < 150.0, "pull {pull} N at 30°");
    // Near extension the patella passes the pull on at a ratio near 1 (0.92 measured).
    let ratio = plausibility.tendon_force / pull;
    assert!((0.7..1.3).contains(&ratio), "tendon / pull {ratio}");
    assert!(
        plausibility.fiber_stretch_p95 > 1.02 && plausibility.fiber_stretch_p95 < 1.15,
        "fiber stretch p95 {}",
        plausibility.fiber_stretch_p95
    );
    // Back at 0°: unloaded again (the stretch gone, vm95 a small fraction of 30°'s).
    for (m, (end, top)) in last.vm95.iter().zip(&peak.vm95).enumerate() {
        assert!(
            *end < 0.5 * top,
            "muscle {m}: {end} Pa at 0° against {top} Pa at 30°"
        );
    }
    let end = run.plausibility.last().unwrap();
    assert!(end.fiber_stretch_p95 < 1.03, "{}", end.fiber_stretch_p95);
}

#[test]
fn the_procedural_knee_bonds_the_vasti_to_the_intermedius_and_the_femur_stress_free() {
    let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
    let settings = SquatSettings::recommended(Solver::Implicit);
    let geometry = KneeGeometry::procedural_knee(&anatomy, &settings.squat).unwrap();
    let fibers = geometry.fibers().unwrap();
    let model = KneeModel::new(
        &geometry,
        &fibers,
        Activation::Passive,
        &settings.squat,
        settings.element,
    )
    .unwrap();
    let built = knee_interactions(
        &geometry,
        &model.mesh,
        model.material.as_ref(),
        InterfaceLaw::Sliding,
    )
    .unwrap();
    let names: Vec<&str> = built.summaries.iter().map(|s| s.name.as_str()).collect();
    for expected in [
        "VL-VI", "VM-VI", "RF-VI", "VI-femur", "VL-femur", "VM-femur",
    ] {
        assert!(names.contains(&expected), "{names:?}");
    }
    assert_eq!(
        names
            .iter()
            .filter(|n| n.ends_with("-femur-contact"))
            .count(),
        4
    );
    for expected in ["VM-VL-contact", "RF-VL-contact", "RF-VM-contact"] {
        assert!(names.contains(&expected), "{names:?}");
    }
    // At 0° every cohesive bond rests: no force anywhere, though the muscles start 1–4 mm
    // apart. The faceted coarse meshes overlap the femur a little: the contact pushes
    // those nodes out in the first increment; the overlap stays below 1 mm.
    let positions: Vec<Vector3<f64>> = (0..model.mesh.node_count())
        .map(|i| model.mesh.nodes.position(i))
        .collect();
    for interaction in &mut built.solver_interactions() {
        let mut force = vec![Vector3::zeros(); positions.len()];
        interaction.search(0.0, &positions).unwrap();
        interaction
            .forces(0.0, &positions, false, &mut force)
            .unwrap();
        let largest = force.iter().map(|f| f.norm()).fold(0.0, f64::max);
        if interaction.name().ends_with("-contact") {
            let fields = interaction.nodal_fields(positions.len());
            let gap = fields
                .iter()
                .find(|f| f.name.ends_with("contact_gap"))
                .unwrap();
            let deepest = gap.values.iter().fold(0.0f64, |a, &b| a.min(b));
            eprintln!(
                "{}: {largest:.3} N, deepest overlap {:.3} mm",
                interaction.name(),
                -1e3 * deepest
            );
            assert!(deepest > -1e-3, "{}: {deepest} m", interaction.name());
        } else {
            assert!(largest < 1e-12, "{}: {largest} N", interaction.name());
        }
    }
    // The flow solver's fibers fill every belly (the muscle blocks come first; the
    // tendons' blocks follow and keep the swept mesh's direction along the centreline).
    let bellies: usize = (0..geometry.muscles.len())
        .map(|b| model.mesh.blocks[b].len())
        .sum();
    assert!(bellies < model.mesh.element_count());
    assert_eq!(fibers.direction.len(), bellies);
    assert!(
        fibers
            .direction
            .iter()
            .all(|d| (d.norm() - 1.0).abs() < 1e-9)
    );
}

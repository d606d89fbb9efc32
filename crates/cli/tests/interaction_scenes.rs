//! `musclefem run` on scenes with rigid bodies and interactions: the contact force and
//! the cohesive traction reach the history and the frames, and the force balance holds.

mod support;

use support::run;

use run::{example, musclefem, test_dir, text};

use std::path::Path;

use musclefem_io::csv::read_table;
use musclefem_io::output::read_pvd;

/// The history as a header and rows of numbers.
fn history(root: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let path = root.join("history.csv");
    let csv = std::fs::read_to_string(&path).unwrap();
    let header: Vec<String> = csv
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    let rows = read_table(&path, &header.join(",")).unwrap();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

/// Block on a rigid sphere: the support's reaction balances the contact resultant
/// (the block is otherwise free), the contact pushes up, and the frames carry the
/// contact pressure.
#[test]
fn a_block_pressed_on_a_rigid_sphere_balances_the_contact_force() {
    let dir = test_dir("musclefem-interactions", "sphere");
    let out = musclefem(
        &dir,
        &[
            "run",
            &example("block_on_rigid_sphere.toml"),
            "--out",
            "result",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let root = dir.join("result");
    let (header, rows) = history(&root);
    let last = rows.last().unwrap();
    let reaction = last[column(&header, "reaction_block.z1.z_n")];
    let contact = last[column(&header, "indenter_force_z_n")];
    let area = last[column(&header, "indenter_active_area_m2")];
    assert!(contact > 0.0, "the sphere pushes the block up: {contact} N");
    assert!(
        (reaction + contact).abs() <= 1e-6 * contact,
        "support reaction {reaction} N against contact {contact} N"
    );
    assert!(area > 0.0 && area < 4e-4, "contact area {area} m²");
    let frames = read_pvd(&root.join("result.pvd")).unwrap();
    let last_frame = std::fs::read_to_string(root.join(&frames.last().unwrap().file)).unwrap();
    assert!(
        last_frame.contains("Name=\"indenter_contact_pressure\""),
        "the frames carry the contact pressure"
    );
}

/// Two blocks bonded by the cohesive law, pulled apart: the traction follows K_nn δ up to
/// initiation, softens, and the interface carries nothing after failure.
#[test]
fn bonded_blocks_follow_the_cohesive_law_and_separate() {
    let dir = test_dir("musclefem-interactions", "peel");
    let out = musclefem(
        &dir,
        &[
            "run",
            &example("bonded_blocks_peel.toml"),
            "--out",
            "result",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let root = dir.join("result");
    let (header, rows) = history(&root);
    let (time, force, bonded) = (
        column(&header, "time_s"),
        column(&header, "glue_force_z_n"),
        column(&header, "glue_bonded_area_m2"),
    );
    let area = 1e-4;
    let (stiffness, initiation, failure) = (5e4, 0.002, 0.004);
    let mut peak: f64 = 0.0;
    for row in &rows {
        // The interface pulls the upper block down: its force on the nodes is along −z
        // on the upper side and +z on the lower one; the resultant over the secondary
        // (upper) side is what the history reports.
        peak = peak.max(row[force].abs());
        let pulled = 0.006 * row[time];
        if pulled < 0.9 * initiation {
            // Up to initiation the opening is the pull less the blocks' own small stretch
            // (below 2 % here): the traction is K_nn δ within that.
            let traction = row[force].abs() / area;
            let expected = stiffness * pulled;
            assert!(
                (traction - expected).abs() <= 0.02 * expected + 1e-9,
                "t = {} s: traction {traction} Pa, K δ = {expected} Pa",
                row[time]
            );
        }
        if pulled > 1.05 * failure {
            assert!(
                row[force].abs() < 1e-9,
                "after failure at t = {} s the interface still carries {} N",
                row[time],
                row[force]
            );
        }
    }
    let strength = stiffness * initiation * area;
    assert!(
        (peak - strength).abs() <= 0.05 * strength,
        "peak {peak} N against K δ0 A = {strength} N"
    );
    assert!(
        rows[0][bonded] > 0.99 * area,
        "bonded area {}",
        rows[0][bonded]
    );
}

/// Mistakes in an interaction name the line: an unknown main surface (with a
/// suggestion), and a cohesive key on a contact.
#[test]
fn a_bad_interaction_names_its_line() {
    let dir = test_dir("musclefem-interactions", "bad");
    let good = std::fs::read_to_string(example("block_on_rigid_sphere.toml")).unwrap();
    let bad = good.replacen("main = \"ball\"", "main = \"bal\"", 1);
    std::fs::write(dir.join("bad.toml"), &bad).unwrap();
    let out = musclefem(&dir, &["check", "bad.toml"]);
    assert!(!out.status.success());
    let line = bad
        .lines()
        .position(|l| l.starts_with("main = \"bal\""))
        .unwrap()
        + 1;
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(&format!("bad.toml:{line}:")) && stderr.contains("ball"),
        "{stderr}"
    );

    let bad = good.replacen(
        "main = \"ball\"",
        "main = \"ball\"\nbond_tolerance = 1e-3",
        1,
    );
    std::fs::write(dir.join("bad2.toml"), &bad).unwrap();
    let out = musclefem(&dir, &["check", "bad2.toml"]);
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("bond_tolerance") && stderr.contains("does not apply"),
        "{stderr}"
    );
}

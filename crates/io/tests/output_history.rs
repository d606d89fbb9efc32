//! Output: CSV histories of the explicit and implicit solvers.

use std::fs;
use std::path::PathBuf;

use musclefem_core::solver::RigidReaction;
use musclefem_core::solver::explicit::HistoryRow;
use musclefem_core::solver::implicit::{EnergyBalance, ImplicitHistoryRow};
use musclefem_io::csv::read_table;
use musclefem_io::output::{
    ExistingResults, HistoryColumns, HistoryWriter, RunDirectory, write_explicit_history,
    write_implicit_history,
};
use nalgebra::Vector3;

/// A fresh, empty directory for one test.
fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("musclefem-io-history-tests")
        .join(format!("{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn explicit_rows() -> Vec<HistoryRow> {
    (0..7)
        .map(|i| {
            let t = i as f64;
            HistoryRow {
                time: 0.1 * t,
                time_step: 1.6e-6 + 1e-22 * t,
                reactions: vec![1.0 / 3.0 + t, -2.5e-9 * t],
                rigid_reactions: vec![RigidReaction {
                    force: Vector3::new(t, 2.0 * t, 0.1 + 0.2),
                    moment: Vector3::new(-t, 1e300, f64::MIN_POSITIVE),
                }],
                internal_energy: 10.0 + t,
                hourglass_energy: 1e-7 * t,
                viscous_energy: 0.01 * t,
                kinetic_energy: 2.0 / 3.0 * t,
                external_work: 10.5 * t,
                interaction_work: 0.0,
                interactions: vec![],
            }
        })
        .collect()
}

#[test]
fn explicit_history_csv_has_the_documented_header_and_full_precision() {
    let dir = test_dir("history-explicit");
    let path = dir.join("history.csv");
    let columns = HistoryColumns::new(vec!["top".into(), "side-x".into()], vec!["femur".into()]);
    let header = "time_s,time_step_s,reaction_top_n,reaction_side-x_n,\
        reaction_femur_x_n,reaction_femur_y_n,reaction_femur_z_n,\
        moment_femur_x_n_m,moment_femur_y_n_m,moment_femur_z_n_m,\
        internal_energy_j,kinetic_energy_j,external_work_j,viscous_energy_j,hourglass_energy_j";
    assert_eq!(columns.explicit_header(), header);
    let rows = explicit_rows();
    write_explicit_history(&path, &columns, &rows).unwrap();
    assert_eq!(
        fs::read_to_string(&path).unwrap().lines().next().unwrap(),
        header
    );
    let back = read_table(&path, header).unwrap();
    assert_eq!(back.len(), rows.len());
    for (b, r) in back.iter().zip(&rows) {
        let f = r.rigid_reactions[0].force;
        let m = r.rigid_reactions[0].moment;
        let expected = [
            r.time,
            r.time_step,
            r.reactions[0],
            r.reactions[1],
            f.x,
            f.y,
            f.z,
            m.x,
            m.y,
            m.z,
            r.internal_energy,
            r.kinetic_energy,
            r.external_work,
            r.viscous_energy,
            r.hourglass_energy,
        ];
        assert_eq!(
            b.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            expected.map(f64::to_bits)
        );
    }

    // A row with another number of reactions, or a bad name, is refused naming the file.
    let mut bad = rows.clone();
    bad[3].reactions.pop();
    let err = write_explicit_history(&path, &columns, &bad)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("history.csv") && err.contains("t = 0.30000000000000004 s"),
        "{err}"
    );
    let named = HistoryColumns::new(vec!["a,b".into()], vec![]);
    let err = write_explicit_history(&path, &named, &[])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("history.csv") && err.contains("'a,b'"),
        "{err}"
    );
    let twice = HistoryColumns::new(vec!["a".into()], vec!["a".into()]);
    assert!(
        write_explicit_history(&path, &twice, &[])
            .unwrap_err()
            .to_string()
            .contains("two reactions")
    );
    // The failed writes left the complete file of the good run.
    assert_eq!(read_table(&path, header).unwrap().len(), rows.len());
}

#[test]
fn implicit_history_csv() {
    let dir = test_dir("history-implicit");
    let path = dir.join("history.csv");
    let columns = HistoryColumns::new(vec!["z1".into()], vec![]);
    let header = "time_s,time_step_s,newton_iterations,reaction_z1_n,internal_energy_j,\
                  kinetic_energy_j,external_work_j";
    assert_eq!(columns.implicit_header(), header);
    let rows: Vec<ImplicitHistoryRow> = (1..4)
        .map(|i| ImplicitHistoryRow {
            time: 0.1 * i as f64,
            increment: 0.1,
            iterations: i + 2,
            reactions: vec![-1.0 / 7.0 * i as f64],
            rigid_reactions: vec![],
            energy: EnergyBalance {
                kinetic: 1e-3 / 3.0 * i as f64,
                internal_work: 2.0 / 3.0 * i as f64,
                external_work: 0.7 * i as f64,
            },
            interactions: vec![],
        })
        .collect();
    write_implicit_history(&path, &columns, &rows).unwrap();
    let back = read_table(&path, header).unwrap();
    let expected: Vec<Vec<f64>> = rows
        .iter()
        .map(|r| {
            vec![
                r.time,
                r.increment,
                r.iterations as f64,
                r.reactions[0],
                r.energy.internal_work,
                r.energy.kinetic,
                r.energy.external_work,
            ]
        })
        .collect();
    assert_eq!(back, expected);
}

#[test]
fn history_writer_rewrites_the_file_at_the_first_row_and_every_n_rows() {
    let dir = test_dir("history-writer");
    let run = RunDirectory::create(&dir, ExistingResults::Refuse).unwrap();
    let columns = HistoryColumns::new(vec!["top".into(), "side".into()], vec!["femur".into()]);
    let mut writer = run.explicit_history(&columns).unwrap().flush_every(3);
    let path = dir.join("history.csv");
    let header = columns.explicit_header();
    let rows = explicit_rows();
    let on_disk = || read_table(&path, &header).map(|r| r.len()).ok();
    let mut seen = Vec::new();
    for row in &rows {
        writer.push_explicit(row).unwrap();
        seen.push(on_disk());
    }
    // The first row at once (a run killed early keeps it), then every third.
    assert_eq!(
        seen,
        [
            Some(1),
            Some(1),
            Some(1),
            Some(4),
            Some(4),
            Some(4),
            Some(7)
        ]
    );
    let err = writer.push(vec![1.0]).unwrap_err().to_string();
    assert!(
        err.contains("history.csv") && err.contains("15 columns"),
        "{err}"
    );
    writer.finish().unwrap();
    assert_eq!(on_disk(), Some(7));
    // Plain rows need a plain writer.
    let mut plain = HistoryWriter::new(&path, "a,b");
    assert!(plain.push_explicit(&rows[0]).is_err());
}

//! `musclefem sweep` over two MPI ranks (`mpirun -np 2`, cargo feature `mpi`; the
//! packages come from scripts/setup-mpi.sh): the same table as a local sweep.

#![cfg(feature = "mpi")]

mod support;

use std::path::Path;
use std::process::Command;

use support::run::{CHEAP_ELONGATION, musclefem, test_dir, text};

/// The sweep's flags: the cheap model (`CHEAP_ELONGATION`), one run at a time per rank.
fn sweep() -> Vec<&'static str> {
    let mut args = vec!["sweep", "--base", "passive", "--jobs", "1"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    args.extend_from_slice(&["--vary", "sigma0=5e5,7e5,9e5", "--vary", "b=12,18"]);
    args
}

/// The table without the wall times (column 5 of run,sigma0,b,status,wall_time_s,...).
fn without_wall_times(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|line| {
            let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
            cells.remove(4);
            cells
        })
        .collect()
}

#[test]
fn two_ranks_share_the_runs_and_rank_0_writes_the_same_table() {
    let dir = test_dir("sweep_mpi", "two-ranks");
    let mut distributed = Command::new("mpirun");
    distributed
        .args(["-np", "2", env!("CARGO_BIN_EXE_musclefem")])
        .args(sweep())
        .args(["--out", "mpi"])
        // OpenMPI refuses to run as root (containers, CI) without these.
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .current_dir(&dir);
    let out = distributed
        .output()
        .expect("mpirun runs (scripts/setup-mpi.sh)");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("6 to run over 2 MPI ranks"), "{stdout}");
    assert_eq!(
        stdout.matches("elongation (").count(),
        1,
        "rank 0 alone reports: {stdout}"
    );

    let local = musclefem(&dir, &[&sweep()[..], &["--out", "local"]].concat());
    assert!(local.status.success(), "{}", text(&local.stderr));
    let mpi_table = without_wall_times(&dir.join("mpi/sweep.csv"));
    assert_eq!(mpi_table.len(), 7);
    assert!(
        mpi_table[1..].iter().all(|row| row[3] == "ok"),
        "{mpi_table:?}"
    );
    assert_eq!(mpi_table, without_wall_times(&dir.join("local/sweep.csv")));
    assert!(dir.join("mpi/sensitivity.png").exists());
}

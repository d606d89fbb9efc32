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
    // Handed out one at a time: both ranks ran some, six in all.
    let shares = stdout
        .lines()
        .find_map(|l| l.strip_prefix("runs per rank (handed out one at a time): "))
        .unwrap_or_else(|| panic!("no share line: {stdout}"));
    let counts: Vec<usize> = shares
        .split(", ")
        .map(|s| s.rsplit(' ').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(counts.len(), 2, "{shares}");
    assert_eq!(counts.iter().sum::<usize>(), 6, "{shares}");
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

/// A distributed sweep stopped from outside (SIGTERM to mpirun, as a Slurm time limit
/// does) keeps every row finished before it in sweep.csv, whichever rank ran it, and a
/// rerun skips them.
#[test]
fn a_stopped_distributed_sweep_keeps_its_rows_and_a_rerun_skips_them() {
    let dir = test_dir("sweep_mpi", "stopped");
    let mut args = vec!["sweep", "--base", "passive", "--jobs", "1"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    // Runs of about half a second: 0.02 s increments.
    let step = args.iter().position(|a| *a == "--time-step").unwrap() + 1;
    args[step] = "0.02";
    args.extend_from_slice(&["--vary", "sigma0=4e5:1.15e6:16"]);
    args.extend_from_slice(&["--out", "mpi"]);
    let mut child = Command::new("mpirun")
        .args(["-np", "2", env!("CARGO_BIN_EXE_musclefem")])
        .args(&args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("mpirun runs (scripts/setup-mpi.sh)");
    let table = dir.join("mpi/sweep.csv");
    let rows = || {
        std::fs::read_to_string(&table)
            .map(|t| t.lines().count().saturating_sub(1))
            .unwrap_or(0)
    };
    let started = std::time::Instant::now();
    while rows() < 3 && child.try_wait().unwrap().is_none() {
        assert!(started.elapsed().as_secs() < 120, "no rows after 2 min");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let signal = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(signal.success());
    child.wait().unwrap();
    // mpirun may return before its ranks are gone: until then the rerun is refused (the
    // directory's lock), and nothing is written.
    let (kept, rerun) = loop {
        let kept = rows();
        let rerun = musclefem(&dir, &args);
        if !text(&rerun.stderr).contains("another musclefem run") {
            break (kept, rerun);
        }
        assert!(started.elapsed().as_secs() < 180, "the ranks did not end");
        std::thread::sleep(std::time::Duration::from_millis(200));
    };
    assert!((3..16).contains(&kept), "{kept} rows kept");
    assert!(rerun.status.success(), "{}", text(&rerun.stderr));
    let stdout = text(&rerun.stdout);
    assert!(
        stdout.contains(&format!("16 runs, {kept} already in")),
        "{kept} rows kept: {stdout}"
    );
    assert_eq!(rows(), 16);
}

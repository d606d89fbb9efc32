//! A sweep across machines: started under `mpirun` (or `srun`), every MPI rank takes a
//! share of the pending runs (run i of the pending list goes to rank i mod size) and runs
//! it `--jobs` at a time; rank 0 reads and cleans the output directory, writes sweep.csv
//! after each of its own runs, gathers the other ranks' rows when they finish, and writes
//! the whole table and the sensitivities. Only rank 0 touches the files: the output
//! directory need not be shared. The other ranks' rows reach sweep.csv at the end only, so
//! a stopped distributed sweep resumes from rank 0's rows.

use anyhow::{Context, Result};
use mpi::environment::Universe;
use mpi::traits::*;

use super::table;
use super::{Plan, SweepArgs};

/// Environment variables set by the MPI launchers (OpenMPI's mpirun, MPICH/Hydra, Slurm's
/// PMI and PMIx).
const LAUNCHER_VARIABLES: [&str; 3] = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"];

/// MPI, if this process was started by an MPI launcher (`None` otherwise: a local sweep).
pub fn start() -> Result<Option<Universe>> {
    if !LAUNCHER_VARIABLES
        .iter()
        .any(|v| std::env::var_os(v).is_some())
    {
        return Ok(None);
    }
    // Only the main thread calls MPI; the solver's worker threads do not.
    let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)
        .context("initialising MPI (started by an MPI launcher)")?;
    Ok(Some(universe))
}

pub fn sweep(args: &SweepArgs, plan: &Plan, universe: &Universe) -> Result<()> {
    let world = universe.world();
    let (rank, size) = (world.rank(), world.size());
    let root = world.process_at_rank(0);
    // Rank 0 writes the table: it holds the output directory's lock.
    let _lock = if rank == 0 {
        Some(plan.lock_output()?)
    } else {
        None
    };
    // Rank 0 reads (or with --force removes) the previous table and tells the others
    // which runs are done.
    let (done, done_runs) = if rank == 0 {
        let done = plan.previous_records(args.force)?;
        let runs: Vec<u64> = done.iter().map(|r| r.run as u64).collect();
        for other in 1..size {
            world.process_at_rank(other).send(&runs[..]);
        }
        let runs: Vec<usize> = runs.into_iter().map(|r| r as usize).collect();
        (done, runs)
    } else {
        let (runs, _) = root.receive_vec::<u64>();
        let runs: Vec<usize> = runs.into_iter().map(|r| r as usize).collect();
        (Vec::new(), runs)
    };
    let pending = plan.pending(&done_runs);
    let share: Vec<usize> = pending
        .iter()
        .enumerate()
        .filter(|(i, _)| *i as i32 % size == rank)
        .map(|(_, &run)| run)
        .collect();
    if rank == 0 {
        plan.announce(
            done_runs.len(),
            pending.len(),
            &format!(" over {size} MPI ranks"),
        );
        let mut records = plan.run_share(&share, done, true)?;
        for other in 1..size {
            let (bytes, _) = world.process_at_rank(other).receive_vec::<u8>();
            let text = String::from_utf8(bytes).context("rows from another rank")?;
            let source = plan.table_path.with_file_name(format!("(rank {other})"));
            records.extend(table::parse_table(&text, &source, &plan.columns)?);
        }
        plan.write_table(&records)?;
        plan.finish(args, &records)
    } else {
        // A rank whose runs fail to start still reports (no rows) so rank 0 does not wait
        // forever; the error is returned after.
        let result = plan.run_share(&share, Vec::new(), false);
        let rows = result.as_ref().map_or_else(
            |_| table::header(&plan.columns),
            |r| table::format_table(&plan.columns, r),
        );
        root.send(rows.as_bytes());
        result.map(|_| ())
    }
}

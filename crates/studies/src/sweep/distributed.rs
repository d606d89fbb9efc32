//! A sweep across machines: started under `mpirun` (or `srun`), rank 0 hands the pending
//! runs out one at a time to whichever rank asks (no static split: a fast machine takes
//! more runs, a slow one fewer), runs `--jobs` of them itself, and writes `sweep.csv`
//! after every finished row, its own and the other ranks' alike. A sweep stopped by a
//! time limit keeps every finished row, and a rerun (local or distributed) skips them.
//! Only rank 0 touches the files: the output directory need not be shared.
//!
//! Messages (rank 0 is the coordinator, the others are workers; only the main thread of a
//! process calls MPI, the runs go on in its worker threads):
//! - worker → 0, [`REQUEST`]: the table of the run it just finished (header and one row;
//!   empty for its first requests) and a request for another run;
//! - worker → 0, [`ROW`]: a finished run's table, no request (the worker was told there
//!   are no more);
//! - 0 → worker, [`ASSIGN`]: a run number, or [`NO_MORE`];
//! - worker → 0, [`DONE`]: the worker has nothing left (empty, or why its pool failed).

use std::collections::VecDeque;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use anyhow::{Context, Result, anyhow, bail};
use mpi::environment::Universe;
use mpi::point_to_point::MatchedReceiveVec;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use super::table::{self, Record};
use super::{Plan, SweepArgs};

/// Environment variables set by the MPI launchers (OpenMPI's mpirun, MPICH/Hydra, Slurm's
/// PMI and PMIx).
const LAUNCHER_VARIABLES: [&str; 3] = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"];

const REQUEST: i32 = 1;
const ROW: i32 = 2;
const DONE: i32 = 3;
const ASSIGN: i32 = 4;
/// The answer to a request when every run is handed out.
const NO_MORE: u64 = u64::MAX;
/// How long the main thread sleeps when neither a message nor a finished run is waiting.
const IDLE: Duration = Duration::from_millis(2);

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
    if world.rank() == 0 {
        coordinate(args, plan, &world)
    } else {
        work(plan, &world)
    }
}

/// Rank 0: reads the previous table, hands out the pending runs, runs its share and
/// writes every row as it comes.
fn coordinate(args: &SweepArgs, plan: &Plan, world: &SimpleCommunicator) -> Result<()> {
    let size = world.size();
    // Rank 0 writes the table: it holds the output directory's lock.
    let _lock = plan.lock_output()?;
    let mut records = plan.previous_records(args.force)?;
    let done: Vec<usize> = records.iter().map(|r| r.run).collect();
    let pending = plan.pending(&done);
    plan.announce(
        done.len(),
        pending.len(),
        &format!(" over {size} MPI ranks"),
    );
    let queue = Mutex::new(pending.into_iter().collect::<VecDeque<usize>>());
    let next_run = || queue.lock().ok().and_then(|mut q| q.pop_front());
    let mut runs_per_rank = vec![0usize; size as usize];
    let pool = plan.worker_pool()?;
    let (finished, results) = mpsc::channel::<Record>();
    let local_idle = AtomicUsize::new(0);
    let mut errors = Vec::new();
    pool.in_place_scope(|scope| -> Result<()> {
        for _ in 0..plan.jobs {
            let finished = finished.clone();
            let (next_run, local_idle) = (&next_run, &local_idle);
            scope.spawn(move |_| {
                while let Some(run) = next_run() {
                    if finished.send(plan.run_one(run)).is_err() {
                        break;
                    }
                }
                local_idle.fetch_add(1, Ordering::SeqCst);
            });
        }
        let mut workers_done = 0;
        loop {
            if let Ok(record) = results.try_recv() {
                runs_per_rank[0] += 1;
                records.push(record);
                plan.write_table(&records)?;
                continue;
            }
            if let Some(probed) = world.any_process().immediate_matched_probe() {
                let (bytes, status) = probed.matched_receive_vec::<u8>();
                let source = status.source_rank();
                if status.tag() == DONE {
                    workers_done += 1;
                    if !bytes.is_empty() {
                        errors.push(format!(
                            "rank {source}: {}",
                            String::from_utf8_lossy(&bytes)
                        ));
                    }
                    continue;
                }
                if !bytes.is_empty() {
                    let text = String::from_utf8(bytes).context("rows from another rank")?;
                    let origin = plan.table_path.with_file_name(format!("(rank {source})"));
                    let rows = table::parse_table(&text, &origin, &plan.columns)?;
                    runs_per_rank[source as usize] += rows.len();
                    records.extend(rows);
                    plan.write_table(&records)?;
                }
                if status.tag() == REQUEST {
                    let run = next_run().map_or(NO_MORE, |run| run as u64);
                    world.process_at_rank(source).send_with_tag(&run, ASSIGN);
                }
                continue;
            }
            if workers_done == size - 1 && local_idle.load(Ordering::SeqCst) == plan.jobs {
                // The local runs' last records were sent before they went idle.
                while let Ok(record) = results.try_recv() {
                    runs_per_rank[0] += 1;
                    records.push(record);
                    plan.write_table(&records)?;
                }
                return Ok(());
            }
            std::thread::sleep(IDLE);
        }
    })?;
    let shares: Vec<String> = runs_per_rank
        .iter()
        .enumerate()
        .map(|(rank, runs)| format!("rank {rank}: {runs}"))
        .collect();
    println!(
        "runs per rank (handed out one at a time): {}",
        shares.join(", ")
    );
    if !errors.is_empty() {
        bail!("{}", errors.join("; "));
    }
    plan.finish(args, &records)
}

/// A rank other than 0: asks for runs, `--jobs` at a time, and sends each finished run's
/// row to rank 0 with the next request.
fn work(plan: &Plan, world: &SimpleCommunicator) -> Result<()> {
    let root = world.process_at_rank(0);
    let pool = match plan.worker_pool() {
        Ok(pool) => pool,
        Err(e) => {
            root.send_with_tag(e.to_string().as_bytes(), DONE);
            return Err(e);
        }
    };
    let (finished, results) = mpsc::channel::<Record>();
    let mut unanswered = 0usize;
    let mut running = 0usize;
    let mut more = true;
    let nothing: &[u8] = &[];
    for _ in 0..plan.jobs {
        root.send_with_tag(nothing, REQUEST);
        unanswered += 1;
    }
    let outcome = pool.in_place_scope(|scope| -> Result<()> {
        loop {
            if unanswered > 0
                && let Some((message, _)) = root.immediate_matched_probe_with_tag(ASSIGN)
            {
                let (run, _) = message.matched_receive::<u64>();
                unanswered -= 1;
                if run == NO_MORE {
                    more = false;
                } else {
                    let run = usize::try_from(run).map_err(|_| anyhow!("run {run}"))?;
                    running += 1;
                    let finished = finished.clone();
                    scope.spawn(move |_| {
                        let _ = finished.send(plan.run_one(run));
                    });
                }
                continue;
            }
            if let Ok(record) = results.try_recv() {
                running -= 1;
                let text = table::format_table(&plan.columns, &[record]);
                if more {
                    root.send_with_tag(text.as_bytes(), REQUEST);
                    unanswered += 1;
                } else {
                    root.send_with_tag(text.as_bytes(), ROW);
                }
                continue;
            }
            if unanswered == 0 && running == 0 {
                return Ok(());
            }
            std::thread::sleep(IDLE);
        }
    });
    let why = outcome
        .as_ref()
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    root.send_with_tag(why.as_bytes(), DONE);
    outcome
}

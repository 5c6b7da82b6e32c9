//! `mpirun -np K pdbem sweep ...` (feature `mpi`): the runs of a sweep spread over the
//! ranks with dynamic load balancing, the sweep's table and plots written by rank 0,
//! equal to those of the serial sweep (wall times aside).
//!
//! Scheme: rank 0 is the coordinator on its main thread (the only thread that calls MPI,
//! `MPI_THREAD_FUNNELED`) and a worker on a second thread, so with 2 ranks both work.
//! Every worker asks for a grid index, runs it into `<out>/run_<k>/` ([`super::run_one`],
//! a failed or panicking run is a row with its error) and sends the row back with its
//! next request; the coordinator answers with the next index in grid order, or with
//! [`STOP`] when none is left. A rank is busy as long as runs remain, whatever their
//! lengths (growth runs differ by 100x): the idle time is at most one run at the end
//! (greedy list scheduling, [`super::schedule`]).
//!
//! Before any run, every rank loads and checks the sweep and rank 0 takes the folder's
//! lock; an all-reduce makes all ranks go on or all stop with an error. Each rank sizes
//! its thread pool by the rule of [`super::ranks`]. Rank 0 writes `sweep.csv`, the
//! plots and `sweep_mpi.json` (who ran which run when, [`super::schedule::MpiRecord`]).

use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use anyhow::Context;
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Threading;
use serde::{Deserialize, Serialize};

use super::schedule::{efficiency, MpiRecord, RankInfo, RunTiming};
use super::{check_sweep, grid, run_one, write_results, SweepRow, Vary};
use crate::output::OutputWriter;
use crate::scene::Scene;

/// Worker to coordinator: a request for work, with the result of the previous run.
const TAG_REQUEST: i32 = 1;
/// Coordinator to worker: the grid index to run, or [`STOP`].
const TAG_WORK: i32 = 2;
/// No more work.
pub const STOP: u64 = u64::MAX;
/// How long the coordinator waits for its own worker before it looks for messages again.
const POLL: Duration = Duration::from_millis(1);

/// What a worker sends with each request.
#[derive(Debug, Serialize, Deserialize)]
struct Request {
    /// The rank, its host and threads (first request only).
    hello: Option<RankInfo>,
    /// The run it finished: grid index, row, its duration (s).
    done: Option<(usize, SweepRow, f64)>,
}

/// Runs the sweep over the ranks of `mpirun`; the rows on rank 0, `None` on the others.
pub fn run_mpi_sweep(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    quiet: bool,
) -> anyhow::Result<Option<Vec<SweepRow>>> {
    let threads = super::ranks::set_rank_threads();
    let (universe, _) = mpi::initialize_with_threading(Threading::Funneled)
        .context("MPI is already initialised in this process")?;
    let world = universe.world();
    let rank = world.rank() as usize;
    let (threads, rule) = match threads {
        Ok(t) => t,
        Err(e) => (rayon::current_num_threads(), format!("{e:#}")),
    };
    let info = RankInfo {
        rank,
        host: hostname(),
        threads,
        threads_rule: rule,
    };
    // Every rank checks the sweep; rank 0 also takes the folder.
    let ready = check_sweep(scene, varies).and_then(|()| {
        if rank == 0 {
            OutputWriter::create_run(out_dir)
                .map(Some)
                .with_context(|| format!("cannot create {}", out_dir.display()))
        } else {
            Ok(None)
        }
    });
    let mut all_ok = 0i32;
    world.all_reduce_into(
        &i32::from(ready.is_ok()),
        &mut all_ok,
        SystemOperation::min(),
    );
    // mpirun ends the job at the first rank that exits with an error and can drop what
    // the others had still to say: a rank that cannot start says why before the barrier,
    // the others leave only after it.
    let writer = match (ready, all_ok) {
        (Err(e), _) => {
            eprintln!("error: rank {rank}: {e:#}");
            world.barrier();
            anyhow::bail!("rank {rank} could not start the sweep (the message above)")
        }
        (Ok(_), 0) => {
            world.barrier();
            anyhow::bail!(
                "rank {rank}: another rank could not start the sweep (see its message); \
                 nothing was run"
            )
        }
        (Ok(w), _) => w,
    };
    if rank != 0 {
        work_remote(&world, scene, varies, out_dir, info);
        return Ok(None);
    }
    let writer = writer.context("rank 0 holds the sweep folder")?;
    let (rows, record) = coordinate(&world, scene, varies, out_dir, info, quiet)?;
    write_results(scene, varies, &rows, &writer)?;
    writer.write_json("sweep_mpi.json", &record)?;
    writer.commit()?;
    if !quiet {
        eprintln!(
            "{} ranks, load-balance efficiency {:.3} (sum of run times / (ranks x {:.1} s))",
            record.ranks, record.efficiency, record.makespan_s
        );
    }
    Ok(Some(rows))
}

/// This machine's name, empty where unknown.
fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .unwrap_or_default()
}

/// A worker on a rank other than 0: ask, run, send back, until [`STOP`].
fn work_remote(
    world: &SimpleCommunicator,
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    info: RankInfo,
) {
    let root = world.process_at_rank(0);
    let mut request = Request {
        hello: Some(info),
        done: None,
    };
    loop {
        root.send_with_tag(&encode(request)[..], TAG_REQUEST);
        let (k, _) = root.receive_with_tag::<u64>(TAG_WORK);
        if k == STOP {
            return;
        }
        let k = k as usize;
        let t0 = Instant::now();
        let row = run_one(scene, varies, out_dir, k);
        request = Request {
            hello: None,
            done: Some((k, row, t0.elapsed().as_secs_f64())),
        };
    }
}

/// The request as JSON; a row that would not come back intact (a number JSON cannot
/// carry) becomes a failed row that says so.
fn encode(request: Request) -> Vec<u8> {
    let bytes = serde_json::to_vec(&request).unwrap_or_default();
    if serde_json::from_slice::<Request>(&bytes).is_ok() {
        return bytes;
    }
    let Request { hello, done } = request;
    let done = done.map(|(k, row, run_s)| {
        let error = format!(
            "the run's results cannot be sent to rank 0 as JSON (a non-finite number?): {}",
            row.error.unwrap_or_default()
        );
        let row = SweepRow {
            params: row.params,
            summary: None,
            error: Some(error),
        };
        (k, row, run_s)
    });
    serde_json::to_vec(&Request { hello, done }).expect("a failed row is plain JSON")
}

/// The coordinator's book: next index, rows, timings.
struct Book {
    total: usize,
    next: usize,
    t0: Instant,
    started: Vec<f64>,
    slots: Vec<Option<SweepRow>>,
    runs: Vec<RunTiming>,
    ranks: Vec<RankInfo>,
    bar: indicatif::ProgressBar,
}

impl Book {
    /// Records a request from `rank`; returns the index to hand out, or [`STOP`].
    fn answer(&mut self, rank: usize, request: Request) -> u64 {
        let now = self.t0.elapsed().as_secs_f64();
        if let Some(info) = request.hello {
            self.ranks.push(info);
        }
        if let Some((k, row, run_s)) = request.done {
            if k < self.total && self.slots[k].is_none() {
                self.slots[k] = Some(row);
                self.runs.push(RunTiming {
                    run: k,
                    rank,
                    start_s: self.started[k],
                    end_s: now,
                    run_s,
                });
                self.bar.inc(1);
            }
        }
        if self.next < self.total {
            let k = self.next;
            self.next += 1;
            self.started[k] = now;
            k as u64
        } else {
            STOP
        }
    }
}

/// Rank 0: hands out the grid to every rank and to its own worker thread; returns the
/// rows in grid order and the record of the schedule.
fn coordinate(
    world: &SimpleCommunicator,
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    info: RankInfo,
    quiet: bool,
) -> anyhow::Result<(Vec<SweepRow>, MpiRecord)> {
    let total = grid(varies).len();
    let size = world.size() as usize;
    let mut book = Book {
        total,
        next: 0,
        t0: Instant::now(),
        started: vec![0.0; total],
        slots: vec![None; total],
        runs: Vec::new(),
        ranks: Vec::new(),
        bar: crate::runner::context::progress_bar(total as u64, quiet),
    };
    let (to_local, local_in) = mpsc::channel::<u64>();
    let (local_out, from_local) = mpsc::channel::<Request>();
    std::thread::scope(|s| {
        s.spawn(move || work_local(&local_in, &local_out, scene, varies, out_dir, info));
        let mut remote_left = size - 1;
        let mut local_left = true;
        while remote_left > 0 || local_left {
            if let Some(probed) = world
                .any_process()
                .immediate_matched_probe_with_tag(TAG_REQUEST)
            {
                let (bytes, status) = probed.matched_receive_vec::<u8>();
                let src = status.source_rank();
                let Ok(request) = serde_json::from_slice::<Request>(&bytes) else {
                    // Workers send only what parses back (`encode`): a broken protocol,
                    // and the ranks waiting for an answer must not hang.
                    eprintln!("error: rank {src} sent a request that does not parse");
                    world.abort(1);
                };
                let k = book.answer(src as usize, request);
                world.process_at_rank(src).send_with_tag(&k, TAG_WORK);
                remote_left -= usize::from(k == STOP);
                continue;
            }
            if !local_left {
                std::thread::sleep(POLL);
                continue;
            }
            match from_local.recv_timeout(POLL) {
                Ok(request) => {
                    let k = book.answer(0, request);
                    local_left = k != STOP;
                    // The worker has gone only if it panicked outside a run; the missing
                    // rows are then reported below.
                    let _ = to_local.send(k);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => local_left = false,
            }
        }
    });
    book.bar.finish_and_clear();
    let makespan = book.t0.elapsed().as_secs_f64();
    let missing: Vec<String> = (0..total)
        .filter(|&k| book.slots[k].is_none())
        .map(|k| k.to_string())
        .collect();
    if !missing.is_empty() {
        anyhow::bail!(
            "runs {} of the sweep came back from no rank",
            missing.join(", ")
        );
    }
    let busy: f64 = book.runs.iter().map(|r| r.run_s).sum();
    book.ranks.sort_by_key(|r| r.rank);
    let record = MpiRecord {
        ranks: size,
        rank_info: book.ranks,
        runs: book.runs,
        makespan_s: makespan,
        efficiency: efficiency(busy, size, makespan),
    };
    Ok((book.slots.into_iter().flatten().collect(), record))
}

/// Rank 0's own worker (a thread; no MPI calls): the same loop as a remote worker,
/// through channels.
fn work_local(
    work: &mpsc::Receiver<u64>,
    results: &mpsc::Sender<Request>,
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    info: RankInfo,
) {
    let mut request = Request {
        hello: Some(info),
        done: None,
    };
    loop {
        if results.send(request).is_err() {
            return;
        }
        let Ok(k) = work.recv() else { return };
        if k == STOP {
            return;
        }
        let k = k as usize;
        let t0 = Instant::now();
        let row = run_one(scene, varies, out_dir, k);
        request = Request {
            hello: None,
            done: Some((k, row, t0.elapsed().as_secs_f64())),
        };
    }
}

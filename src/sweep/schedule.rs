//! Who ran what, when, in a sweep spread over ranks, and what that says about load
//! balance: `<out>/sweep_mpi.json` of an MPI sweep ([`MpiRecord`]), and the measures of
//! `pdbem bench sweep-mpi`.
//!
//! - Load-balance efficiency of a schedule: E = sum of the run times / (ranks x makespan)
//!   (1 when no rank ever waits; the makespan counts from the first hand-out to the
//!   last result).
//! - Projection to W workers ([`list_makespan`]): the coordinator hands the next run in
//!   grid order to the first worker that asks, i.e. greedy list scheduling; simulated on
//!   given run times, with no messaging cost (a run takes seconds, a message
//!   microseconds). Graham's bound: makespan <= sum / W + max run time.
//! - The static split of `--shard I/N` with N = W ([`round_robin_makespan`]): worker i
//!   runs k = i, i + W, ..., whatever their lengths.

use serde::{Deserialize, Serialize};

/// One run of an MPI sweep.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunTiming {
    /// Grid index.
    pub run: usize,
    /// Rank that ran it.
    pub rank: usize,
    /// Hand-out time, seconds after the start (rank 0's clock).
    pub start_s: f64,
    /// Time the result came back, seconds after the start (rank 0's clock).
    pub end_s: f64,
    /// The run's own duration on its rank (s).
    pub run_s: f64,
}

/// One rank of an MPI sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RankInfo {
    /// Rank.
    pub rank: usize,
    /// Host name (`/proc/sys/kernel/hostname`, empty where unknown).
    pub host: String,
    /// Threads of its rayon pool.
    pub threads: usize,
    /// Why that many ([`super::ranks`]).
    pub threads_rule: String,
}

/// `<out>/sweep_mpi.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MpiRecord {
    /// Number of ranks.
    pub ranks: usize,
    /// Every rank that asked for work.
    pub rank_info: Vec<RankInfo>,
    /// Every run, in the order the results came back.
    pub runs: Vec<RunTiming>,
    /// From the first hand-out to the last result (s).
    pub makespan_s: f64,
    /// sum of `run_s` / (ranks x makespan).
    pub efficiency: f64,
}

/// Load-balance efficiency: `busy` seconds of work over `workers` x `makespan`.
pub fn efficiency(busy: f64, workers: usize, makespan: f64) -> f64 {
    if workers == 0 || makespan <= 0.0 {
        return f64::NAN;
    }
    busy / (workers as f64 * makespan)
}

/// Makespan of greedy list scheduling: run times in the given order, each to the worker
/// that is free first.
pub fn list_makespan(times: &[f64], workers: usize) -> f64 {
    let mut free = vec![0.0f64; workers.max(1)];
    for &t in times {
        let (i, _) = free
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .expect("at least one worker");
        free[i] += t;
    }
    free.into_iter().fold(0.0, f64::max)
}

/// Makespan of the round-robin static split: worker i runs k with k mod W = i.
pub fn round_robin_makespan(times: &[f64], workers: usize) -> f64 {
    let w = workers.max(1);
    (0..w)
        .map(|i| times.iter().skip(i).step_by(w).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Minimum, median and maximum.
pub fn min_median_max(times: &[f64]) -> Option<(f64, f64, f64)> {
    if times.is_empty() {
        return None;
    }
    let mut v = times.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    Some((v[0], median, v[n - 1]))
}

/// A projection of a study onto `workers` workers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Projection {
    /// Workers (ranks, one run at a time each).
    pub workers: usize,
    /// Runs in the study.
    pub runs: usize,
    /// Sum of the run times (s).
    pub busy_s: f64,
    /// Makespan with dynamic hand-out (s).
    pub dynamic_makespan_s: f64,
    /// Its load-balance efficiency.
    pub dynamic_efficiency: f64,
    /// Makespan of the static round-robin split (s).
    pub static_makespan_s: f64,
    /// Its load-balance efficiency.
    pub static_efficiency: f64,
    /// No schedule beats max(busy / workers, longest run) (s).
    pub lower_bound_s: f64,
}

/// A study of `runs` runs whose times repeat the measured `times` in order (grid
/// order, as a study of `runs / times.len()` copies of the measured grid would), on
/// `workers` workers.
pub fn project(times: &[f64], runs: usize, workers: usize) -> Projection {
    let study: Vec<f64> = times.iter().copied().cycle().take(runs).collect();
    let busy: f64 = study.iter().sum();
    let longest = study.iter().copied().fold(0.0, f64::max);
    let dynamic = list_makespan(&study, workers);
    let fixed = round_robin_makespan(&study, workers);
    Projection {
        workers,
        runs,
        busy_s: busy,
        dynamic_makespan_s: dynamic,
        dynamic_efficiency: efficiency(busy, workers, dynamic),
        static_makespan_s: fixed,
        static_efficiency: efficiency(busy, workers, fixed),
        lower_bound_s: (busy / workers.max(1) as f64).max(longest),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn list_scheduling_by_hand() {
        // 3, 3 start on the two workers; the 2s go to whichever frees first: 5, 5, 7.
        assert_eq!(list_makespan(&[3.0, 3.0, 2.0, 2.0, 2.0], 2), 7.0);
        // One long run last: makespan = its start + its length.
        assert_eq!(list_makespan(&[1.0, 1.0, 1.0, 1.0, 10.0], 2), 12.0);
        // More workers than runs: the longest run.
        assert_eq!(list_makespan(&[4.0, 1.0], 8), 4.0);
        // Round robin puts 10 and 10 on worker 0: 20; dynamic 10 + 1 = 11 at most.
        let t = [10.0, 1.0, 10.0, 1.0];
        assert_eq!(round_robin_makespan(&t, 2), 20.0);
        assert_eq!(list_makespan(&t, 2), 11.0);
    }

    #[test]
    fn projection_bounds() {
        let times: Vec<f64> = (0..16).map(|i| 1.0 + (i * 7 % 16) as f64).collect();
        for w in [1, 2, 3, 64] {
            let p = project(&times, 256, w);
            assert!(p.dynamic_makespan_s >= p.lower_bound_s - 1e-12);
            // Graham: list scheduling is within sum / W + max.
            let longest = times.iter().copied().fold(0.0, f64::max);
            assert!(p.dynamic_makespan_s <= p.busy_s / w as f64 + longest + 1e-12);
            assert!(p.dynamic_efficiency > 0.0 && p.dynamic_efficiency <= 1.0 + 1e-12);
        }
        // One worker: no idle time at all.
        assert!((project(&times, 32, 1).dynamic_efficiency - 1.0).abs() < 1e-12);
        assert_eq!(min_median_max(&[3.0, 1.0, 2.0, 4.0]), Some((1.0, 2.5, 4.0)));
        assert!(efficiency(1.0, 0, 1.0).is_nan());
    }
}

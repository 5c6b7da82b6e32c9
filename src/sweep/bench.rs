//! `pdbem bench sweep-mpi --out DIR` (issue 22): one sweep of 16 growth runs of
//! `cases/growth_inclined_crack.ron` over crack positions, two ways on 2 cores:
//! (a) `mpirun -np 2` with one thread per rank (`RAYON_NUM_THREADS=1`), the runs spread
//! by the MPI coordinator ([`super::mpi`]); (b) one process, `RAYON_NUM_THREADS=2`, the runs
//! one after another, each on two threads. It reports the wall-time ratio (b) / (a), the
//! CPU times, the per-run times, the load-balance efficiency of (a) and a projection onto
//! 64 and 128 workers from the measured per-run times ([`super::schedule::project`]), with
//! the load average of the machine before, between and after. Needs a pdbem built with
//! `--features mpi`, `mpirun` on the PATH, and `/usr/bin/time` for CPU times (left out
//! without it). Writes `DIR/bench.json`, `DIR/report.md`, and the two sweeps in
//! `DIR/mpi/` and `DIR/threads/`.
//!
//! The crack centre moves along y = 25 mm from x = 10 mm to 40 mm in 2 mm steps (`pdbem
//! check` accepts each: the 5 mm windows at the tips stay inside the plate; at x = 7 mm
//! they would not). Growth mode as the case sets (PD-BEM, about 20 s a run on 2 threads,
//! shorter where the crack starts near an edge). `--quick`: 4 positions, 15 load steps.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use anyhow::Context;
use serde::Serialize;

use super::schedule::{min_median_max, project, MpiRecord, Projection};

/// The case of the bench.
pub const CASE: &str = "growth_inclined_crack";
/// Ranks of (a) = threads of (b).
pub const CORES: usize = 2;
/// Workers of the projections.
const WORKERS: [usize; 2] = [64, 128];
/// Study sizes of the projections (copies of the measured grid).
const STUDY_SIZES: [usize; 3] = [64, 256, 1024];

/// Wall and CPU time of one command.
#[derive(Debug, Clone, Serialize)]
pub struct Timed {
    /// Wall time (s).
    pub wall_s: f64,
    /// User CPU time of the command and its children (s), from `/usr/bin/time`.
    pub user_s: Option<f64>,
    /// System CPU time (s).
    pub sys_s: Option<f64>,
}

/// Minimum, median, maximum (s).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Spread {
    /// Shortest.
    pub min_s: f64,
    /// Median.
    pub median_s: f64,
    /// Longest.
    pub max_s: f64,
}

/// `bench.json`.
#[derive(Debug, Serialize)]
pub struct SweepMpiReport {
    /// "sweep-mpi".
    pub bench: &'static str,
    /// The case file.
    pub case: String,
    /// The `--vary` arguments.
    pub vary: Vec<String>,
    /// Runs in the sweep.
    pub runs: usize,
    /// Runs that failed (rows with an error).
    pub failed: usize,
    /// `/proc/loadavg` before (a), between, after (b).
    pub load: Vec<String>,
    /// (a) `mpirun -np 2`, 1 thread per rank.
    pub mpi: Timed,
    /// (b) one process, 2 threads.
    pub threads: Timed,
    /// Wall (b) / wall (a): above 1 when ranks beat threads.
    pub wall_ratio: f64,
    /// CPU (user + sys) of (b) / (a).
    pub cpu_ratio: Option<f64>,
    /// Per-run times of (a) (1 thread each).
    pub run_time_1_thread: Option<Spread>,
    /// Per-run times of (b) (2 threads each, successful runs).
    pub run_time_2_threads: Option<Spread>,
    /// Load-balance efficiency of (a): sum of run times / (ranks x makespan).
    pub efficiency: f64,
    /// Makespan of (a) on rank 0's clock (s).
    pub makespan_s: f64,
    /// The two tables agree (wall times aside).
    pub tables_equal: bool,
    /// Projections from the per-run times of (a).
    pub projections: Vec<Projection>,
}

/// The crack centres of the bench.
pub fn positions(quick: bool) -> Vec<String> {
    let xs: Vec<u32> = if quick {
        vec![10, 20, 30, 40]
    } else {
        (0..16).map(|i| 10 + 2 * i).collect()
    };
    xs.iter().map(|x| format!("(0.{x:03},0.025)")).collect()
}

/// Runs the bench into `out`.
pub fn run(out: &Path, quick: bool) -> anyhow::Result<()> {
    if !cfg!(feature = "mpi") {
        anyhow::bail!(
            "bench sweep-mpi needs a pdbem built with `cargo build --release --features mpi`"
        );
    }
    let case = crate::cases::case_path(CASE)?;
    let exe = std::env::current_exe().context("cannot find the pdbem executable")?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut vary = vec![format!("cracks.0.center={}", positions(quick).join(","))];
    if quick {
        vary.push("load.count=15".into());
    }
    let sweep_args = |dir: &str| -> Vec<String> {
        let mut a = vec!["sweep".into(), case.display().to_string()];
        for v in &vary {
            a.extend(["--vary".into(), v.clone()]);
        }
        a.extend(["--out".into(), out.join(dir).display().to_string()]);
        a.push("--quiet".into());
        a
    };
    let mut load = vec![loadavg()];
    let mut a = vec!["--oversubscribe".into(), "-np".into(), CORES.to_string()];
    a.extend(["-x".into(), "RAYON_NUM_THREADS".into()]);
    a.push(exe.display().to_string());
    a.extend(sweep_args("mpi"));
    let mpi = timed("mpirun", &a, 1, &out.join("mpi.time"))?;
    load.push(loadavg());
    let threads = timed(
        &exe.display().to_string(),
        &sweep_args("threads"),
        CORES,
        &out.join("threads.time"),
    )?;
    load.push(loadavg());
    let report = report(out, &case, vary, load, mpi, threads)?;
    let w = crate::output::OutputWriter::create(out)?;
    w.write_json("bench.json", &report)?;
    let md = markdown(&report);
    w.write_bytes("report.md", md.as_bytes())?;
    w.commit()?;
    crate::console::out(&md);
    Ok(())
}

/// The measures from the two sweep folders.
fn report(
    out: &Path,
    case: &Path,
    vary: Vec<String>,
    load: Vec<String>,
    mpi: Timed,
    threads: Timed,
) -> anyhow::Result<SweepMpiReport> {
    let file = out.join("mpi/sweep_mpi.json");
    let text = std::fs::read_to_string(&file)
        .with_context(|| format!("cannot read {}", file.display()))?;
    let rec: MpiRecord = serde_json::from_str(&text)
        .with_context(|| format!("{} is not an MPI sweep record", file.display()))?;
    let mut one: Vec<(usize, f64)> = rec.runs.iter().map(|r| (r.run, r.run_s)).collect();
    one.sort_by_key(|r| r.0);
    let one: Vec<f64> = one.into_iter().map(|r| r.1).collect();
    let (ta, tb) = (csv(&out.join("mpi"))?, csv(&out.join("threads"))?);
    let wall_col = column(&tb, "wall_time_s")?;
    let status_col = column(&tb, "status")?;
    let two: Vec<f64> = tb[1..]
        .iter()
        .filter_map(|r| r[wall_col].parse::<f64>().ok())
        .collect();
    let failed = tb[1..].iter().filter(|r| r[status_col] != "ok").count();
    let cpu = |t: &Timed| Some(t.user_s? + t.sys_s?);
    let projections = WORKERS
        .iter()
        .flat_map(|&w| STUDY_SIZES.iter().map(move |&n| (w, n)))
        .map(|(w, n)| project(&one, n, w))
        .collect();
    Ok(SweepMpiReport {
        bench: "sweep-mpi",
        case: case.display().to_string(),
        vary,
        runs: one.len(),
        failed,
        load,
        wall_ratio: threads.wall_s / mpi.wall_s,
        cpu_ratio: cpu(&threads).zip(cpu(&mpi)).map(|(b, a)| b / a),
        mpi,
        threads,
        run_time_1_thread: spread(&one),
        run_time_2_threads: spread(&two),
        efficiency: rec.efficiency,
        makespan_s: rec.makespan_s,
        tables_equal: without(&ta, wall_col) == without(&tb, wall_col),
        projections,
    })
}

fn spread(times: &[f64]) -> Option<Spread> {
    min_median_max(times).map(|(min_s, median_s, max_s)| Spread {
        min_s,
        median_s,
        max_s,
    })
}

/// `sweep.csv` of a folder as rows of fields.
fn csv(dir: &Path) -> anyhow::Result<Vec<Vec<String>>> {
    let file = dir.join("sweep.csv");
    let text = std::fs::read_to_string(&file)
        .with_context(|| format!("cannot read {}", file.display()))?;
    Ok(text.lines().map(split_csv_line).collect())
}

/// The fields of one CSV line (RFC 4180 quoting: `"a,b"`, `""` for a quote).
fn split_csv_line(line: &str) -> Vec<String> {
    let mut fields = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    fields.push(cur);
    fields
}

fn column(rows: &[Vec<String>], name: &str) -> anyhow::Result<usize> {
    rows.first()
        .and_then(|h| h.iter().position(|c| c == name))
        .with_context(|| format!("sweep.csv has no column {name}"))
}

fn without(rows: &[Vec<String>], col: usize) -> Vec<Vec<String>> {
    rows.iter()
        .map(|r| {
            let mut r = r.clone();
            if col < r.len() {
                r.remove(col);
            }
            r
        })
        .collect()
}

/// The machine's load average (`/proc/loadavg`: 1, 5, 15 minutes), as `uptime` shows it.
fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// Runs `program args` with `RAYON_NUM_THREADS=threads` (and OpenMPI allowed to run as
/// root) through `/usr/bin/time` where it exists; fails when the command fails.
fn timed(
    program: &str,
    args: &[String],
    threads: usize,
    time_file: &Path,
) -> anyhow::Result<Timed> {
    let gnu_time = Path::new("/usr/bin/time").is_file();
    let mut cmd = if gnu_time {
        let mut c = Command::new("/usr/bin/time");
        c.args(["-f", "%e %U %S", "-o"]).arg(time_file).arg(program);
        c
    } else {
        Command::new(program)
    };
    cmd.args(args)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    let t0 = Instant::now();
    let status = cmd
        .status()
        .with_context(|| format!("cannot start {program} (is it installed?)"))?;
    let wall_s = t0.elapsed().as_secs_f64();
    if !status.success() {
        anyhow::bail!("{program} {} failed ({status})", args.join(" "));
    }
    let cpu: Vec<f64> = if gnu_time {
        std::fs::read_to_string(time_file)
            .unwrap_or_default()
            .split_whitespace()
            .filter_map(|v| v.parse().ok())
            .collect()
    } else {
        Vec::new()
    };
    Ok(Timed {
        wall_s,
        user_s: cpu.get(1).copied(),
        sys_s: cpu.get(2).copied(),
    })
}

fn secs(v: Option<f64>) -> String {
    v.map_or("n/a".into(), |v| format!("{v:.1}"))
}

/// `report.md`.
pub fn markdown(r: &SweepMpiReport) -> String {
    let mut s = format!(
        "# bench sweep-mpi\n\n{} runs of {} ({} failed), `--vary {}`\n\n\
         load average (1, 5, 15 min) before / between / after: {}\n\n\
         | | wall (s) | user (s) | sys (s) |\n|---|---|---|---|\n\
         | (a) mpirun -np {CORES}, 1 thread per rank | {:.1} | {} | {} |\n\
         | (b) 1 process, {CORES} threads | {:.1} | {} | {} |\n\n\
         wall (b) / (a) = {:.3}; CPU (b) / (a) = {}; tables equal (wall times aside): {}\n\n",
        r.runs,
        r.case,
        r.failed,
        r.vary.join(" --vary "),
        r.load.join(" / "),
        r.mpi.wall_s,
        secs(r.mpi.user_s),
        secs(r.mpi.sys_s),
        r.threads.wall_s,
        secs(r.threads.user_s),
        secs(r.threads.sys_s),
        r.wall_ratio,
        r.cpu_ratio.map_or("n/a".into(), |v| format!("{v:.3}")),
        r.tables_equal
    );
    for (name, sp) in [
        ("1 thread (a)", r.run_time_1_thread),
        ("2 threads (b)", r.run_time_2_threads),
    ] {
        if let Some(sp) = sp {
            s += &format!(
                "per-run time, {name}: min {:.1} s, median {:.1} s, max {:.1} s\n\n",
                sp.min_s, sp.median_s, sp.max_s
            );
        }
    }
    s += &format!(
        "load-balance efficiency of (a): {:.3} (sum of run times / ({CORES} x makespan {:.1} s))\n\n\
         Projection from the per-run times of (a), the measured grid repeated; one run at a \
         time per worker, no messaging cost:\n\n\
         | workers | runs | sum (s) | dynamic makespan (s) | efficiency | static round robin (s) | efficiency | lower bound (s) |\n\
         |---|---|---|---|---|---|---|---|\n",
        r.efficiency, r.makespan_s
    );
    for p in &r.projections {
        s += &format!(
            "| {} | {} | {:.0} | {:.1} | {:.3} | {:.1} | {:.3} | {:.1} |\n",
            p.workers,
            p.runs,
            p.busy_s,
            p.dynamic_makespan_s,
            p.dynamic_efficiency,
            p.static_makespan_s,
            p.static_efficiency,
            p.lower_bound_s
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quoting() {
        assert_eq!(
            split_csv_line(r#"0,"(0.010,0.025)",ok,"say ""hi"", then",,"#),
            vec!["0", "(0.010,0.025)", "ok", r#"say "hi", then"#, "", ""]
        );
    }

    #[test]
    fn bench_positions() {
        let p = positions(false);
        assert_eq!(p.len(), 16);
        assert_eq!(p[0], "(0.010,0.025)");
        assert_eq!(p[15], "(0.040,0.025)");
        assert_eq!(positions(true).len(), 4);
    }
}

//! The `pdbem` command line (clap): `check`, `run`, `sweep`, `bench`,
//! `plot-paths`. [`main`] parses the arguments and returns the exit code.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::bench::BenchKind;
use crate::runner::mode::mode_of;
use crate::runner::summary::RunSummary;
use crate::runner::{run_scene_with, RunOptions};
use crate::scene::shapes::SceneGeometry;
use crate::scene::{GrowthMode, Scene};

/// Hybrid peridynamics + boundary element crack-growth engine for 2-D elastic bodies.
#[derive(Debug, Parser)]
#[command(name = "pdbem", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Sub-commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Validate a scene and print a short summary.
    Check {
        /// Scene file (RON).
        scene: PathBuf,
        /// Also write the geometry plot to this folder.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Memory budget in bytes (suffixes K, M, G, T: 4G, 512M). Default: half the
        /// machine's memory.
        #[arg(long, value_parser = parse_max_memory)]
        max_memory: Option<u64>,
    },
    /// Solve a scene and write summary.json, CSV tables and plots.
    Run {
        /// Scene file (RON).
        scene: PathBuf,
        /// Run folder. Default `runs/<scene name>`.
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress output.
        #[arg(long)]
        quiet: bool,
        /// Override `growth.mode` of the scene (scenes with a `growth` section).
        #[arg(long, value_enum)]
        growth_mode: Option<GrowthModeArg>,
        /// Memory budget in bytes (suffixes K, M, G, T: 4G, 512M). Default: half the
        /// machine's memory.
        #[arg(long, value_parser = parse_max_memory)]
        max_memory: Option<u64>,
        /// Relative tolerance on every K and CMOD of a static BEM scene: refine until the
        /// error estimate meets it (sets `bem.tolerance`, in [4e-4, 0.5]).
        #[arg(long)]
        tol: Option<f64>,
        /// Growth runs: continue an interrupted run from the checkpoint in the run folder
        /// (the same scene and options; refused when the scene changed).
        #[arg(long)]
        resume: bool,
    },
    /// Run a scene over a grid of values of dotted fields.
    Sweep {
        /// Scene file (RON).
        scene: PathBuf,
        /// FIELD=v1,v2,... (dotted path, e.g. cracks.0.length or bem.element_size); repeat for a grid.
        #[arg(long = "vary", required = true)]
        vary: Vec<String>,
        /// Sweep folder. Default `runs/<scene name>-sweep`.
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress output.
        #[arg(long)]
        quiet: bool,
        /// Memory budget in bytes (suffixes K, M, G, T: 4G, 512M). Default: half the
        /// machine's memory.
        #[arg(long, value_parser = parse_max_memory)]
        max_memory: Option<u64>,
        /// Run only part I of N of the grid (I from 1), e.g. a Slurm array task:
        /// `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT` with `--array=1-N`; then
        /// `--collect`.
        #[arg(long, value_parser = crate::sweep::shard::Shard::parse, conflicts_with = "collect")]
        shard: Option<crate::sweep::shard::Shard>,
        /// Join the finished shards in the sweep folder into its table and plots.
        #[arg(long)]
        collect: bool,
    },
    /// Benchmarks.
    Bench {
        /// Which benchmark.
        #[arg(value_enum)]
        kind: BenchKind,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Smaller sizes.
        #[arg(long)]
        quick: bool,
        /// `trade` only: rebuild `report.md`, `bench.json` and the plots from the run
        /// folders of an earlier `bench trade` into the same folder (nothing is run).
        #[arg(long)]
        collect: bool,
        /// `growth`: the case to run three ways: a file stem in `cases/` under the
        /// current folder, or the path of a scene file. Default growth_tension_edge.
        /// `seed001`: one configuration only (e.g. `inclined_crack`).
        #[arg(long)]
        case: Option<String>,
    },
    /// Overlay the crack paths of several growth runs.
    PlotPaths {
        /// Run folders.
        #[arg(required = true)]
        runs: Vec<PathBuf>,
        /// Output file: a stem for PNG and SVG, or a name ending in .png / .svg for
        /// that format only. Default `paths` in the current folder.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// `--growth-mode` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum GrowthModeArg {
    /// PD windows over the tips, BEM elsewhere.
    PdBem,
    /// BEM alone: SIF, maximum circumferential stress kink, fixed increment.
    BemOnly,
    /// PD over the whole body at the window resolution.
    FullPd,
}

impl From<GrowthModeArg> for GrowthMode {
    fn from(m: GrowthModeArg) -> GrowthMode {
        match m {
            GrowthModeArg::PdBem => GrowthMode::PdBem,
            GrowthModeArg::BemOnly => GrowthMode::BemOnly,
            GrowthModeArg::FullPd => GrowthMode::FullPd,
        }
    }
}

/// Exit code of a growth run that ended early (`complete: false`) or a sweep with failed
/// runs: the outputs are written. 1 is any error (bad scene, failed setup, a folder in
/// use, nothing written), 2 a command line clap refuses.
pub const EXIT_INCOMPLETE: u8 = 3;

/// The error of a sweep (run whole, or joined by `--collect`) some of whose runs failed:
/// every row is in the table, the failed ones with their `error` (exit code
/// [`EXIT_INCOMPLETE`]).
#[derive(Debug)]
pub struct FailedRuns {
    /// The sweep folder.
    pub out: PathBuf,
    /// Failed runs.
    pub failed: usize,
    /// All runs.
    pub total: usize,
    /// The first failure's message.
    pub first: String,
}

impl std::fmt::Display for FailedRuns {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of {} runs failed or ended early (their rows in {} carry the error or the reason; the other runs' outputs are written); first: {}",
            self.failed,
            self.total,
            self.out.display(),
            self.first
        )
    }
}

impl std::error::Error for FailedRuns {}

/// The error of a growth run that ended early with its outputs written (exit code
/// [`EXIT_INCOMPLETE`]).
#[derive(Debug)]
pub struct IncompleteRun {
    /// The run folder.
    pub out: PathBuf,
    /// `failure_reason` of the summary.
    pub reason: String,
}

impl std::fmt::Display for IncompleteRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the run ended early (complete: false, outputs of the completed steps in {}): {}",
            self.out.display(),
            self.reason
        )
    }
}

impl std::error::Error for IncompleteRun {}

/// Parses the command line, runs the command, prints errors; returns the exit code: 0
/// done, 1 error, 2 bad command line (clap), [`EXIT_INCOMPLETE`] a growth run that ended
/// early or a sweep with failed runs, its outputs written.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match execute(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if is_incomplete(&e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(EXIT_INCOMPLETE)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Whether `e` is a run that ended early or a sweep with failed runs, outputs written
/// (exit code [`EXIT_INCOMPLETE`]).
pub fn is_incomplete(e: &anyhow::Error) -> bool {
    e.downcast_ref::<IncompleteRun>().is_some() || e.downcast_ref::<FailedRuns>().is_some()
}

/// Runs one command.
pub fn execute(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Check {
            scene,
            plot,
            max_memory,
        } => {
            set_budget(max_memory);
            check(&scene, plot.as_deref())
        }
        Command::Run {
            scene,
            out,
            quiet,
            growth_mode,
            max_memory,
            tol,
            resume,
        } => {
            set_budget(max_memory);
            let options = RunOptions {
                quiet,
                resume,
                ..Default::default()
            };
            let cli = CliRun {
                growth_mode: growth_mode.map(GrowthMode::from),
                tol,
            };
            run(&scene, out, options, &cli)
        }
        Command::Sweep {
            scene,
            vary,
            out,
            quiet,
            max_memory,
            shard,
            collect,
        } => {
            set_budget(max_memory);
            let part = match (shard, collect) {
                (Some(s), _) => SweepPart::Shard(s),
                (None, true) => SweepPart::Collect,
                (None, false) => SweepPart::All,
            };
            sweep(&scene, &vary, out, quiet, part)
        }
        Command::Bench {
            kind,
            out,
            quick,
            collect,
            case,
        } => {
            if collect {
                crate::bench::collect(kind, &out)
            } else {
                crate::bench::run(kind, &out, quick, case.as_deref())
            }
        }
        Command::PlotPaths { runs, out } => plot_paths(&runs, out),
    }
}

fn parse_max_memory(text: &str) -> Result<u64, String> {
    crate::setup::estimate::parse_bytes(text)
}

fn set_budget(max_memory: Option<u64>) {
    // The engines' sparse factors and dense BEM systems within it too.
    crate::setup::estimate::set_budget(max_memory.unwrap_or(0));
}

fn load(path: &Path) -> anyhow::Result<Scene> {
    let scene = Scene::load(path)?;
    for note in &scene.notes {
        eprintln!("note: {}: {note}", path.display());
    }
    Ok(scene)
}

fn check(path: &Path, plot_dir: Option<&Path>) -> anyhow::Result<()> {
    let scene = load(path)?;
    crate::setup::estimate::check(&scene)?;
    crate::setup::reference_loads::check(&scene)?;
    crate::setup::fit_stations::check(&scene)?;
    let bem_only_cost = if scene
        .growth
        .as_ref()
        .is_some_and(|g| g.mode == GrowthMode::BemOnly)
    {
        Some(crate::growth::bem_only::cost_line(
            &crate::growth::bem_only::check(&scene)?,
        ))
    } else {
        None
    };
    let geometry_notes = crate::runner::plausibility::thin_ligaments(&scene)
        .into_iter()
        .chain(crate::runner::plausibility::close_tips(&scene))
        .chain(crate::runner::plausibility::close_holes(&scene))
        .chain(crate::runner::plausibility::outline_necks(&scene))
        .chain(crate::setup::horizon_scale::note(&scene));
    let cost_note = bem_only_cost.as_ref().and_then(|(_, n)| n.clone());
    for note in geometry_notes.chain(cost_note) {
        eprintln!("note: {}: {note}", path.display());
    }
    let footprint = crate::setup::footprint::of(&scene)?;
    crate::outln!("{}", describe(&scene));
    for line in footprint.describe() {
        crate::outln!("{line}");
    }
    if let Some((line, _)) = &bem_only_cost {
        crate::outln!("{line}");
    }
    if let Some(dir) = plot_dir {
        let w = crate::output::OutputWriter::create(dir)?;
        let fig = crate::runner::report::geometry_plot(&scene, None);
        let mut s = RunSummary::default();
        crate::runner::report::save_plot(&w, "geometry", &fig, &scene.outputs.formats, &mut s)?;
        w.commit()?;
        crate::outln!("geometry plot written to {}", dir.display());
    }
    Ok(())
}

/// A short human-readable summary of a valid scene.
pub fn describe(scene: &Scene) -> String {
    let geo = SceneGeometry::of(scene);
    let m = &scene.material;
    let mut out = vec![
        format!(
            "scene {} ({}): valid",
            scene.name,
            scene.file_label().display()
        ),
        format!("  mode: {}", mode_of(scene).as_str()),
        format!(
            "  material: E = {} Pa, nu = {}, plane {:?}, thickness {} m",
            m.e, m.nu, m.plane, m.thickness
        ),
    ];
    if !scene.description.is_empty() {
        out.insert(1, format!("  description: {}", scene.description));
    }
    out.push(match (&geo.outline, geo.remote) {
        (Some(o), _) => {
            let (lo, hi) = crate::geometry::bounding_box(&o.points);
            format!(
                "  body: {} outline points, {} x {} m, {} hole(s)",
                o.points.len(),
                hi.x - lo.x,
                hi.y - lo.y,
                geo.holes.len()
            )
        }
        (None, Some(s)) => format!(
            "  body: infinite plate, remote stress sxx {} syy {} sxy {} Pa, {} hole(s)",
            s[0],
            s[1],
            s[2],
            geo.holes.len()
        ),
        (None, None) => "  body: infinite plate".into(),
    });
    for c in &geo.cracks {
        let len = crate::geometry::polyline_length(&c.points);
        let kind = if c.mouth {
            "edge crack (CMOD reported)"
        } else {
            "interior crack"
        };
        out.push(format!("  crack {}: {kind}, length {len} m", c.name));
    }
    out.push(format!(
        "  boundary groups: {}",
        scene.edge_groups().join(", ")
    ));
    let f = crate::runner::reference::load_factor(scene);
    for (name, r) in crate::runner::reference::tip_references(scene) {
        out.push(format!(
            "  reference at {name} (load factor {f}): K_I = {:.6e}, K_II = {:.6e} Pa m^0.5",
            r.k1, r.k2
        ));
    }
    if let Some((name, c)) = crate::runner::reference::cmod_reference(scene) {
        out.push(format!(
            "  reference CMOD of {name} (load factor {f}): {c:.6e} m"
        ));
    }
    out.join("\n")
}

fn default_out(scene: &Scene, suffix: &str) -> PathBuf {
    PathBuf::from("runs").join(format!("{}{suffix}", scene.name))
}

/// The scene with `growth.mode` replaced, validated again (BEM-only needs fracture data,
/// the PD modes a `coupling` section).
pub fn with_growth_mode(scene: &Scene, mode: GrowthMode) -> anyhow::Result<Scene> {
    let mut s = scene.clone();
    match s.growth.as_mut() {
        Some(g) => g.mode = mode,
        None => anyhow::bail!(
            "{}: --growth-mode needs a scene with a `growth` section",
            scene.file_label().display()
        ),
    }
    s.validate()?;
    Ok(s)
}

/// The scene with `bem.tolerance` set to `tol`, validated again (static BEM scenes
/// only; the range is the field's).
pub fn with_tolerance(scene: &Scene, tol: f64) -> anyhow::Result<Scene> {
    if !tol.is_finite() {
        anyhow::bail!("--tol {tol}: the tolerance must be a finite number in [4e-4, 0.5]");
    }
    let value = serde_json::json!(tol);
    Ok(crate::scene::path::with_overrides(
        scene,
        &[("bem.tolerance".to_string(), value)],
    )?)
}

/// Command-line changes to the scene before `run` (beyond the runner's [`RunOptions`]).
#[derive(Debug, Clone, Default)]
pub struct CliRun {
    /// `--growth-mode`.
    pub growth_mode: Option<GrowthMode>,
    /// `--tol`.
    pub tol: Option<f64>,
}

fn run(path: &Path, out: Option<PathBuf>, options: RunOptions, cli: &CliRun) -> anyhow::Result<()> {
    let mut scene = load(path)?;
    if let Some(m) = cli.growth_mode {
        scene = with_growth_mode(&scene, m)?;
    }
    if let Some(tol) = cli.tol {
        scene = with_tolerance(&scene, tol)?;
    }
    let out = out.unwrap_or_else(|| default_out(&scene, ""));
    let summary = run_scene_with(&scene, &out, &options)?;
    // Results are printed with --quiet too: it silences progress only.
    print_summary(&summary, &out);
    match summary.incomplete() {
        Some(reason) => Err(IncompleteRun { out, reason }.into()),
        None => Ok(()),
    }
}

/// Prints the run's summary; a closed stdout (`| head`) ends the printing quietly.
fn print_summary(s: &RunSummary, out_dir: &Path) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    let mut lines = crate::console::summary_lines(s);
    lines.push(format!("outputs in {}", out_dir.display()));
    for line in lines {
        if writeln!(out, "{line}").is_err() {
            break;
        }
    }
}

fn plot_paths(runs: &[PathBuf], out: Option<PathBuf>) -> anyhow::Result<()> {
    let out = out.unwrap_or_else(|| PathBuf::from("paths"));
    let done = crate::growth::overlay::plot_paths(runs, &out)?;
    for w in &done.warnings {
        eprintln!("warning: {w}");
    }
    for d in &done.deviations {
        crate::outln!(
            "{} {}: {:.4e} m from {} over a common reach of {:.4e} m",
            d.run,
            d.tip,
            d.deviation,
            done.reference,
            d.reach
        );
    }
    for f in &done.files {
        crate::outln!("{}", f.display());
    }
    Ok(())
}

/// Which part of a sweep a command runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepPart {
    /// The whole grid.
    All,
    /// One shard.
    Shard(crate::sweep::shard::Shard),
    /// Join the finished shards.
    Collect,
}

fn sweep(
    path: &Path,
    vary: &[String],
    out: Option<PathBuf>,
    quiet: bool,
    part: SweepPart,
) -> anyhow::Result<()> {
    let scene = load(path)?;
    let varies = vary
        .iter()
        .map(|v| crate::sweep::parse_vary(v))
        .collect::<Result<Vec<_>, _>>()
        .map_err(anyhow::Error::msg)?;
    let out = out.unwrap_or_else(|| default_out(&scene, "-sweep"));
    if part != SweepPart::All && crate::sweep::ranks::launcher_world_size().is_some_and(|n| n > 1) {
        anyhow::bail!("--shard and --collect run in one process, not under mpirun");
    }
    let rows = match part {
        SweepPart::All => {
            match crate::sweep::run_sweep_launched(&scene, &varies, &out, quiet)? {
                Some(rows) => rows,
                None => return Ok(()), // an MPI rank other than 0: rank 0 reports
            }
        }
        SweepPart::Shard(s) => {
            let rows = crate::sweep::shard::run_shard(&scene, &varies, &out, s, quiet)?;
            let failed = rows.iter().filter(|r| r.problem().is_some()).count();
            crate::outln!(
                "shard {}/{}: {} runs ({failed} failed or ended early) in {}; join the shards with --collect",
                s.index,
                s.count,
                rows.len(),
                out.display()
            );
            // A shard's failed runs are rows of the table `--collect` joins, and its exit
            // code: a scheduler's `afterok` dependency still starts the collect job.
            return Ok(());
        }
        SweepPart::Collect => crate::sweep::shard::collect(&scene, &varies, &out)?,
    };
    let failed = rows.iter().filter(|r| r.problem().is_some()).count();
    crate::outln!(
        "{} runs ({} failed or ended early); table in {}",
        rows.len(),
        failed,
        out.join("sweep.csv").display()
    );
    failed_runs(&rows, out.join("sweep.csv"))
}

/// [`FailedRuns`] when a run of `rows` failed or ended early (its table, or shard
/// folder, at `out`).
fn failed_runs(rows: &[crate::sweep::SweepRow], out: PathBuf) -> anyhow::Result<()> {
    let failed = rows.iter().filter(|r| r.problem().is_some()).count();
    match rows.iter().find_map(|r| r.problem()) {
        None => Ok(()),
        Some(first) => Err(FailedRuns {
            out,
            failed,
            total: rows.len(),
            first,
        }
        .into()),
    }
}

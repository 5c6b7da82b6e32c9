//! [`RunContext`]: what a solver's report gets besides the scene (the run folder, the
//! staged writer, quiet or not), and [`progress_bar`]: a bar on a terminal, one line per
//! change on a stderr that is not one (a log file, CI), nothing with `--quiet`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, TermLike};

use crate::output::OutputWriter;

/// What a solver gets besides the scene.
#[derive(Debug)]
pub struct RunContext {
    /// Final run folder (files appear there only when the run succeeds).
    pub out_dir: PathBuf,
    /// No progress output.
    pub quiet: bool,
    /// Writer for every output file of the run (staged until success).
    pub writer: OutputWriter,
    /// Growth runs: go on from the checkpoint in the run folder (`pdbem run --resume`,
    /// [`crate::growth::checkpoint`]).
    pub resume: bool,
    /// Growth runs: stop after this load step once its checkpoint is written, as if the
    /// process had been killed there (a test hook; the run then fails with
    /// "stopped after step k" and leaves the checkpoint).
    pub stop_after: Option<usize>,
    /// Growth runs, a test hook: `Some((k, n))` makes the first `n` tries of load step `k`
    /// fail as a solver failure does (full PD: the equilibrium before any bond broke;
    /// BEM-only: every re-meshed geometry of step k, which has no retry).
    pub fail_tries: Option<(usize, usize)>,
    /// Full PD and PD-BEM: the least time between two checkpoints inside load steps
    /// ([`ROUND_CHECKPOINT_INTERVAL`] unless a test sets it).
    pub round_checkpoint_every: Duration,
    /// Inside load step k, `Some((k, r))`, once its checkpoint is written, stop (a test
    /// hook like `stop_after`): full PD after break round r, PD-BEM after the relocation
    /// that brings the run's relocation records to r.
    pub stop_within: Option<(usize, usize)>,
}

/// Full PD (after a break round at which its solvers are renewed) and PD-BEM (just after a
/// relocation) write a checkpoint inside a load step when this long has passed since the
/// run's last checkpoint: 5 minutes, a few seconds of writing against minutes of work lost
/// at a kill.
pub const ROUND_CHECKPOINT_INTERVAL: Duration = Duration::from_secs(300);

impl RunContext {
    /// Creates the run folder and its staging area.
    pub fn new(out_dir: &Path, quiet: bool) -> std::io::Result<RunContext> {
        Ok(RunContext {
            out_dir: out_dir.to_path_buf(),
            quiet,
            writer: OutputWriter::create_run(out_dir)?,
            resume: false,
            stop_after: None,
            fail_tries: None,
            round_checkpoint_every: ROUND_CHECKPOINT_INTERVAL,
            stop_within: None,
        })
    }

    /// Prints a progress message to stderr unless quiet.
    pub fn log(&self, message: &str) {
        if !self.quiet {
            eprintln!("{message}");
        }
    }

    /// A progress bar of `len` steps ([`progress_bar`]).
    pub fn progress(&self, len: u64) -> ProgressBar {
        progress_bar(len, self.quiet)
    }

    /// [`Self::progress`] drawn by `on_terminal` (an indicatif template) on a terminal and
    /// by `in_lines` when stderr is a file or pipe, where a line is written whenever that
    /// text changes (so `in_lines` leaves out what changes every second).
    pub fn styled_progress(&self, len: u64, on_terminal: &str, in_lines: &str) -> ProgressBar {
        let bar = self.progress(len);
        let template = if stderr_is_terminal() {
            on_terminal
        } else {
            in_lines
        };
        if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    }
}

/// True when progress goes to an interactive terminal (bars) rather than to lines.
pub fn stderr_is_terminal() -> bool {
    std::io::stderr().is_terminal()
}

/// A progress bar of `len` steps: hidden when `quiet`; drawn in place on a terminal;
/// otherwise written as plain lines on stderr, one whenever the bar's text changes (at
/// most twice a second), so a redirected run still shows where it is.
pub fn progress_bar(len: u64, quiet: bool) -> ProgressBar {
    if quiet {
        ProgressBar::hidden()
    } else if stderr_is_terminal() {
        ProgressBar::new(len)
    } else {
        let target = ProgressDrawTarget::term_like_with_hz(Box::new(LineTerm::default()), 2);
        let bar = ProgressBar::with_draw_target(Some(len), target);
        if let Ok(style) = indicatif::ProgressStyle::with_template("{pos}/{len} {msg}") {
            bar.set_style(style);
        }
        bar
    }
}

/// A pretend terminal that prints each new bar text as a line on stderr.
#[derive(Debug, Default)]
struct LineTerm {
    last: Mutex<String>,
}

impl LineTerm {
    fn emit(&self, s: &str) {
        let text = s.trim_end();
        if text.is_empty() {
            return;
        }
        if let Ok(mut last) = self.last.lock() {
            if *last != text {
                eprintln!("{text}");
                *last = text.to_string();
            }
        }
    }
}

impl TermLike for LineTerm {
    fn width(&self) -> u16 {
        100
    }
    fn move_cursor_up(&self, _n: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_down(&self, _n: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_right(&self, _n: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_left(&self, _n: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        self.emit(s);
        Ok(())
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        self.emit(s);
        Ok(())
    }
    fn clear_line(&self) -> std::io::Result<()> {
        Ok(())
    }
    fn flush(&self) -> std::io::Result<()> {
        Ok(())
    }
}

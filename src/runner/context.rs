//! [`RunContext`]: what a solver's report gets besides the scene (the run folder, the
//! staged writer, quiet or not).

use std::path::{Path, PathBuf};

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
}

impl RunContext {
    /// Creates the run folder and its staging area.
    pub fn new(out_dir: &Path, quiet: bool) -> std::io::Result<RunContext> {
        Ok(RunContext {
            out_dir: out_dir.to_path_buf(),
            quiet,
            writer: OutputWriter::create_run(out_dir)?,
            resume: false,
            stop_after: None,
        })
    }

    /// Prints a progress message to stderr unless quiet.
    pub fn log(&self, message: &str) {
        if !self.quiet {
            eprintln!("{message}");
        }
    }

    /// A progress bar of `len` steps (hidden when quiet).
    pub fn progress(&self, len: u64) -> indicatif::ProgressBar {
        if self.quiet {
            indicatif::ProgressBar::hidden()
        } else {
            indicatif::ProgressBar::new(len)
        }
    }
}

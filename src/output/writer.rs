//! The run-folder writer: every file of a run goes first to a staging folder
//! `<out>/.staging-<pid>/` (each file itself written atomically); `commit`
//! renames them into `<out>/`; dropping the writer without commit (a failed
//! run) deletes the staging folder, and the run folder too if this writer
//! created it and it is empty. So a failed run leaves no half-written outputs.
//!
//! A writer that owns its folder ([`OutputWriter::create_run`]: runs, sweeps) lists its
//! files in `<out>/.pdbem-files`; the next such commit into the same folder removes the
//! files of that list it did not write again (a re-run with fewer load steps leaves no
//! snapshot of the old run beside the new ones). Files pdbem did not write are never
//! touched, and writers that add a file to a shared folder ([`OutputWriter::create`]:
//! `plot-paths`, `check --plot`) neither read nor write the list.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::atomic::write_atomic;
use super::csv::CsvTable;

/// Writer of one run folder (usable through `&self` from solver code).
#[derive(Debug)]
pub struct OutputWriter {
    out_dir: PathBuf,
    staging: PathBuf,
    created: Vec<PathBuf>,
    owns_folder: bool,
    files: Mutex<Vec<String>>,
    done: Mutex<bool>,
}

impl OutputWriter {
    /// Creates `out_dir` (if needed) and a fresh staging folder inside it.
    pub fn create(out_dir: &Path) -> io::Result<OutputWriter> {
        let created = missing_ancestors(out_dir);
        fs::create_dir_all(out_dir)?;
        let staging = out_dir.join(format!(".staging-{}", std::process::id()));
        if staging.exists() {
            fs::remove_dir_all(&staging)?;
        }
        fs::create_dir_all(&staging)?;
        Ok(OutputWriter {
            out_dir: out_dir.to_path_buf(),
            staging,
            created,
            owns_folder: false,
            files: Mutex::new(Vec::new()),
            done: Mutex::new(false),
        })
    }

    /// [`OutputWriter::create`] for a folder that holds one run: its commit replaces the
    /// previous run's files (see the module docs).
    pub fn create_run(out_dir: &Path) -> io::Result<OutputWriter> {
        let mut w = OutputWriter::create(out_dir)?;
        w.owns_folder = true;
        Ok(w)
    }

    /// The final run folder.
    pub fn out_dir(&self) -> &Path {
        &self.out_dir
    }

    /// Staging path for a file name (for writers that need a path, e.g.
    /// plotters); call [`OutputWriter::register`] after writing it.
    pub fn staging_path(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// Records a file written directly into the staging folder.
    pub fn register(&self, name: &str) {
        if let Ok(mut f) = self.files.lock() {
            if !f.iter().any(|n| n == name) {
                f.push(name.to_string());
            }
        }
    }

    /// Writes bytes as `name`.
    pub fn write_bytes(&self, name: &str, bytes: &[u8]) -> io::Result<()> {
        write_atomic(&self.staging_path(name), bytes)?;
        self.register(name);
        Ok(())
    }

    /// Writes a CSV table as `name`.
    pub fn write_csv(&self, name: &str, table: &CsvTable) -> io::Result<()> {
        self.write_bytes(name, table.to_csv().as_bytes())
    }

    /// Writes pretty JSON as `name`.
    pub fn write_json<T: serde::Serialize>(&self, name: &str, value: &T) -> io::Result<()> {
        let mut text = serde_json::to_string_pretty(value).map_err(io::Error::other)?;
        text.push('\n');
        self.write_bytes(name, text.as_bytes())
    }

    /// Names of the files written so far.
    pub fn files(&self) -> Vec<String> {
        self.files.lock().map(|f| f.clone()).unwrap_or_default()
    }

    /// Moves every staged file into the run folder and removes the staging folder; a
    /// writer that owns its folder first removes the files an earlier run listed in
    /// [`MANIFEST`] that this one did not write, and writes the new list.
    pub fn commit(&self) -> io::Result<Vec<PathBuf>> {
        let mut out = Vec::new();
        let files = self.files();
        if self.owns_folder {
            self.replace_manifest(&files)?;
        }
        for name in files {
            let to = self.out_dir.join(&name);
            fs::rename(self.staging_path(&name), &to)?;
            out.push(to);
        }
        fs::remove_dir_all(&self.staging)?;
        if let Ok(mut d) = self.done.lock() {
            *d = true;
        }
        Ok(out)
    }

    /// Removes the files of the previous run's [`MANIFEST`] that are not in `files`, then
    /// lists `files` there.
    fn replace_manifest(&self, files: &[String]) -> io::Result<()> {
        let manifest = self.out_dir.join(MANIFEST);
        if let Ok(old) = fs::read_to_string(&manifest) {
            for name in old.lines().filter(|n| is_plain_name(n)) {
                if !files.iter().any(|f| f == name) {
                    let _ = fs::remove_file(self.out_dir.join(name));
                }
            }
        }
        let mut list = files.join("\n");
        list.push('\n');
        write_atomic(&manifest, list.as_bytes())
    }

    /// Discards the staged files (what `Drop` does without `commit`).
    pub fn abort(&self) {
        let _ = fs::remove_dir_all(&self.staging);
        // Folders this writer created, deepest first; only empty ones go.
        for dir in &self.created {
            if fs::remove_dir(dir).is_err() {
                break;
            }
        }
        if let Ok(mut d) = self.done.lock() {
            *d = true;
        }
    }
}

/// The list of the files of the last committed run, in the run folder.
pub const MANIFEST: &str = ".pdbem-files";

/// A file name without folders (a manifest line pdbem may act on).
fn is_plain_name(name: &str) -> bool {
    !name.is_empty()
        && name != MANIFEST
        && !name.contains(['/', '\\'])
        && name != "."
        && name != ".."
}

/// `dir` and its ancestors that do not exist yet, deepest first.
fn missing_ancestors(dir: &Path) -> Vec<PathBuf> {
    dir.ancestors()
        .take_while(|d| !d.as_os_str().is_empty() && !d.exists())
        .map(Path::to_path_buf)
        .collect()
}

impl Drop for OutputWriter {
    fn drop(&mut self) {
        let done = self.done.lock().map(|d| *d).unwrap_or(true);
        if !done {
            self.abort();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("pdbem-writer-{}-{name}", std::process::id()))
    }

    #[test]
    fn commit_moves_files() {
        let d = scratch("commit");
        let _ = fs::remove_dir_all(&d);
        let w = OutputWriter::create(&d).expect("create");
        w.write_bytes("a.txt", b"x").expect("write");
        w.commit().expect("commit");
        assert_eq!(fs::read_to_string(d.join("a.txt")).expect("read"), "x");
        // A writer that does not own the folder leaves no manifest.
        assert_eq!(fs::read_dir(&d).expect("dir").count(), 1);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn a_second_run_removes_only_the_first_runs_files_it_did_not_write_again() {
        let d = scratch("rerun");
        let _ = fs::remove_dir_all(&d);
        let w = OutputWriter::create_run(&d).expect("create");
        w.write_bytes("steps.csv", b"1").expect("write");
        w.write_bytes("snapshot_step019.png", b"old")
            .expect("write");
        w.commit().expect("commit");
        fs::write(d.join("notes.txt"), b"mine").expect("user file");
        // A plot added to the folder by another command stays through the re-run.
        let p = OutputWriter::create(&d).expect("create");
        p.write_bytes("overlay.png", b"plot").expect("write");
        p.commit().expect("commit");
        let w = OutputWriter::create_run(&d).expect("create");
        w.write_bytes("steps.csv", b"2").expect("write");
        w.write_bytes("snapshot_step004.png", b"new")
            .expect("write");
        w.commit().expect("commit");
        assert_eq!(fs::read_to_string(d.join("steps.csv")).expect("read"), "2");
        assert!(d.join("snapshot_step004.png").exists());
        assert!(!d.join("snapshot_step019.png").exists(), "stale file kept");
        assert_eq!(
            fs::read_to_string(d.join("notes.txt")).expect("read"),
            "mine"
        );
        assert!(
            d.join("overlay.png").exists(),
            "another command's file removed"
        );
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn drop_without_commit_leaves_nothing() {
        let d = scratch("abort");
        let _ = fs::remove_dir_all(&d);
        {
            let w = OutputWriter::create(&d.join("nested")).expect("create");
            w.write_bytes("a.txt", b"x").expect("write");
        }
        assert!(!d.exists());
    }
}

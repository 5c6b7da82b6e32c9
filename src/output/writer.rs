//! The run-folder writer: every file of a run goes first to a staging folder
//! `<out>/.staging-<pid>/` (each file itself written atomically); `commit`
//! renames them into `<out>/`; dropping the writer without commit (a failed
//! run) deletes the staging folder, and the run folder too if this writer
//! created it and it is empty. So a failed run leaves no half-written outputs.

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
            files: Mutex::new(Vec::new()),
            done: Mutex::new(false),
        })
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

    /// Moves every staged file into the run folder and removes the staging folder.
    pub fn commit(&self) -> io::Result<Vec<PathBuf>> {
        let mut out = Vec::new();
        for name in self.files() {
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
        assert_eq!(fs::read_dir(&d).expect("dir").count(), 1);
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

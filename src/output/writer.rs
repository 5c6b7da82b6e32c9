//! The run-folder writer: every file of a run goes first to a staging folder
//! `<out>/.staging-<pid>/` (each file itself written atomically); `commit`
//! renames them into `<out>/`; dropping the writer without commit (a failed
//! run) deletes the staging folder, and the run folder too if this writer
//! created it and it is empty. So a failed run leaves no half-written outputs.
//!
//! Concurrency and interruption (Linux: a process is alive while `/proc/<pid>` exists;
//! elsewhere every recorded process counts as alive):
//! - a writer that owns its folder holds the lock `<out>/.pdbem-lock` (created with
//!   `create_new`, holding the pid) until it commits or aborts; a second run into a folder
//!   whose lock holder is alive is refused, naming the process; the lock of a dead
//!   process is taken over;
//! - staging folders `.staging-<pid>` of dead processes (a run killed with SIGKILL) are
//!   deleted when the next writer opens the folder;
//! - the commit first moves the files it replaces or retires into `.previous-<pid>/`,
//!   then moves the new files in, writes the manifest, and deletes `.previous-<pid>/`; a
//!   failure on the way moves everything back, so the previous outputs stay as they were.
//!   A `.previous-<pid>` of a dead process (killed during those renames) is moved back
//!   when the next writer opens the folder.
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
    /// The lock file this writer holds (writers that own their folder).
    lock: Option<PathBuf>,
    /// Test hook: the commit fails after moving this many new files in.
    fail_after: Option<usize>,
}

impl OutputWriter {
    /// Creates `out_dir` (if needed) and a fresh staging folder inside it.
    pub fn create(out_dir: &Path) -> io::Result<OutputWriter> {
        let created = missing_ancestors(out_dir);
        fs::create_dir_all(out_dir)?;
        clean_stale(out_dir);
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
            lock: None,
            fail_after: None,
        })
    }

    /// [`OutputWriter::create`] for a folder that holds one run: it takes the folder's
    /// lock (refused while another live process holds it) and its commit replaces the
    /// previous run's files (see the module docs).
    pub fn create_run(out_dir: &Path) -> io::Result<OutputWriter> {
        let created = missing_ancestors(out_dir);
        let lock = take_lock(out_dir)?;
        let mut w = match OutputWriter::create(out_dir) {
            Ok(w) => w,
            Err(e) => {
                let _ = fs::remove_file(&lock);
                return Err(e);
            }
        };
        w.created = created;
        w.owns_folder = true;
        w.lock = Some(lock);
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
    /// writer that owns its folder also retires the files an earlier run listed in
    /// [`MANIFEST`] that this one did not write, and writes the new list. Old files are
    /// moved aside first and back on any failure (module docs).
    pub fn commit(&self) -> io::Result<Vec<PathBuf>> {
        let files = self.files();
        let aside = self
            .out_dir
            .join(format!(".previous-{}", std::process::id()));
        let mut old: Vec<String> = files.clone();
        if self.owns_folder {
            if let Ok(list) = fs::read_to_string(self.out_dir.join(MANIFEST)) {
                old.extend(list.lines().filter(|n| is_plain_name(n)).map(String::from));
            }
        }
        old.sort();
        old.dedup();
        old.retain(|n| self.out_dir.join(n).is_file());
        let mut moved = Moves::default();
        if let Err(e) = self.swap_in(&files, &old, &aside, &mut moved) {
            moved.undo(self, &aside);
            return Err(e);
        }
        let _ = fs::remove_dir_all(&aside);
        fs::remove_dir_all(&self.staging)?;
        self.release();
        Ok(files.iter().map(|n| self.out_dir.join(n)).collect())
    }

    /// The renames of [`Self::commit`], each recorded in `moved` for the undo.
    fn swap_in(
        &self,
        files: &[String],
        old: &[String],
        aside: &Path,
        moved: &mut Moves,
    ) -> io::Result<()> {
        if !old.is_empty() {
            fs::create_dir_all(aside)?;
        }
        for name in old {
            fs::rename(self.out_dir.join(name), aside.join(name))?;
            moved.aside.push(name.clone());
        }
        for (i, name) in files.iter().enumerate() {
            if self.fail_after == Some(i) {
                return Err(io::Error::other("injected commit failure (test)"));
            }
            fs::rename(self.staging_path(name), self.out_dir.join(name))?;
            moved.placed.push(name.clone());
        }
        if self.owns_folder {
            let mut list = files.join("\n");
            list.push('\n');
            write_atomic(&self.out_dir.join(MANIFEST), list.as_bytes())?;
        }
        Ok(())
    }

    /// Marks the writer done and gives up its lock.
    fn release(&self) {
        if let Ok(mut d) = self.done.lock() {
            *d = true;
        }
        if let Some(lock) = &self.lock {
            let _ = fs::remove_file(lock);
        }
    }

    /// Test hook: the next commit fails after moving `n` new files into place.
    #[doc(hidden)]
    pub fn inject_commit_failure(&mut self, n: usize) {
        self.fail_after = Some(n);
    }

    /// Discards the staged files (what `Drop` does without `commit`).
    pub fn abort(&self) {
        let _ = fs::remove_dir_all(&self.staging);
        if let Some(lock) = &self.lock {
            let _ = fs::remove_file(lock);
        }
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

/// The lock file of a run folder (module docs).
pub const LOCK: &str = ".pdbem-lock";

/// The renames a commit made so far.
#[derive(Default)]
struct Moves {
    /// Old files moved into the aside folder.
    aside: Vec<String>,
    /// New files moved from staging into the run folder.
    placed: Vec<String>,
}

impl Moves {
    /// Moves the new files back to staging and the old ones back into place.
    fn undo(&self, w: &OutputWriter, aside: &Path) {
        for name in self.placed.iter().rev() {
            let _ = fs::rename(w.out_dir.join(name), w.staging_path(name));
        }
        for name in self.aside.iter().rev() {
            let _ = fs::rename(aside.join(name), w.out_dir.join(name));
        }
        let _ = fs::remove_dir(aside);
    }
}

/// Whether process `pid` is alive: `/proc/<pid>` exists (Linux). Without `/proc` every
/// process counts as alive (nothing is cleaned up, a lock must be removed by hand).
pub fn process_alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// The pid of a `<prefix><pid>` name.
fn pid_of(name: &str, prefix: &str) -> Option<u32> {
    name.strip_prefix(prefix)?.parse().ok()
}

/// Deletes the staging folders of dead processes and moves back the old outputs a dead
/// process had moved aside during its commit.
fn clean_stale(out_dir: &Path) {
    let Ok(entries) = fs::read_dir(out_dir) else {
        return;
    };
    let me = std::process::id();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let stale = |prefix| pid_of(&name, prefix).is_some_and(|p| p != me && !process_alive(p));
        if stale(".staging-") {
            let _ = fs::remove_dir_all(e.path());
        } else if stale(".previous-") {
            if let Ok(old) = fs::read_dir(e.path()) {
                for f in old.flatten() {
                    let _ = fs::rename(f.path(), out_dir.join(f.file_name()));
                }
            }
            let _ = fs::remove_dir(e.path());
        }
    }
}

/// Takes the lock of a run folder: refused while a live process holds it; a dead
/// holder's lock is taken over.
fn take_lock(out_dir: &Path) -> io::Result<PathBuf> {
    fs::create_dir_all(out_dir)?;
    let lock = out_dir.join(LOCK);
    for _ in 0..2 {
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&lock)
        {
            Ok(mut f) => {
                use std::io::Write;
                writeln!(f, "{}", std::process::id())?;
                return Ok(lock);
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                let holder = fs::read_to_string(&lock).unwrap_or_default();
                match holder.trim().parse::<u32>() {
                    Ok(pid) if process_alive(pid) => {
                        return Err(io::Error::other(format!(
                            "the folder is in use by pdbem process {pid} (lock {}); wait for \
                             it to finish, or remove the lock if no pdbem runs there",
                            lock.display()
                        )))
                    }
                    _ => {
                        let _ = fs::remove_file(&lock);
                    }
                }
            }
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other(format!(
        "cannot take the lock {}",
        lock.display()
    )))
}

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
    fn a_failed_commit_leaves_the_previous_outputs_as_they_were() {
        let d = scratch("failed-commit");
        let _ = fs::remove_dir_all(&d);
        let w = OutputWriter::create_run(&d).expect("create");
        w.write_bytes("a.txt", b"old a").expect("write");
        w.write_bytes("b.txt", b"old b").expect("write");
        w.write_bytes("gone.txt", b"old only").expect("write");
        w.commit().expect("commit");
        let mut w = OutputWriter::create_run(&d).expect("create");
        w.write_bytes("a.txt", b"new a").expect("write");
        w.write_bytes("b.txt", b"new b").expect("write");
        w.write_bytes("c.txt", b"new c").expect("write");
        // Fails after a.txt and b.txt are in place.
        w.inject_commit_failure(2);
        assert!(w.commit().is_err());
        drop(w);
        for (f, text) in [
            ("a.txt", "old a"),
            ("b.txt", "old b"),
            ("gone.txt", "old only"),
        ] {
            assert_eq!(fs::read_to_string(d.join(f)).expect("read"), text, "{f}");
        }
        assert!(!d.join("c.txt").exists());
        let left: Vec<String> = fs::read_dir(&d)
            .expect("dir")
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with('.') && n != MANIFEST)
            .collect();
        assert!(left.is_empty(), "left behind: {left:?}");
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn a_second_run_into_a_locked_folder_is_refused_and_a_dead_lock_is_taken_over() {
        let d = scratch("lock");
        let _ = fs::remove_dir_all(&d);
        let w = OutputWriter::create_run(&d).expect("create");
        let e = OutputWriter::create_run(&d).expect_err("second writer");
        assert!(e.to_string().contains("in use by pdbem process"), "{e}");
        drop(w);
        assert!(!d.join(LOCK).exists(), "lock released");
        // A lock and a staging folder left by a dead process (pid beyond pid_max).
        fs::create_dir_all(&d).expect("dir");
        fs::write(d.join(LOCK), "4194305\n").expect("lock");
        fs::create_dir_all(d.join(".staging-4194305")).expect("staging");
        let w = OutputWriter::create_run(&d).expect("dead lock taken over");
        assert!(!d.join(".staging-4194305").exists(), "stale staging kept");
        w.abort();
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

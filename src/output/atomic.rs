//! Atomic file writing: write `name.tmp` in the same folder, flush, rename.
//! On any error the temporary file is removed, so no partial file is left and
//! an existing file of the same name is untouched.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// The temporary name used while writing `path`: `<path>.tmp`.
pub fn temp_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".tmp");
    path.with_file_name(name)
}

/// Writes `bytes` to `path` atomically (temp + rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Writes `path` atomically with a closure that fills the file.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut io::BufWriter<fs::File>) -> io::Result<()>,
) -> io::Result<()> {
    let tmp = temp_path(path);
    let result = (|| {
        let file = fs::File::create(&tmp)?;
        let mut w = io::BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("pdbem-atomic-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).expect("temp dir");
        d
    }

    #[test]
    fn writes_and_leaves_no_temp() {
        let d = scratch("ok");
        let p = d.join("a.txt");
        write_atomic(&p, b"hello").expect("write");
        assert_eq!(fs::read_to_string(&p).expect("read"), "hello");
        assert!(!temp_path(&p).exists());
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn failed_fill_leaves_old_file_and_no_temp() {
        let d = scratch("fail");
        let p = d.join("a.txt");
        write_atomic(&p, b"old").expect("write");
        let err = write_atomic_with(&p, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("boom"))
        });
        assert!(err.is_err());
        assert_eq!(fs::read_to_string(&p).expect("read"), "old");
        assert!(!temp_path(&p).exists());
        let _ = fs::remove_dir_all(&d);
    }
}

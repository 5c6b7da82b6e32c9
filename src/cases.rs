//! Where the scenes of `cases/` are found: under the current folder (an installed binary
//! runs from a clone, not from the folder it was built in).

use std::path::Path;

use anyhow::Result;

/// The scene file of a bench case: `case` itself when it names a `.ron` file or a path,
/// else `cases/<case>.ron` under the current folder (an installed binary runs from a
/// clone, not from the folder it was built in).
pub fn case_path(case: &str) -> Result<std::path::PathBuf> {
    let given = Path::new(case);
    if case.ends_with(".ron") || given.components().count() > 1 {
        return Ok(given.to_path_buf());
    }
    let path = Path::new("cases").join(format!("{case}.ron"));
    if path.is_file() {
        return Ok(path);
    }
    let here = std::env::current_dir()
        .map(|d| d.display().to_string())
        .unwrap_or_else(|_| ".".into());
    anyhow::bail!(
        "bench case {case}: no file cases/{case}.ron under the current folder {here}; run from a pdbem clone or give the path of a scene file"
    )
}

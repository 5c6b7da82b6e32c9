//! Scene errors: I/O, RON syntax (with line and column), validation issues
//! (dotted field path + reason) and sweep-path errors.

use std::fmt;
use std::path::PathBuf;

/// One violated rule: the dotted field path, the offending value and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Issue {
    /// Dotted path into the scene, e.g. `material.nu` or `cracks.0.length`.
    pub path: String,
    /// The offending value as written (when there is one).
    pub value: Option<String>,
    /// The rule it breaks, phrased as what to change.
    pub reason: String,
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.value {
            Some(v) => write!(f, "{} = {}: {}", self.path, v, self.reason),
            None => write!(f, "{}: {}", self.path, self.reason),
        }
    }
}

/// Errors of loading, validating and editing scenes.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{file}: cannot read scene: {error}")]
    Io {
        /// Scene file.
        file: PathBuf,
        /// Underlying error, in the message (not a `source`, which `{:#}` would print a
        /// second time).
        error: std::io::Error,
    },
    /// RON syntax error, unknown or missing field, wrong type.
    #[error("{file}:{line}:{column}: {message}")]
    Syntax {
        /// Scene file (or a label for inline text).
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What the parser found (names the field for unknown/missing fields).
        message: String,
    },
    /// The scene parsed but breaks one or more rules.
    #[error("{}", format_issues(file, issues))]
    Invalid {
        /// Scene file (or a label).
        file: PathBuf,
        /// Every violated rule.
        issues: Vec<Issue>,
    },
    /// A dotted path (`--vary`) does not lead to a settable value.
    #[error("{file}: --vary {path}: {reason}")]
    Path {
        /// Scene file (or a label).
        file: PathBuf,
        /// The dotted path as given.
        path: String,
        /// Why it cannot be set.
        reason: String,
    },
}

fn format_issues(file: &std::path::Path, issues: &[Issue]) -> String {
    issues
        .iter()
        .map(|i| format!("{}: {}", file.display(), i))
        .collect::<Vec<_>>()
        .join("\n")
}

impl SceneError {
    /// The validation issues, empty for other kinds.
    pub fn issues(&self) -> &[Issue] {
        match self {
            SceneError::Invalid { issues, .. } => issues,
            _ => &[],
        }
    }
}

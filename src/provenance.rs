//! What made a run: version, git commit (at build time, `build.rs`), rayon thread count,
//! command line and start time, written to `summary.json` as `provenance`, and the
//! resolved scene (`scene.ron`: sweep overrides, `--growth-mode` and every default
//! written out) that `pdbem run scene.ron` runs again.
//!
//! Entry points: [`Provenance::now`], [`resolved_scene_ron`], [`utc_iso8601`].

use std::time::{SystemTime, UNIX_EPOCH};

use serde::Serialize;

use crate::scene::Scene;

/// Git commit of the build ("unknown" without git; `-dirty` with uncommitted changes).
pub const GIT_COMMIT: &str = env!("PDBEM_GIT_COMMIT");

/// The provenance of one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Provenance {
    /// Crate version.
    pub version: String,
    /// Git commit of the build.
    pub git_commit: String,
    /// Rayon worker threads.
    pub threads: usize,
    /// The command line, as given.
    pub command_line: Vec<String>,
    /// Start of the run, UTC, ISO 8601 (`2026-11-24T13:16:20Z`).
    pub start_time: String,
}

impl Provenance {
    /// The provenance of a run starting now.
    pub fn now() -> Provenance {
        Provenance {
            version: env!("CARGO_PKG_VERSION").into(),
            git_commit: GIT_COMMIT.into(),
            threads: rayon::current_num_threads(),
            command_line: std::env::args().collect(),
            start_time: utc_iso8601(SystemTime::now()),
        }
    }
}

/// `t` as UTC ISO 8601 to the second (`YYYY-MM-DDThh:mm:ssZ`); times before 1970 give
/// the epoch.
pub fn utc_iso8601(t: SystemTime) -> String {
    let secs = t.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let (y, m, d) = civil_from_days(days);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        (rem % 3600) / 60,
        rem % 60
    )
}

/// Proleptic Gregorian date of a day count since 1970-01-01 (H. Hinnant's
/// `civil_from_days`, http://howardhinnant.github.io/date_algorithms.html).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// The scene as RON with every field written out (defaults included), readable by
/// [`Scene::load`], under a comment saying what wrote it.
pub fn resolved_scene_ron(scene: &Scene, p: &Provenance) -> Result<String, ron::Error> {
    let config = ron::ser::PrettyConfig::new()
        .extensions(
            ron::extensions::Extensions::IMPLICIT_SOME
                | ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES,
        )
        .indentor("    ".to_string());
    let body = ron::ser::to_string_pretty(scene, config)?;
    let source = scene
        .source
        .as_ref()
        .map_or("<inline>".to_string(), |s| s.display().to_string());
    Ok(format!(
        "// The resolved scene of this run: {source} with sweep overrides and\n\
         // --growth-mode applied and every default written out. Written by pdbem {} ({})\n\
         // at {}; `pdbem run scene.ron` runs it again.\n{body}\n",
        p.version, p.git_commit, p.start_time
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn iso8601_of_known_instants() {
        let at = |s: u64| utc_iso8601(UNIX_EPOCH + Duration::from_secs(s));
        assert_eq!(at(0), "1970-01-01T00:00:00Z");
        assert_eq!(at(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(at(1_798_114_580), "2026-12-24T12:16:20Z");
        assert_eq!(at(4_107_542_399), "2100-02-28T23:59:59Z");
    }

    #[test]
    fn resolved_scene_reads_back_equal() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/cases/growth_tension_edge.ron"
        ))
        .expect("case");
        let scene = Scene::from_ron_str(&text, "growth_tension_edge.ron").expect("valid");
        let ron = resolved_scene_ron(&scene, &Provenance::now()).expect("serialises");
        let back = Scene::from_ron_str(&ron, "scene.ron").expect("reads back");
        assert_eq!(back.to_json(), scene.to_json());
        assert!(ron.contains("horizon_factor"), "defaults written out");
    }
}

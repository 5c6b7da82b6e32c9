//! What a growth run produced, mode-independent: tip paths, per-step records, window
//! relocations. Written by the output layer as `path_<tip>.csv`, `steps.csv` and the
//! `summary.json` fields of docs/outputs.md.

use pdbem_geometry::polyline_length;
use serde::{Deserialize, Serialize};

use super::criterion::TipSif;
use super::front::Front;

/// One point of a tip path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathPoint {
    /// Position (m).
    pub x: f64,
    /// Position (m).
    pub y: f64,
    /// Load step (0-based) at which the tip reached this point; the initial tip has the
    /// step before any growth (0).
    pub step: usize,
    /// Load factor of that step.
    pub load: f64,
}

/// The path of one crack tip, starting at its initial position.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TipPath {
    /// Tip name, `<crack>.end` or `<crack>.start` (file `path_<name>.csv`).
    pub name: String,
    /// Points in growth order.
    pub points: Vec<PathPoint>,
    /// Why the tip stopped, when it did: `"outline"` (reached the outer boundary:
    /// structural failure), `"hole:<name>"`, `"coalescence:<tip>"`, `"window"` ...
    pub ended: Option<String>,
}

/// One converged load step.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StepRecord {
    /// Step index (0-based).
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// Crack-mouth opening displacement (m) of the first edge crack, when there is one.
    pub cmod: Option<f64>,
    /// Tip positions after the step, in the order of [`GrowthHistory::paths`].
    pub tips: Vec<[f64; 2]>,
    /// Coupling iterations of the step (0 for BEM-only and full PD).
    pub coupling_iterations: usize,
    /// Final coupling residual (0 when not coupled); `None` (`null` in `growth.json`,
    /// empty in `steps.csv`) when the coupling broke down in the step: the failure step of
    /// a PD-BEM run whose ligament gave way in a window.
    pub coupling_residual: Option<f64>,
    /// Bonds broken so far (PD modes), 0 otherwise.
    pub broken_bonds: usize,
    /// Wall time of the step (s).
    pub wall_time_s: f64,
}

/// A window outline (corners counter-clockwise, m) at a given step: the initial windows
/// and every window after a relocation, for the path plot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowOutline {
    /// Step after which this outline holds.
    pub step: usize,
    /// Tip the window serves.
    pub tip: String,
    /// Corners (m).
    pub corners: [[f64; 2]; 4],
}

/// Where and when the BEM body of a PD-BEM run first reached the PD onset stretch
/// (`pdbem_coupling::growth::overstrain`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Overstrain {
    /// Load step (0-based).
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// The most strained sample, one horizon inside the boundary (m).
    pub position: [f64; 2],
    /// Maximum principal strain there (-).
    pub strain: f64,
    /// Onset stretch of the PD failure law (-).
    pub onset: f64,
}

/// The first step after which a PD window held damage more than
/// [`crate::growth::records::STRAY_REACH`] horizons from every crack it tracks: a second
/// crack that PD-BEM does not follow.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowStray {
    /// Load step (0-based).
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// Window index.
    pub window: usize,
    /// The damaged node farthest from the window's crack lines (m).
    pub position: [f64; 2],
    /// Its damage (-).
    pub damage: f64,
    /// Its distance to the nearest crack line of the window (m).
    pub distance: f64,
    /// The window's horizon (m).
    pub horizon: f64,
}

/// One window relocation (the geometry iteration of Algorithm 2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Relocation {
    /// Step after which the window moved.
    pub step: usize,
    /// Tip.
    pub tip: String,
    /// Window centre before (m).
    pub from: [f64; 2],
    /// Window centre after (m); equal to `from` for a refined window against the outline
    /// rebuilt in place with its zone on the tip (`fine_zone` module docs).
    pub to: [f64; 2],
    /// BEM elements added to each crack face.
    pub elements_added: usize,
    /// This relocation's share of the rebuild wall time (mesh, assembly, factorization,
    /// new windows): relocations carried out by one rebuild share its time, so the
    /// shares add up to the total rebuild time (s).
    pub rebuild_s: f64,
}

/// Everything a growth run produced.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct GrowthHistory {
    /// `"pd-bem"`, `"bem-only"` or `"full-pd"`.
    pub mode: String,
    /// One path per tip.
    pub paths: Vec<TipPath>,
    /// One record per converged step.
    pub steps: Vec<StepRecord>,
    /// Window outlines (initial and after each relocation); empty without windows.
    pub windows: Vec<WindowOutline>,
    /// Relocations in order.
    pub relocations: Vec<Relocation>,
    /// Load factor of the first step in which a crack grew: K_eq >= K_c (BEM-only), a tip
    /// more than one horizon from its initial position (PD modes).
    pub initiation_load: Option<f64>,
    /// True when a crack reached the outer boundary (seed 002 Alg. 2 step 9).
    pub failure: bool,
    /// Load factor at failure.
    pub failure_load: Option<f64>,
    /// PD-BEM: the first step in which the BEM body away from the windows is strained to
    /// the PD onset stretch (where full PD would start a crack PD-BEM cannot grow); None
    /// when it never is, and in the other modes.
    #[serde(default)]
    pub overstrain: Option<Overstrain>,
    /// PD-BEM: the first step after which a window held damage off every crack it tracks
    /// (a second crack); None when none did, and in the other modes.
    #[serde(default)]
    pub stray_damage: Option<WindowStray>,
    /// Messages for the user (why the run stopped, merged windows, ...).
    pub notes: Vec<String>,
    /// Why the run ended early without structural failure (a load step no back-off could
    /// solve, a geometry that could not be meshed or solved), with what was tried; None
    /// when the run completed. The history then holds the steps completed before.
    #[serde(default)]
    pub failure_reason: Option<String>,
    /// The fracture-mechanics record along the path ([`super::sif_path`]): one row per
    /// tip and state, in order.
    #[serde(default)]
    pub sif_path: Vec<SifRow>,
    /// Field snapshots for plots (damage in the active windows, displacement at chosen
    /// steps); not serialised.
    #[serde(skip)]
    pub snapshots: Vec<FieldSnapshot>,
}

impl GrowthHistory {
    /// How the run ended (`summary.json` `end_state`): `failure` (a crack cut the body),
    /// `ended_early` (a step or geometry that could not be solved, with
    /// `failure_reason`), `tips_ended_at_holes_body_holds` (every tip stopped, one or more
    /// at a hole, whose crack then joins it, and the body holds: not a failure),
    /// `tips_ended_body_holds` (every tip stopped elsewhere, the body holds) or
    /// `load_budget_spent` (tips still growing when the load steps ran out).
    pub fn end_state(&self) -> &'static str {
        let at_hole = |p: &TipPath| p.ended.as_deref().is_some_and(|e| e.starts_with("hole:"));
        if self.failure {
            "failure"
        } else if self.failure_reason.is_some() {
            "ended_early"
        } else if !self.paths.is_empty() && self.paths.iter().all(|p| p.ended.is_some()) {
            if self.paths.iter().any(at_hole) {
                "tips_ended_at_holes_body_holds"
            } else {
                "tips_ended_body_holds"
            }
        } else {
            "load_budget_spent"
        }
    }
}

/// One row of `sif_path.csv`: one tip at one state of the crack geometry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SifRow {
    /// Load step (0-based).
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// Tip name.
    pub tip: String,
    /// Tip position (m).
    pub x: f64,
    /// Tip position (m).
    pub y: f64,
    /// Arc length of the tip's crack (m): for an edge crack the crack length a.
    pub crack_length: f64,
    /// Length grown at this tip (m).
    pub extension: f64,
    /// K_I at the load (Pa m^0.5).
    pub k1: f64,
    /// K_II at the load.
    pub k2: f64,
    /// Equivalent K by maximum circumferential stress.
    pub k_eq: f64,
    /// Kink angle (degrees, counter-clockwise from the crack line).
    pub kink_deg: f64,
    /// Energy release rate (K_I^2 + K_II^2) / E' (J/m^2).
    pub g: f64,
    /// CMOD of the first edge crack at the load (m), when there is one.
    pub cmod: Option<f64>,
}

impl SifRow {
    /// Rows of the tips still growing, from their SIFs at unit load (`sifs`), the CMOD at
    /// unit load and the state's `(step, load)`.
    pub fn rows(
        front: &Front,
        sifs: &[TipSif],
        cmod1: Option<f64>,
        (step, load): (usize, f64),
        e_prime: f64,
    ) -> Vec<SifRow> {
        sifs.iter()
            .filter(|s| front.tips[s.tip].ended.is_none())
            .map(|s| {
                let p = front.tip_position(s.tip);
                let (k1, k2) = (load * s.k1, load * s.k2);
                SifRow {
                    step,
                    load,
                    tip: front.tips[s.tip].name.clone(),
                    x: p.x,
                    y: p.y,
                    crack_length: polyline_length(&front.cracks[front.tips[s.tip].crack].points),
                    // abs: an ungrown tip gives -0.
                    extension: front.extension(s.tip).abs(),
                    k1,
                    k2,
                    k_eq: load * s.k_eq,
                    kink_deg: s.theta.to_degrees(),
                    g: energy_release(k1, k2, e_prime),
                    cmod: cmod1.map(|c| c * load),
                }
            })
            .collect()
    }
}

/// A field sampled at points at one step (damage in a window, displacement magnitude ...),
/// for snapshot plots. Not serialised.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FieldSnapshot {
    /// Step (0-based).
    pub step: usize,
    /// What it shows, used in the file name: `damage_window0`, `displacement`, ...
    pub label: String,
    /// Sample positions (m).
    pub points: Vec<[f64; 2]>,
    /// Values at the points.
    pub values: Vec<f64>,
    /// Where the tip of a window snapshot was when it was taken (before a relocation:
    /// the tip that triggered it); empty where the paths tell (end of a load step).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tips: Vec<[f64; 2]>,
    /// The discretisation each point belongs to (0: BEM interior points, 1: PD nodes),
    /// where a snapshot mixes them, so a plot sizes each one's markers on its own;
    /// empty: one discretisation.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub groups: Vec<u32>,
}

/// G = (K_I^2 + K_II^2) / E', without squaring K (K of 1e155 Pa m^0.5 squared overflows).
pub fn energy_release(k1: f64, k2: f64, e_prime: f64) -> f64 {
    let s = k1.hypot(k2) / e_prime.sqrt();
    s * s
}

#[cfg(test)]
mod tests {
    /// G = K^2 / E' without squaring K: finite up to the largest K a double holds.
    #[test]
    fn energy_release_does_not_overflow() {
        assert!((super::energy_release(3.0, 4.0, 25.0) - 1.0).abs() < 1e-15);
        let g = super::energy_release(1.27e155, 0.0, 1e158);
        assert!((g / 1.6129e152 - 1.0).abs() < 1e-12, "{g}");
    }

    use super::*;

    /// `pdbem plot-paths` reads `growth.json` back: a step whose coupling broke down (no
    /// residual, no CMOD) must survive the round trip, not stop the overlay (it did while
    /// the residual was a bare f64 written as `null`).
    #[test]
    fn a_history_with_a_broken_down_step_reads_back() {
        let h = GrowthHistory {
            mode: "pd-bem".into(),
            steps: vec![
                StepRecord {
                    step: 0,
                    load: 0.1,
                    cmod: Some(1e-3),
                    coupling_residual: Some(2e-5),
                    ..Default::default()
                },
                StepRecord {
                    step: 1,
                    load: 0.12,
                    ..Default::default()
                },
            ],
            failure: true,
            failure_load: Some(0.12),
            ..Default::default()
        };
        let text = serde_json::to_string(&h).unwrap();
        assert!(text.contains("\"coupling_residual\":null"), "{text}");
        let back: GrowthHistory = serde_json::from_str(&text).unwrap();
        assert_eq!(back, h);
    }
}

//! What a run returns: [`RunSummary`] (serialised as `summary.json`, schema in
//! docs/outputs.md) with its [`TipResult`]s and [`CrackResult`]s.

use serde::{Deserialize, Serialize};

/// Result of one run; serialised as `summary.json` (schema: docs/outputs.md).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// `bem`, `pd`, `coupled` or `growth`.
    pub mode: String,
    /// BEM elements (null when no BEM mesh).
    pub elements: Option<usize>,
    /// Wall time of the solve (s), set by the runner when the solver leaves 0.
    pub wall_time_s: f64,
    /// Crack tips.
    pub tips: Vec<TipResult>,
    /// Cracks.
    pub cracks: Vec<CrackResult>,
    /// Messages for the user (warnings, degraded plots).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// Mode-specific fields, written at the top level of `summary.json`
    /// (e.g. `nodes`, `bonds`, `coupling`, `relocations`).
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
    /// Mesh nodes / element end points for the geometry plot (not serialised).
    #[serde(skip)]
    pub plot_nodes: Vec<(f64, f64)>,
}

/// Results at one crack tip. SIFs in Pa sqrt(m), angles in degrees.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TipResult {
    /// Tip name, `<crack>.end` or `<crack>.start`.
    pub name: String,
    /// Tip position (m).
    pub position: [f64; 2],
    /// Reported K_I (the solver's preferred estimate).
    pub k1: f64,
    /// Reported K_II.
    pub k2: f64,
    /// Kink angle by maximum circumferential stress (from the crack line, CCW positive).
    pub kink_deg: f64,
    /// Where `k1`, `k2` come from when not the crack-opening fit: `interaction_integral`
    /// (a crack loaded on one face, or a fit without stations,
    /// [`crate::run_bem::level::tip_result`]). Absent: the fit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_source: Option<String>,
    /// K_I from crack-opening displacement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_cod: Option<f64>,
    /// K_II from crack-opening displacement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_cod: Option<f64>,
    /// K_I from the J / interaction integral.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_j: Option<f64>,
    /// K_II from the interaction integral.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_j: Option<f64>,
    /// J-integral on the tip's contour (J/m^2), from the solved field alone (no auxiliary
    /// field): a check on `g`, equal to it in linear elastic fracture mechanics.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub j: Option<f64>,
    /// Energy release rate of the reported K, G = (k1^2 + k2^2) / E' (J/m^2); set by the
    /// runner for every tip ([`crate::runner::plausibility::review`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g: Option<f64>,
    /// Reference K_I.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_ref: Option<f64>,
    /// Reference K_II.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_ref: Option<f64>,
    /// Reference kink angle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kink_ref_deg: Option<f64>,
    /// Reference K_I from the FEM table (SENT, 0.1 <= a/W <= 0.8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_ref_fem: Option<f64>,
    /// Relative error of `k1` (see [`super::reference::relative_error`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_err: Option<f64>,
    /// Relative error of `k2`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_err: Option<f64>,
    /// Kink angle error (degrees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kink_err_deg: Option<f64>,
    /// Relative error of `k1` against the FEM table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_err_fem: Option<f64>,
    /// Error estimate of `k1` (Pa m^0.5): |K_I(h) - K_I(2h)| ([`crate::refine`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_err_est: Option<f64>,
    /// Error estimate of `k2` (Pa m^0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_err_est: Option<f64>,
    /// Messages about this tip (how its K was obtained when not the usual way); the
    /// runner moves them into the summary's `notes`
    /// ([`super::plausibility::review`]). Not serialised.
    #[serde(skip)]
    pub notes: Vec<String>,
}

/// Results of one crack.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CrackResult {
    /// Crack name.
    pub name: String,
    /// Crack-mouth opening displacement (m), for cracks with a mouth on the outline.
    pub cmod: Option<f64>,
    /// Reference CMOD (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cmod_ref: Option<f64>,
    /// Relative CMOD error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cmod_err: Option<f64>,
    /// Error estimate of `cmod` (m): |CMOD(h) - CMOD(2h)| ([`crate::refine`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cmod_err_est: Option<f64>,
}

impl RunSummary {
    /// Why a growth run ended early (`complete: false`, its `failure_reason`); None for a
    /// complete run and for other modes.
    pub fn incomplete(&self) -> Option<String> {
        if self.extra.get("complete") != Some(&serde_json::Value::Bool(false)) {
            return None;
        }
        Some(
            self.extra
                .get("failure_reason")
                .and_then(|r| r.as_str())
                .unwrap_or("no reason given")
                .to_string(),
        )
    }

    /// The first reported number of the tips and cracks that is not finite, as a dotted
    /// path with its value (`tips.0.k1 = inf`); `None` when all are finite. A run must not
    /// report NaN or infinity (`summary.json` would write `null`).
    pub fn non_finite(&self) -> Option<String> {
        let walk = |section: &str, i: usize, v: serde_json::Value, raw: &[(&str, f64)]| {
            for (name, x) in raw {
                if !x.is_finite() {
                    return Some(format!("{section}.{i}.{name} = {x}"));
                }
            }
            let obj = v.as_object()?;
            obj.iter()
                .find(|(k, v)| v.is_null() && k.as_str() != "cmod")
                .map(|(k, _)| format!("{section}.{i}.{k} = NaN or infinite"))
        };
        for (i, t) in self.tips.iter().enumerate() {
            let raw = [
                ("position.0", t.position[0]),
                ("position.1", t.position[1]),
                ("k1", t.k1),
                ("k2", t.k2),
                ("kink_deg", t.kink_deg),
            ];
            let v = serde_json::to_value(t).unwrap_or(serde_json::Value::Null);
            if let Some(f) = walk("tips", i, v, &raw) {
                return Some(f);
            }
        }
        for (i, c) in self.cracks.iter().enumerate() {
            let raw: Vec<(&str, f64)> = [
                ("cmod", c.cmod),
                ("cmod_ref", c.cmod_ref),
                ("cmod_err", c.cmod_err),
            ]
            .into_iter()
            .filter_map(|(k, v)| v.map(|v| (k, v)))
            .collect();
            let v = serde_json::to_value(c).unwrap_or(serde_json::Value::Null);
            if let Some(f) = walk("cracks", i, v, &raw) {
                return Some(f);
            }
        }
        None
    }
}

//! Parameters of crack growth (seed 002 Algorithm 2) and their validation.

use pdbem_pd::crack_path::PathParams;

use crate::error::CouplingError;
use crate::iteration::{CouplingParams, PdSolve, StaggeredParams};

/// Load stepping: step k (0-based) runs at load factor `initial + k step` (seed 002
/// Algorithm 2 steps 2-3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadSteps {
    /// Load factor of the first step (> 0).
    pub initial: f64,
    /// Increment per step (>= 0).
    pub step: f64,
    /// Number of steps (>= 1); the run also ends at structural failure.
    pub count: usize,
}

impl LoadSteps {
    /// Load factor of step `k`.
    pub fn factor(&self, k: usize) -> f64 {
        load_factor(self.initial, self.step, k)
    }
}

/// `initial + k step` rounded to 12 significant digits, so that the factors the scene
/// means (3.35, not 3.3499999999999996) are the ones solved, logged and printed; the
/// rounding moves a factor by at most 5e-13 of itself.
pub fn load_factor(initial: f64, step: f64, k: usize) -> f64 {
    let f = initial + k as f64 * step;
    format!("{f:.11e}").parse().unwrap_or(f)
}

/// Parameters of [`crate::growth::Growth`].
#[derive(Debug, Clone, PartialEq)]
pub struct GrowthParams {
    /// Load steps.
    pub loads: LoadSteps,
    /// The window moves when the tip comes closer than `(1 - trigger_ratio)` of the window
    /// side to an interface side (seed 002 section 2.3.3: 0.9).
    pub trigger_ratio: f64,
    /// Window move per relocation (m), along the growth direction (seed 002 section 3.2.2:
    /// 0.5 m); snapped to the PD lattice so old and new nodes coincide.
    pub move_distance: f64,
    /// BEM elements added to each crack face per relocation (seed 002 section 3.2.2: 5).
    pub elements_per_extension: usize,
    /// Tip tracker settings (damage threshold 0.38, smoothing over 2 dx).
    pub path: PathParams,
    /// Length over which the growth direction at the tip is measured (multiples of dx).
    /// Default 5: long enough to average the lattice zig-zag, short enough to follow a
    /// kink within the window.
    pub direction_length: f64,
    /// A tip closer than this to the outer boundary (multiples of dx) has cut the body
    /// (seed 002 Algorithm 2 step 9). Default 1.5: the last real node row lies dx/2 from
    /// the boundary, so damage there means the crack reached it.
    pub boundary_reach: f64,
    /// Relocations allowed within one load step (unstable growth under load control runs
    /// through several windows in one step). Default 200.
    pub max_relocations_per_step: usize,
    /// Algorithm 1 parameters of every step. [`GrowthParams::new`] sets the PD solver to
    /// [`PdSolve::Staggered`] with one break round per coupling iteration: the crack
    /// advances by about one break front per iteration, so the window follows it (the
    /// seed's ADR with a fixed number of steps per iteration limits growth the same way).
    pub coupling: CouplingParams,
    /// End the run at the first load step whose BEM body reaches the PD onset stretch
    /// away from the windows ([`crate::growth::overstrain`]), or after which a window
    /// holds damage off every crack it tracks (the stray-damage watch of
    /// [`crate::growth::driver`]), with [`crate::growth::GrowthResult::failure_reason`]:
    /// PD would start, or has started, a crack there that PD-BEM does not model. False
    /// (the default here): note it and go on. Scenes end by default
    /// (`growth.overstrain: End`).
    pub end_on_overstrain: bool,
}

impl GrowthParams {
    /// Default settings of seed 002 section 3.2.2 with the given loads and move distance.
    pub fn new(loads: LoadSteps, move_distance: f64) -> Self {
        GrowthParams {
            loads,
            trigger_ratio: 0.9,
            move_distance,
            elements_per_extension: 5,
            path: PathParams::default(),
            direction_length: 5.0,
            boundary_reach: 1.5,
            max_relocations_per_step: 200,
            end_on_overstrain: false,
            coupling: CouplingParams {
                pd_solve: PdSolve::Staggered(StaggeredParams::default()),
                ..Default::default()
            },
        }
    }

    /// Checks every field; the message names the field and its range.
    pub fn validate(&self) -> Result<(), CouplingError> {
        let bad = |field: &'static str, message: String| {
            Err(CouplingError::InvalidGrowth { field, message })
        };
        let l = &self.loads;
        if !(l.initial.is_finite() && l.initial > 0.0) {
            return bad("loads.initial", format!("{} must be positive", l.initial));
        }
        if !(l.step.is_finite() && l.step >= 0.0) {
            return bad("loads.step", format!("{} must be >= 0", l.step));
        }
        if l.count == 0 {
            return bad("loads.count", "need at least one load step".into());
        }
        if !(self.trigger_ratio > 0.5 && self.trigger_ratio < 1.0) {
            return bad(
                "trigger_ratio",
                format!(
                    "{} must lie in (0.5, 1) (seed 002: 0.9)",
                    self.trigger_ratio
                ),
            );
        }
        if !(self.move_distance.is_finite() && self.move_distance > 0.0) {
            return bad(
                "move_distance",
                format!("{} m must be positive", self.move_distance),
            );
        }
        if self.elements_per_extension == 0 {
            return bad("elements_per_extension", "need at least one element".into());
        }
        if !(self.direction_length.is_finite() && self.direction_length >= 1.0) {
            return bad(
                "direction_length",
                format!("{} dx must be at least 1 dx", self.direction_length),
            );
        }
        if !(self.boundary_reach.is_finite() && self.boundary_reach > 0.0) {
            return bad(
                "boundary_reach",
                format!("{} dx must be positive", self.boundary_reach),
            );
        }
        self.path
            .validate()
            .map_err(|e| CouplingError::InvalidGrowth {
                field: "path",
                message: e.to_string(),
            })
    }
}

/// Why PD-BEM growth refuses the tanh degradation law (seed 000 Eq. 12). A window's
/// equilibria are solved with the bond history frozen, and a softening bond past `s_c`
/// then carries no force without breaking, so whole groups of window nodes can move
/// without limit at no residual: the solvers reached such runaway states and the run
/// reported them. Measured on `growth_tension_edge` with `Degradation(s_m: 0.02, s_c:
/// 0.06)` from load 2.5: a window displacement of 90 m after the first equilibrium (the
/// window is 2 m wide), then 1e135 m, a CMOD of -1.6e58 m and exit 0. The seed's PD-BEM
/// method (seed 002) breaks bonds at a critical stretch.
pub const TANH_LAW_REFUSED: &str = "the tanh degradation law is not supported in PD-BEM growth: the windows solve their equilibria with the bond history frozen, where a softening bond past s_c carries no force without breaking, and the solvers then find runaway states; use CriticalStretch or FromGc (the seed's PD-BEM method breaks bonds at a critical stretch), or growth.mode FullPd";

/// Refuses a bond law PD-BEM growth cannot solve ([`TANH_LAW_REFUSED`]).
pub fn check_bond_law(failure: &pdbem_pd::Failure) -> Result<(), CouplingError> {
    if matches!(failure, pdbem_pd::Failure::Degradation { .. }) {
        return Err(CouplingError::InvalidGrowth {
            field: "pd.failure",
            message: TANH_LAW_REFUSED.into(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tanh_law_is_refused_and_breaking_laws_pass() {
        let tanh = pdbem_pd::Failure::Degradation {
            s_m: 0.01,
            s_c: 0.03,
            beta: 3.0,
        };
        let e = check_bond_law(&tanh).unwrap_err().to_string();
        assert!(e.contains("pd.failure") && e.contains("runaway"), "{e}");
        for ok in [
            pdbem_pd::Failure::None,
            pdbem_pd::Failure::CriticalStretch { s0: 0.01 },
            pdbem_pd::Failure::FractureEnergy { g_c: 1.0 },
        ] {
            assert!(check_bond_law(&ok).is_ok());
        }
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let loads = LoadSteps {
            initial: 1.0,
            step: 0.1,
            count: 3,
        };
        assert!(GrowthParams::new(loads, 0.5).validate().is_ok());
        let mut p = GrowthParams::new(loads, 0.5);
        p.trigger_ratio = 1.2;
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("trigger_ratio") && e.contains("1.2"), "{e}");
        let p = GrowthParams::new(LoadSteps { count: 0, ..loads }, 0.5);
        assert!(p
            .validate()
            .unwrap_err()
            .to_string()
            .contains("loads.count"));
        let p = GrowthParams::new(loads, -1.0);
        assert!(p
            .validate()
            .unwrap_err()
            .to_string()
            .contains("move_distance"));
    }
}

#[cfg(test)]
mod load_tests {
    #[test]
    fn load_factors_are_the_decimal_ones() {
        assert_eq!(super::load_factor(3.3, 0.05, 1), 3.35);
        assert_eq!(super::load_factor(0.1, 0.2, 1), 0.3);
        assert_eq!(super::load_factor(1e6, 0.0, 7), 1e6);
    }
}

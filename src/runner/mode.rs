//! [`Mode`]: how a scene is solved, from the sections it contains ([`mode_of`]).

use crate::scene::Scene;

/// How a scene is solved, from the sections it contains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No `pd`: BEM alone.
    Bem,
    /// `pd` without `coupling`: PD over the whole body.
    Pd,
    /// `coupling` without `growth`: static PD-BEM coupling (issue 4).
    Coupled,
    /// `growth`: crack growth (issue 5).
    Growth,
}

impl Mode {
    /// The `mode` string of `summary.json`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Mode::Bem => "bem",
            Mode::Pd => "pd",
            Mode::Coupled => "coupled",
            Mode::Growth => "growth",
        }
    }
}

/// The mode of a scene.
pub fn mode_of(scene: &Scene) -> Mode {
    if scene.growth.is_some() {
        Mode::Growth
    } else if scene.coupling.is_some() {
        Mode::Coupled
    } else if scene.pd.is_some() {
        Mode::Pd
    } else {
        Mode::Bem
    }
}

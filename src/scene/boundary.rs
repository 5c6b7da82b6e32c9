//! `boundary` and `load`: conditions on named edge groups, and the load factor
//! that scales every boundary value (and the remote stress) per load step.

use serde::{Deserialize, Serialize};

/// One condition on a named edge group. Parts of the boundary that no
/// condition names are traction-free.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryCondition {
    /// Edge group: an outline edge, `outline`, a patch, a hole, a crack
    /// (both faces) or a crack face `<crack>.upper` / `<crack>.lower`.
    pub on: String,
    /// Global x component. Default `Free`.
    #[serde(default)]
    pub x: Component,
    /// Global y component. Default `Free`.
    #[serde(default)]
    pub y: Component,
    /// Normal traction (Pa, positive = tension, along the outward normal).
    /// Only with `x` and `y` free. Default: none.
    #[serde(default)]
    pub normal: Option<f64>,
    /// Tangential traction (Pa, along the boundary's running direction). Only
    /// with `x` and `y` free. Default: none.
    #[serde(default)]
    pub shear: Option<f64>,
}

/// One component of a boundary condition.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Component {
    /// Traction-free (the default).
    #[default]
    Free,
    /// Prescribed displacement (m), scaled by the load factor.
    Displacement(f64),
    /// Prescribed traction (Pa), scaled by the load factor.
    Traction(f64),
}

impl Component {
    /// The prescribed value (0 for `Free`).
    pub fn value(&self) -> f64 {
        match self {
            Component::Free => 0.0,
            Component::Displacement(v) | Component::Traction(v) => *v,
        }
    }
}

impl BoundaryCondition {
    /// True when this condition prescribes a non-zero value (it loads the body).
    pub fn is_loading(&self) -> bool {
        self.x.value() != 0.0
            || self.y.value() != 0.0
            || self.normal.is_some_and(|v| v != 0.0)
            || self.shear.is_some_and(|v| v != 0.0)
    }
}

/// Load stepping: step k (0-based) applies the factor `initial + k step` to
/// every boundary value and to the remote stress.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Load {
    /// Factor of the first step (-). Default 1.
    pub initial: f64,
    /// Factor increment per step (-). Default 0.
    pub step: f64,
    /// Number of steps, 1 to 100000. Default 1 (a single step at factor `initial`).
    pub count: usize,
}

impl Default for Load {
    fn default() -> Self {
        Load {
            initial: 1.0,
            step: 0.0,
            count: 1,
        }
    }
}

impl Load {
    /// The load factor of every step (at most
    /// [`MAX_LOAD_STEPS`](crate::scene::validate::limits::MAX_LOAD_STEPS) of them: validation
    /// rejects more, and an unvalidated count must not allocate without bound).
    pub fn factors(&self) -> Vec<f64> {
        (0..self
            .count
            .min(crate::scene::validate::limits::MAX_LOAD_STEPS))
            .map(|k| pdbem_coupling::growth::params::load_factor(self.initial, self.step, k))
            .collect()
    }
}

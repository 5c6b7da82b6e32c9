//! `coupling` (issue 4: PD windows iterated against the BEM body) and
//! `growth` (issue 5: load stepping with moving windows). Absent = not built.

use serde::{Deserialize, Serialize};

use super::body::Pt;

/// Static PD-BEM coupling (seed 002 Algorithm 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Coupling {
    /// Side L_w of the square window (m), > 0 (for `Region`: its width).
    pub side: f64,
    /// Real PD nodes per window side (dx = side / n): at least 2 m (two horizons, m =
    /// `pd.horizon_factor`; 7 at the default), at most 5000, even with `AtTips`.
    pub n: usize,
    /// Where the windows go. Default `AtTips`.
    #[serde(default)]
    pub placement: Placement,
    /// Interface relaxation. Default `Aitken(0.3)` (seed 002 section 3.1.3 uses w = 0.3).
    #[serde(default)]
    pub relaxation: Relaxation,
    /// Convergence: relative change of interface displacements below psi, in (0, 0.1].
    /// Default 1e-4.
    #[serde(default = "default_psi")]
    pub psi: f64,
    /// Coupling iteration cap, >= 1. Default 50.
    #[serde(default = "default_max_iter")]
    pub max_iter: usize,
    /// How BEM displacements reach the PD virtual layers. Default `Copy` (seed 002 Eq. 23).
    #[serde(default)]
    pub displacement_map: DisplacementMap,
    /// Which side takes which interface condition. Default `DisplacementToPd`.
    #[serde(default)]
    pub ordering: CouplingOrdering,
    /// A zone of finer cells centred on the crack tip of every window (coarse at the
    /// interface, fine at the tip; dual horizons between the sizes). Default none.
    #[serde(default)]
    pub refine: Option<WindowRefine>,
}

/// The refinement zone of the windows (`pdbem_pd::mixed`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindowRefine {
    /// Half the side of the square zone (m), > 0: window cells whose centres lie within it
    /// are split. The zone must keep two horizons from every window side.
    pub half_size: f64,
    /// Splits per cell: 1 (4 children, dx / 2) or 2 (16 children, dx / 4).
    pub levels: u32,
}

impl Coupling {
    /// PD grid spacing of the windows (m): `side / n` (for a `Region`, whose width must
    /// equal `side`, width / n).
    pub fn dx(&self) -> f64 {
        self.side / self.n as f64
    }
}

fn default_psi() -> f64 {
    1e-4
}

fn default_max_iter() -> usize {
    50
}

/// Window placement.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Placement {
    /// One square window centred on each crack tip inside the body, axes along the crack.
    #[default]
    AtTips,
    /// One square window centred at `center` (m), rotated by `angle_deg`.
    Centered {
        /// Window centre (m).
        center: Pt,
        /// Rotation (degrees, counter-clockwise). Default 0.
        #[serde(default)]
        angle_deg: f64,
    },
    /// An axis-aligned rectangle (e.g. half a beam); sides on the outline take
    /// the scene's boundary conditions.
    Region {
        /// Lower-left x (m).
        x0: f64,
        /// Lower-left y (m).
        y0: f64,
        /// Width (m), > 0; must equal `side`.
        width: f64,
        /// Height (m), > 0.
        height: f64,
    },
}

/// Interface relaxation scheme (seed 002 Eqs. 25-28; IQN-ILS as in preCICE).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Relaxation {
    /// Constant factor w in (0, 1].
    Constant(f64),
    /// Aitken's dynamic factor, starting at w0 in (0, 1].
    Aitken(f64),
    /// Interface quasi-Newton with least squares.
    IqnIls {
        /// Relaxation of the first iteration, in (0, 1]. Default 0.1.
        #[serde(default = "default_w0")]
        w0: f64,
    },
}

fn default_w0() -> f64 {
    0.1
}

impl Default for Relaxation {
    fn default() -> Self {
        Relaxation::Aitken(0.3)
    }
}

/// BEM-to-PD displacement map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum DisplacementMap {
    /// Copy the interface element's value to its row of virtual nodes (seed 002 Eq. 23).
    #[default]
    Copy,
    /// Evaluate the BEM displacement at each virtual node (interior points).
    Interior,
    /// First-order expansion from the element value, its tangential derivative and
    /// traction (exact for uniform strain; as cheap as `Copy`).
    Taylor,
}

/// Interface ordering of Algorithm 1 (`pdbem_coupling::Ordering`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum CouplingOrdering {
    /// PD takes the BEM displacements on its virtual layers, BEM the PD forces as
    /// tractions (seed 002 Eqs. 23-24).
    #[default]
    DisplacementToPd,
    /// PD takes the BEM tractions through seed 001's transfer functions, BEM the PD
    /// interface displacement (static coupled solves only).
    TractionToPd,
}

/// Crack growth (seed 002 Algorithm 2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Growth {
    /// `PdBem` (default), `BemOnly` (SIF + kink + `da`) or `FullPd`.
    #[serde(default)]
    pub mode: GrowthMode,
    /// Move the window when the tip passes this fraction of the window, in (0, 1). Default 0.9 (seed 002).
    #[serde(default = "default_trigger")]
    pub trigger_ratio: f64,
    /// Window move per relocation (m), in (0, coupling.side]. Default side / 4.
    #[serde(default)]
    pub move_distance: Option<f64>,
    /// BEM elements added to each crack face per relocation, >= 1. Default 5 (seed 002 section 3.2.2).
    #[serde(default = "default_elements_per_extension")]
    pub elements_per_extension: usize,
    /// Crack increment of `BemOnly` growth (m), > 0. Default: the element size.
    #[serde(default)]
    pub da: Option<f64>,
    /// Crack advance between the rows of `sif_path.csv` within a load step in the PD modes
    /// (m), >= 0; each row is a BEM solve of the path geometry
    /// (`pdbem_coupling::growth::sif_path`); 0: no record in the PD modes. Default: 1/40
    /// of the smaller side of the body's bounding box (0.25 m on the seed plate).
    #[serde(default)]
    pub sif_spacing: Option<f64>,
    /// Damage above which a node belongs to the macro crack (-). Default 0.38 (DESIGN.md).
    #[serde(default = "default_damage_threshold")]
    pub damage_threshold: f64,
    /// Load steps (0-based, below `load.count`) after which field snapshots are plotted
    /// as well: displacement magnitude over the body, and damage in the PD modes (the
    /// windows of PD-BEM, the whole grid of full PD). Default: none (snapshots at
    /// initiation and at the end only).
    #[serde(default)]
    pub snapshot_steps: Vec<usize>,
    /// PD-BEM: what to do when the BEM body reaches the PD onset stretch away from the
    /// windows (`pdbem_coupling::growth::overstrain`). Default `End`.
    #[serde(default)]
    pub overstrain: OverstrainAction,
}

/// What PD-BEM does at the first load step whose BEM body reaches the PD onset stretch
/// away from the windows, where PD would start a crack the windows cannot model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum OverstrainAction {
    /// End the run there (`complete: false`, `failure_reason`): growth beyond that load
    /// is not computed.
    #[default]
    End,
    /// Note it and go on, assuming the body stays elastic there.
    Note,
}

fn default_trigger() -> f64 {
    0.9
}

fn default_elements_per_extension() -> usize {
    5
}

fn default_damage_threshold() -> f64 {
    0.38
}

/// Growth comparison mode (issue 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum GrowthMode {
    /// PD windows over the tips, BEM elsewhere.
    #[default]
    PdBem,
    /// BEM alone: SIF, maximum circumferential stress kink, fixed increment.
    BemOnly,
    /// PD over the whole body at the window resolution.
    FullPd,
}

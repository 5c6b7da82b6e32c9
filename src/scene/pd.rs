//! `pd`: peridynamic model and solver settings (issue 3). Absent = no PD.
//! Without `coupling` the whole body is solved by PD alone; with `coupling`
//! these settings describe the PD windows.

use serde::{Deserialize, Serialize};

/// Default horizon factor m = delta / dx: 3.015 (seed 000, seed 002).
pub(crate) fn default_horizon_factor() -> f64 {
    3.015
}

/// PD settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdSettings {
    /// Grid spacing dx (m), > 0. Give `dx` or `nx`.
    #[serde(default)]
    pub dx: Option<f64>,
    /// Nodes across the body's bounding-box width (dx = width / nx), at most 100000. Give
    /// `dx` or `nx`.
    #[serde(default)]
    pub nx: Option<usize>,
    /// Constitutive model. Default `Pmb` (bond-based: nu is 1/3 in plane stress, 1/4 in
    /// plane strain, whatever `material.nu` says).
    #[serde(default)]
    pub model: PdModelKind,
    /// Horizon factor m, delta = m dx, in [2, 6] (where the PD calibration holds). Default
    /// 3.015 (seed 000 section 3.2).
    #[serde(default = "default_horizon_factor")]
    pub horizon_factor: f64,
    /// Solver and its parameters. Default `Switching` with default parameters.
    #[serde(default)]
    pub solver: PdSolver,
    /// Bond failure law. Default `Elastic` (no bond breaks).
    #[serde(default)]
    pub failure: Failure,
    /// Surface correction (Madenci & Oterkus energy method). Default false.
    #[serde(default)]
    pub surface_correction: bool,
    /// Stiffen the bonds around pre-crack faces by the energy factor of the bonds the
    /// pre-cracks removed, so the faces match the traction-free LEFM crack. Default: on in
    /// PD-BEM windows (their pre-crack continues a BEM crack), off in stand-alone PD.
    #[serde(default)]
    pub crack_face_correction: Option<bool>,
    /// Names of scene cracks cut as pre-cracks. Default: all scene cracks.
    #[serde(default)]
    pub pre_cracks: Option<Vec<String>>,
    /// How the scene's tractions load the PD body. Default `BodyForceLayer`.
    #[serde(default)]
    pub traction: PdTraction,
    /// Adaptive particle refinement on dual horizons (seed 004 section 3), stand-alone
    /// state-based PD only: an elastic solve, or with `solver: Explicit` adaptive
    /// dynamics. Default: none (a uniform grid).
    #[serde(default)]
    pub refinement: Option<PdRefinement>,
    /// Squares of finer cells on the stand-alone grid (`pdbem_pd::mixed`: each cell whose
    /// centre lies in a zone is split into 4 children per level, the sizes interacting
    /// through dual horizons, seed 004 Eq. 13), for either model and every quasi-static
    /// solver, bond breaking and the tanh law. Default none (a uniform grid).
    #[serde(default)]
    pub refine_zones: Vec<PdZone>,
}

impl PdSettings {
    /// Notes on `refine_zones`: a zone of 2 levels that no 1-level zone surrounds by a
    /// coarse cell puts a size jump of 4 at its edge, where dual horizons are least
    /// accurate (docs/seed004.md, "Fixed zones on the grid").
    pub fn zone_notes(&self) -> Vec<String> {
        let margin = self.dx.unwrap_or(0.0);
        let zones = &self.refine_zones;
        let graded = |z: &PdZone| {
            zones.iter().any(|o| {
                o.levels == 1
                    && (o.centre.0 - z.centre.0)
                        .abs()
                        .max((o.centre.1 - z.centre.1).abs())
                        + z.half_size
                        + margin
                        <= o.half_size
            })
        };
        zones
            .iter()
            .enumerate()
            .filter(|(_, z)| z.levels >= 2 && !graded(z))
            .map(|(i, _)| format!(
                "pd.refine_zones.{i}: 2 levels against coarse cells put a size jump of 4 at the zone's edge, where dual horizons are least accurate (seed 004's plate: initiation 47 MPa with such a zone, 46 MPa on the uniform 0.5 mm grid and with a 1-level zone around it); nest it in a 1-level zone reaching a coarse cell{} beyond it",
                if margin > 0.0 { format!(" ({margin:.4e} m)") } else { String::new() }
            ))
            .collect()
    }
}

/// A square zone of finer cells on a stand-alone PD grid (`pdbem_pd::RefineZone`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdZone {
    /// Centre (x, y) (m).
    pub centre: (f64, f64),
    /// Half the side (m), > 0: the cells whose centres lie within this distance of the
    /// centre along x and along y are split.
    pub half_size: f64,
    /// Splits per cell, 1 (4 children, dx / 2) or 2 (16 children, dx / 4). Default 1.
    #[serde(default = "one_level")]
    pub levels: u32,
}

fn one_level() -> u32 {
    1
}

/// Adaptive particle refinement (seed 004 section 3, `pdbem_pd::refine`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PdRefinement {
    /// Critical damage phi_c of seed 004 Eq. 15 in (0, 1), `None` for no damage
    /// criterion. Default 0.4 (the seed's).
    pub critical_damage: Option<f64>,
    /// Static criterion: refine the particles within this distance (m) of the pre-cracks
    /// (tips included) before the solve. Default none.
    pub near_cracks: Option<f64>,
    /// Static criterion: refine the particles in these circles before the solve.
    pub circles: Vec<RefineCircle>,
    /// Deepest refinement level, 1 to 4 (each level halves the spacing). Default 1.
    pub max_level: u8,
    /// Relative residual of the conjugate-gradient solve, in (0, 1). Default 1e-10.
    pub tolerance: f64,
    /// Children keep their parent's horizon (seed 004 Table 3, delta_2 = delta_1) instead
    /// of halving it. Default false.
    pub keep_horizon: bool,
    /// Factor alpha of seed 004 Eq. 16 (split a particle whose accumulated strain passes
    /// alpha s_c), in (0, 1); with a breaking failure law (the critical stretch or the tanh
    /// law) only. Default none (no strain criterion; the seed uses 0.5).
    pub strain_factor: Option<f64>,
    /// Explicit dynamics: time steps between the refinement checks, >= 1. Default 10.
    pub check_every: usize,
    /// The crack-initiation ramp on the grid's cells: before a round's bonds break, split
    /// the cells below `max_level` that hold an end of a bond past its breaking stretch,
    /// so bonds break on the deepest level only (not a criterion of the seed). Default:
    /// on where it applies (`None`).
    pub split_before_breaking: Option<bool>,
    /// What splits: seed 004's particles or the grid's cells. Default `Auto`.
    pub on: RefineOn,
}

/// What `pd.refinement` splits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum RefineOn {
    /// The grid's cells under the tanh law (`failure: Degradation`) with a quasi-static
    /// solver; seed 004's particles otherwise.
    #[default]
    Auto,
    /// Seed 004's dual-horizon state-based particles (`pdbem_pd::refine`): the elastic
    /// solve and the crack-initiation ramp by conjugate gradients, explicit dynamics.
    Particles,
    /// The grid's cells (`pdbem_pd::adapt`): a mixed-grid model, PMB or state-based,
    /// solved by `pd.solver` (Adr, Implicit, Switching) under every failure law; the
    /// crack-initiation ramp by Newton.
    Cells,
}

impl Default for PdRefinement {
    fn default() -> Self {
        PdRefinement {
            critical_damage: Some(0.4),
            near_cracks: None,
            circles: Vec::new(),
            max_level: 1,
            tolerance: 1e-10,
            keep_horizon: false,
            strain_factor: None,
            check_every: 10,
            split_before_breaking: None,
            on: RefineOn::Auto,
        }
    }
}

impl PdRefinement {
    /// Whether this refinement runs on the grid's cells (`pdbem_pd::adapt`): `on: Cells`,
    /// or by default the tanh law (`failure: Degradation`) under a quasi-static solver
    /// (Adr, Implicit, Switching), with either model. Otherwise the grid becomes seed
    /// 004's dual-horizon particles (`pdbem_pd::refine`: elastic solve, brittle
    /// initiation ramp, explicit dynamics).
    pub fn on_cells(&self, failure: &Failure, solver: &PdSolver) -> bool {
        match self.on {
            RefineOn::Cells => true,
            RefineOn::Particles => false,
            RefineOn::Auto => {
                matches!(failure, Failure::Degradation { .. })
                    && !matches!(solver, PdSolver::Explicit(_))
            }
        }
    }

    /// Notes on settings a refined body does not read (no silent garbage): under explicit
    /// dynamics the conjugate-gradient `tolerance`; in the quasi-static solves `pd.solver`
    /// other than the default (a refined body has one quasi-static solver, conjugate
    /// gradients on its linearised energy, `pdbem_pd::refine`) and `check_every`.
    pub fn inert_notes(&self, solver: &PdSolver, failure: &Failure) -> Vec<String> {
        let defaults = PdRefinement::default();
        let mut notes = Vec::new();
        if self.on_cells(failure, solver) {
            if self.tolerance != defaults.tolerance {
                notes.push(format!(
                    "pd.refinement.tolerance = {:e} is not read: refined cells are solved by pd.solver to its own tolerance",
                    self.tolerance
                ));
            }
            if self.check_every != defaults.check_every {
                notes.push(format!(
                    "pd.refinement.check_every = {} is not read: the quasi-static ramp checks the criteria at every converged load step",
                    self.check_every
                ));
            }
            return notes;
        }
        if matches!(solver, PdSolver::Explicit(_)) {
            if self.tolerance != defaults.tolerance {
                notes.push(format!(
                    "pd.refinement.tolerance = {:e} is not read: adaptive explicit dynamics solves no linear system",
                    self.tolerance
                ));
            }
            return notes;
        }
        if *solver != PdSolver::default() {
            let name = match solver {
                PdSolver::Adr(_) => "Adr",
                PdSolver::Implicit(_) => "Implicit",
                _ => "Switching",
            };
            notes.push(format!(
                "pd.solver ({name}) is not read: a refined body's quasi-static solves are conjugate gradients on its linearised energy, to the relative residual pd.refinement.tolerance = {:e} (pd.solver: Explicit runs adaptive dynamics; the grid's cells refined by the same criteria and solved by this solver: pd.refinement.on: Cells)",
                self.tolerance
            ));
        }
        if self.check_every != defaults.check_every {
            notes.push(format!(
                "pd.refinement.check_every = {} is not read: it spaces the checks of adaptive explicit dynamics; the quasi-static solves check the criteria at every equilibrium",
                self.check_every
            ));
        }
        notes
    }
}

/// A circle of particles to refine before the solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineCircle {
    /// Centre (x, y) (m).
    pub centre: (f64, f64),
    /// Radius (m), > 0.
    pub radius: f64,
    /// Deepest level inside the circle, 1 to `max_level`; default `max_level`. Nested
    /// circles with levels 1, 2, ... grade the spacing so that every size jump is a
    /// factor 2.
    #[serde(default)]
    pub level: Option<u8>,
}

/// How scene tractions enter stand-alone (and full-PD growth) PD models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum PdTraction {
    /// Body force in the node column next to the edge (seed 000 section 2.3).
    #[default]
    BodyForceLayer,
    /// Seed 001's traction transfer functions (Eqs. 12, 16, 17, 23): the traction
    /// is spread over the horizon with the weight q = 1 - r / (k delta).
    TransferFunction,
}

/// PD constitutive model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum PdModelKind {
    /// Bond-based prototype microelastic brittle model (seed 002 Eqs. 3-5): Poisson's
    /// ratio 1/3 (plane stress) or 1/4 (plane strain).
    #[default]
    Pmb,
    /// Ordinary state-based PD (seed 004 section 2.1) with `material.nu`.
    StateBased,
}

/// PD solver choice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum PdSolver {
    /// Adaptive dynamic relaxation (seed 002 Eqs. 9-15).
    Adr(AdrParams),
    /// Implicit Newton-Raphson (seed 000 section 2).
    Implicit(ImplicitParams),
    /// Implicit while no bond passes s_m, ADR while bonds fail (seed 000 section 4).
    Switching(SwitchingParams),
    /// Explicit dynamics from rest under the loads held from t = 0: velocity Verlet with
    /// bond breaking every step (seed 004 section 2.3, `pdbem_pd::dynamics`). Stand-alone
    /// PD only; needs `material.density`.
    Explicit(ExplicitParams),
}

fn default_dynamics_safety() -> f64 {
    0.8
}

/// Explicit dynamics parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitParams {
    /// Simulated time (s), > 0. Required.
    pub end_time: f64,
    /// Time step (s), > 0 and at most the stable step dt_c. Default `safety_factor * dt_c`.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Fraction of dt_c taken without `dt`, in (0, 1]. Default 0.8.
    #[serde(default = "default_dynamics_safety")]
    pub safety_factor: f64,
    /// Time between rows of `dynamics.csv` (s), > 0. Default `end_time / 200`.
    #[serde(default)]
    pub output_every: Option<f64>,
    /// Times (s) of the damage snapshots, in [0, end_time], at most 100. Default: none
    /// (the final state is always written).
    #[serde(default)]
    pub snapshots: Vec<f64>,
    /// Velocities given at t = 0 to the particles of boxes (an impact, seed 004 section
    /// 4.3), optionally held. Default: none (the body starts at rest).
    #[serde(default)]
    pub velocities: Vec<RegionVelocity>,
}

/// A velocity given at t = 0 to the particles whose reference positions lie in a box.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionVelocity {
    /// Lower-left corner (x, y) of the box (m).
    pub min: (f64, f64),
    /// Upper-right corner (x, y) of the box (m), above `min` in both coordinates.
    pub max: (f64, f64),
    /// Velocity (vx, vy) (m/s).
    pub velocity: (f64, f64),
    /// Keep the velocity for the whole run (a prescribed velocity: a rigid impactor).
    /// Default false (an initial velocity only).
    #[serde(default)]
    pub hold: bool,
}

impl Default for PdSolver {
    fn default() -> Self {
        PdSolver::Switching(SwitchingParams::default())
    }
}

/// ADR parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AdrParams {
    /// Convergence tolerance on the relative displacement change (seed 000 Eq. 16), > 0. Default 1e-9 (seed 000 e_0).
    pub tolerance: f64,
    /// Iteration cap per load step, >= 1. Default 100000.
    pub max_iter: usize,
    /// Safety factor on the fictitious density, >= 1. Default 1.
    pub safety_factor: f64,
}

impl Default for AdrParams {
    fn default() -> Self {
        AdrParams {
            tolerance: 1e-9,
            max_iter: 100_000,
            safety_factor: 1.0,
        }
    }
}

/// Implicit Newton-Raphson parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImplicitParams {
    /// Convergence tolerance (seed 000 Eq. 16), > 0. Default 1e-9 (seed 000 e_0).
    pub tolerance: f64,
    /// Newton iterations per load increment, >= 1. Default 50.
    pub max_iter: usize,
}

impl Default for ImplicitParams {
    fn default() -> Self {
        ImplicitParams {
            tolerance: 1e-9,
            max_iter: 50,
        }
    }
}

/// Explicit-implicit switching parameters (seed 000 section 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SwitchingParams {
    /// Convergence tolerance of both phases, > 0. Default 1e-9 (seed 000 e_0).
    pub tolerance: f64,
    /// Newton iterations per implicit increment, >= 1. Default 50.
    pub max_newton: usize,
    /// ADR iterations per explicit increment, >= 1. Default 100000.
    pub max_adr: usize,
    /// Loading steps of the implicit phase, >= 1. Default 3 (seed 000 section 5.2).
    pub implicit_steps: usize,
    /// Loading steps of the explicit phase, >= 1. Default 180 (seed 000 section 5.2).
    pub explicit_steps: usize,
}

impl Default for SwitchingParams {
    fn default() -> Self {
        SwitchingParams {
            tolerance: 1e-9,
            max_newton: 50,
            max_adr: 100_000,
            implicit_steps: 3,
            explicit_steps: 180,
        }
    }
}

/// Bond failure law.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Failure {
    /// Bonds never break.
    #[default]
    Elastic,
    /// PMB bonds break irreversibly at stretch s0 (-), > 0.
    CriticalStretch(f64),
    /// PMB with s0 from `material.fracture.g_c` (REFERENCES.md).
    FromGc,
    /// tanh degradation (seed 000 Eq. 12), 0 < s_m < s_c.
    Degradation {
        /// Stretch where degradation starts (-).
        s_m: f64,
        /// Stretch where the bond is fully broken (-).
        s_c: f64,
        /// Steepness (-), > 0. Seed 000 uses 3.
        beta: f64,
    },
}

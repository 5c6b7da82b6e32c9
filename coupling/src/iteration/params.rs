//! Parameters of Algorithm 1: the interface acceleration ([`Acceleration`]), the PD
//! solver of the windows ([`PdSolve`], [`StaggeredParams`]) and [`CouplingParams`].

use pdbem_pd::solvers::{adr, implicit, switching, Convergence};

use crate::maps::{DisplacementMap, TractionMap};
use crate::relaxation::{Aitken, Constant, IqnIls, Relaxation};

/// Interface acceleration scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Acceleration {
    /// Constant relaxation w in (0, 1] (seed 002 Eq. 25).
    Constant(f64),
    /// Aitken's dynamic relaxation from w0 (seed 002 Eqs. 25-28).
    Aitken(f64),
    /// IQN-ILS with first weight w0.
    IqnIls(f64),
}

impl Acceleration {
    /// The scheme with its weights scaled by `scale` (back-off).
    pub(super) fn build(&self, scale: f64) -> Box<dyn Relaxation> {
        match *self {
            Acceleration::Constant(w) => Box::new(Constant { w: w * scale }),
            Acceleration::Aitken(w) => {
                let mut a = Aitken::new(w * scale);
                a.w_max = scale.min(1.0);
                Box::new(a)
            }
            Acceleration::IqnIls(w) => Box::new(IqnIls::new(w * scale)),
        }
    }

    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            Acceleration::Constant(_) => "constant",
            Acceleration::Aitken(_) => "aitken",
            Acceleration::IqnIls(_) => "iqn-ils",
        }
    }
}

/// Which side of the interface takes which condition in Algorithm 1 (module docs of
/// [`crate::iteration`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ordering {
    /// PD takes the BEM displacements on its virtual layers (seed 002 Eq. 23), BEM the
    /// PD forces as tractions (Eq. 24); the unknown is the virtual-node displacement.
    #[default]
    DisplacementToPd,
    /// PD takes the BEM tractions through seed 001's transfer functions
    /// ([`crate::traction_window`]), BEM the PD displacement of the interface; the
    /// unknown is the interface traction. Static solves only (no bond breaking).
    TractionToPd,
}

/// PD solver of the windows.
#[derive(Debug, Clone, PartialEq)]
pub enum PdSolve {
    /// Explicit-implicit switching (implicit while undamaged), the engine's default.
    Switching(switching::SwitchingParams),
    /// Newton-Raphson.
    Implicit(implicit::ImplicitParams),
    /// Adaptive dynamic relaxation.
    Adr(adr::AdrParams),
    /// Crack growth: Newton equilibrium with the bond state frozen, then at most `rounds`
    /// break rounds (break every bond past its critical stretch, re-equilibrate). With
    /// `rounds = 0` bonds break only at converged interface states: once the residual is
    /// below psi, [`solve_prepared`](super::solve_prepared) commits every window's bond history and iterates on
    /// while bonds break. Either way the coupling iterations carry the growth, so a crack
    /// advances by about one break front at a time and the tip can be checked in between
    /// (Algorithm 2).
    Staggered(StaggeredParams),
}

/// Parameters of [`PdSolve::Staggered`].
#[derive(Debug, Clone, PartialEq)]
pub struct StaggeredParams {
    /// Newton settings of each equilibrium (`target_load` is the load factor).
    pub newton: implicit::ImplicitParams,
    /// Break rounds per PD solve; 0: break only at converged interface states.
    pub rounds: usize,
    /// At converged interface states, break only the bonds within this relative band of
    /// the largest stretch ([`pdbem_pd::breaking`]); 1 breaks every bond past its critical
    /// stretch.
    pub break_fraction: f64,
    /// Break-and-re-equilibrate rounds of the PD model (interface held) per converged
    /// interface state (>= 1).
    pub break_rounds: usize,
    // Measured on cases/growth_tension_edge.ron (mode I, K up to 30 K_c at the end):
    // break_fraction 0.05 puts the crack one lattice column off its line after 0.3 m
    // (path 1 dx off), 0.1 keeps it on the line within 0.05 m over 7 m, 0.2 and 0.3
    // let it wander by 0.25 m once K exceeds 10 K_c.
}

impl Default for StaggeredParams {
    /// Bonds break at converged interface states only, those within 10 % of the largest
    /// stretch at a time, in up to 10 rounds with the interface held (a crack advances
    /// by a few bonds per interface re-convergence); Newton to a relative residual of
    /// 1e-9.
    fn default() -> Self {
        StaggeredParams {
            newton: implicit::ImplicitParams {
                convergence: Convergence::Residual { tol: 1e-9 },
                residual_tol: 1e-9,
                ..Default::default()
            },
            rounds: 0,
            break_fraction: 0.1,
            break_rounds: 10,
        }
    }
}

impl Default for PdSolve {
    /// Switching with one implicit step from the warm start and a residual tolerance of
    /// 1e-9 (two Newton iterations at the small strains of the seed cases).
    fn default() -> Self {
        PdSolve::Switching(switching::SwitchingParams {
            target_load: 1.0,
            implicit_steps: 1,
            explicit_steps: 1,
            convergence: Convergence::Residual { tol: 1e-9 },
            ..Default::default()
        })
    }
}

/// Parameters of Algorithm 1.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingParams {
    /// Acceleration. Default Aitken from 0.3 (seed 002 section 3.1.3 uses w = 0.3).
    pub acceleration: Acceleration,
    /// Tolerance psi on the relative interface residual. Default 1e-4.
    pub psi: f64,
    /// Iteration cap. Default 50.
    pub max_iter: usize,
    /// BEM -> PD map. Default Copy (seed 002 Eq. 23, the scenes' default too).
    pub displacement_map: DisplacementMap,
    /// PD -> BEM map. Default bond crossing.
    pub traction_map: TractionMap,
    /// Consecutive growing residuals that count as divergence. Default 4.
    pub growth_window: usize,
    /// Iterations without 1 % improvement that count as stagnation. Default 25.
    pub stagnation_window: usize,
    /// Restarts with halved weights before giving up. Default 3.
    pub max_backoffs: usize,
    /// PD solver.
    pub pd_solve: PdSolve,
    /// Interface ordering. Default [`Ordering::DisplacementToPd`].
    pub ordering: Ordering,
    /// IQN-ILS keeps the secant columns of the maps before a bond break, and of the
    /// solve before ([`StepOptions::secants`](super::StepOptions::secants)), as reused
    /// columns ([`crate::relaxation::SecantColumns`]). Default true; false starts every
    /// map with an empty model (the cold start, for comparison).
    pub reuse_secants: bool,
}

impl Default for CouplingParams {
    fn default() -> Self {
        CouplingParams {
            acceleration: Acceleration::Aitken(0.3),
            psi: 1e-4,
            max_iter: 50,
            displacement_map: DisplacementMap::default(),
            traction_map: TractionMap::default(),
            growth_window: 4,
            stagnation_window: 25,
            max_backoffs: 3,
            pd_solve: PdSolve::default(),
            ordering: Ordering::default(),
            reuse_secants: true,
        }
    }
}

impl PdSolve {
    /// The solver with its target load set to the load scale.
    pub(super) fn at(&self, scale: f64) -> PdSolve {
        let mut s = self.clone();
        match &mut s {
            PdSolve::Switching(p) => p.target_load = scale,
            PdSolve::Implicit(p) => p.target_load = scale,
            PdSolve::Adr(p) => p.target_load = scale,
            PdSolve::Staggered(p) => p.newton.target_load = scale,
        }
        s
    }
}

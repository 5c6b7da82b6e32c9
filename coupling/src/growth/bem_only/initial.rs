//! The initial geometry of a BEM-only run: its critical loads, and the check `pdbem
//! check` makes before a run (the run's first solve, whose refusal would otherwise come
//! only at run time).

use super::body::fail;
use super::solve::{Checked, Engine, Sizes, Solved};
use super::BemOnlyBody;
use crate::error::CouplingError;
use crate::growth::front::Front;
use crate::growth::records::Scenario;

/// Critical load of one tip of the initial geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct TipCritical {
    /// Tip name.
    pub tip: String,
    /// K_I, K_II at load factor 1 (Pa sqrt(m)).
    pub k: [f64; 2],
    /// Kink angle (degrees).
    pub kink_deg: f64,
    /// Load factor at which K_eq reaches K_c (infinite when K_eq <= 0).
    pub load: f64,
}

/// Critical load factor of every tip of the initial geometry: K_c / K_eq at unit load.
pub fn critical_loads(
    body: &BemOnlyBody,
    front: &Front,
    k_c: f64,
    scenario: &dyn Scenario,
) -> Result<Vec<TipCritical>, CouplingError> {
    let mut engine = Engine::new(body, scenario);
    let sizes = engine.sizes(front, None)?;
    let solved = engine.solve(front, &sizes, false)?;
    Ok(solved
        .sifs
        .iter()
        .map(|s| TipCritical {
            tip: front.tips[s.tip].name.clone(),
            k: [s.k1, s.k2],
            kink_deg: s.theta.to_degrees(),
            load: critical_factor(k_c, s.k_eq),
        })
        .collect())
}

pub(super) fn critical_factor(k_c: f64, k_eq: f64) -> f64 {
    if k_eq > 0.0 {
        k_c / k_eq
    } else {
        f64::INFINITY
    }
}

/// Solves the initial geometry as the run's first geometry is solved (the same sizes for
/// the increment `da`, at unit load, K confirmed on tip elements refined 4x) and refuses
/// it as the run would: faces that overlap (K_I < 0 or CMOD < 0: the loads close the
/// crack) or a K that does not settle.
/// Returns what that solve cost, for the run's cost estimate.
pub fn check_initial(
    body: &BemOnlyBody,
    front: &Front,
    da: Option<f64>,
    scenario: &dyn Scenario,
) -> Result<InitialSolve, CouplingError> {
    let mut engine = Engine::new(body, scenario);
    let sizes = engine.sizes(front, da)?;
    let t0 = std::time::Instant::now();
    let solved = solve_geometry(&mut engine, front, &sizes, 0)?;
    let (lo, hi) = front.bounds();
    let da = sizes.smallest_da();
    Ok(InitialSolve {
        elements: solved.mesh.len(),
        seconds: t0.elapsed().as_secs_f64(),
        da,
        increments_across: (hi - lo).norm() / da * front.tips.len() as f64,
    })
}

/// The first geometry of a BEM-only run as [`check_initial`] solved it.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialSolve {
    /// Elements of its mesh.
    pub elements: usize,
    /// Wall time of its solve (every geometry of the run is solved alike) (s).
    pub seconds: f64,
    /// The smallest increment (m).
    pub da: f64,
    /// Increments for every tip to cross the body's bounding-box diagonal once.
    pub increments_across: f64,
}

/// Solves geometry number `geometry` of a run (the initial one without the growth checks
/// of later ones) and refuses faces that overlap or a K that does not settle: the run's
/// solve of every geometry, and [`check_initial`]'s.
pub(super) fn solve_geometry(
    engine: &mut Engine<'_>,
    front: &Front,
    sizes: &Sizes,
    geometry: usize,
) -> Result<Solved, CouplingError> {
    let checked = engine
        .solve_checked(front, sizes, geometry > 0)
        .map_err(|e| fail(format!("geometry {geometry}: {e}")))?;
    match checked {
        Checked::Ok(s) => Ok(*s),
        Checked::Overlap(why) => Err(fail(format!(
            "geometry {geometry}: {why}: the crack faces overlap in the linear solution, which \
             has no contact (is the load opening the crack?)"
        ))),
        Checked::Unsettled(why) => Err(fail(format!("geometry {geometry}: {why}"))),
    }
}

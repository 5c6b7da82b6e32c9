//! The adaptive driver: refine before the solve (static regions, Eq. 15 on the
//! pre-cracks), solve, and split-and-solve while Eq. 15 or Eq. 16 fires.

use std::time::Instant;

use rayon::prelude::*;

use super::pass::Measures;
use super::{linear, Body, Refinement};
use crate::error::PdError;
use crate::geometry::P2;
use crate::problem::PdProblem;

/// Conjugate-gradient iteration cap per solve.
const MAX_CG: usize = 200_000;

/// One split-and-solve round.
#[derive(Clone, Debug, PartialEq)]
pub struct Round {
    /// Particles split before this round's solve.
    pub split: usize,
    /// Particles after the split.
    pub particles: usize,
    /// Conjugate-gradient iterations of the solve.
    pub iterations: usize,
    /// Wall time of the split (s).
    pub split_s: f64,
    /// Wall time of the solve (s).
    pub solve_s: f64,
}

/// The refined body at equilibrium and the record of its rounds.
#[derive(Clone, Debug)]
pub struct RefinedRun {
    /// The body at the load factor of the run.
    pub body: Body,
    /// Round 0 (set-up refinement and the first solve), then the adaptive rounds.
    pub rounds: Vec<Round>,
}

/// How far past `phi_c` a damage must be to pass Eq. 15. A damage is a ratio of lattice
/// volumes, so it can equal `phi_c` exactly: after the first set-up split of the
/// Kalthoff-Winkler plate four particles by its pre-cracks have damage 0.4 to within
/// 4.4e-16, on either side of it as the order of the sums falls. A tie is not past
/// `phi_c`, and this margin makes it so whatever the round-off.
pub const DAMAGE_TIE: f64 = 1e-12;

/// The particles the criteria select: level below `max_level` and in a static region
/// below the region's level (`with_regions`), damaged beyond `phi_c` (Eq. 15, by more than
/// [`DAMAGE_TIE`]) or strained beyond `alpha s_c` (Eq. 16, `with_strain`). Each particle
/// is tested on its own, cheapest test first (a particle at `max_level` costs nothing).
pub fn flagged(body: &Body, r: &Refinement, with_regions: bool, with_strain: bool) -> Vec<usize> {
    select(
        body,
        r,
        with_regions,
        with_strain,
        |k| body.damage_of(k),
        |_| true,
        |k| body.accumulated_strain_of(k),
    )
}

/// [`flagged`] without static regions and with Eq. 16, from the damage and strains a
/// force pass measured at the body's state ([`super::pass::forces_measuring_into`]);
/// Eq. 15 fires only for the particles `grown` accepts (a dynamic run: those with a bond
/// broken by the run, [`super::dynamics::broke_in_run`]).
pub fn flagged_measured(
    body: &Body,
    r: &Refinement,
    m: &Measures,
    grown: impl Fn(usize) -> bool + Sync,
) -> Vec<usize> {
    select(
        body,
        r,
        false,
        true,
        |k| m.damage[k],
        grown,
        |k| m.strain[k],
    )
}

/// [`flagged`] with the damage and accumulated strain of each particle from `damage` and
/// `strain`; Eq. 15 also asks `grown` of a particle past `phi_c` (tested last: it is the
/// dearest).
fn select(
    body: &Body,
    r: &Refinement,
    with_regions: bool,
    with_strain: bool,
    damage: impl Fn(usize) -> f64 + Sync,
    grown: impl Fn(usize) -> bool + Sync,
    strain: impl Fn(usize) -> P2 + Sync,
) -> Vec<usize> {
    let delta_ref = body.dh.delta.iter().fold(0.0f64, |a, &b| a.max(b));
    let factor = if with_strain { r.strain_factor } else { None };
    let selected = |k: usize| {
        if body.level[k] >= r.max_level {
            return false;
        }
        let x = body.dh.pos[k];
        let region = with_regions
            && r.regions
                .iter()
                .enumerate()
                .any(|(i, s)| body.level[k] < r.region_level(i) && s.contains(x, delta_ref));
        region
            || r.critical_damage
                .is_some_and(|c| damage(k) > c + DAMAGE_TIE && grown(k))
            || match (factor, body.critical_stretch(k)) {
                (Some(a), Some(sc)) => {
                    let e = strain(k);
                    e[0].min(e[1]) > a * sc
                }
                _ => false,
            }
    };
    (0..body.len())
        .into_par_iter()
        .filter(|&k| selected(k))
        .collect()
}

/// The set-up refinement of every driver ([`run`], [`super::ramp`], [`super::run_dynamic`]):
/// the static regions of `r` and Eq. 15 on the pre-cracks, level by level until nothing
/// fires (each split changes its neighbours' damage). Returns the particles split; a
/// split over the memory budget is refused before it allocates ([`Body::budget`]), and so
/// is a start body the criteria could not split ([`room_to_split`]).
pub fn set_up(body: &mut Body, r: &Refinement) -> Result<usize, PdError> {
    let split = split_until_settled(body, r)?;
    room_to_split(body, r)?;
    Ok(split)
}

/// The set-up of a dynamic run ([`super::run_dynamic`]): the static regions of `r` only,
/// level by level; Eq. 15 fires during the run, where bonds break. Refused as [`set_up`].
pub fn set_up_static(body: &mut Body, r: &Refinement) -> Result<usize, PdError> {
    let regions_only = Refinement {
        critical_damage: None,
        strain_factor: None,
        ..r.clone()
    };
    let split = split_until_settled(body, &regions_only)?;
    room_to_split(body, r)?;
    Ok(split)
}

/// Split what `r`'s static regions and Eq. 15 flag until nothing fires.
fn split_until_settled(body: &mut Body, r: &Refinement) -> Result<usize, PdError> {
    let mut split = 0;
    loop {
        let f = flagged(body, r, true, false);
        if f.is_empty() {
            return Ok(split);
        }
        split += body.split(&f)?;
    }
}

/// A split builds the refined body beside the one it splits ([`Body::split`]), so when
/// `r`'s criteria may fire after the set-up, the body must fit the memory budget twice
/// over: [`PdError::TooLarge`] otherwise, before the solve or the first step, instead of
/// at the first split of a run.
pub fn room_to_split(body: &Body, r: &Refinement) -> Result<(), PdError> {
    if r.critical_damage.is_none() && r.strain_factor.is_none() {
        return Ok(());
    }
    let one =
        body.len() as f64 * super::PARTICLE_BYTES + body.dh.bonds.len() as f64 * super::BOND_BYTES;
    crate::tangent::check_budget(
        &format!(
            "pd.refinement: a split during the run builds the refined body beside the body it splits ({} particles and {} directed bonds at the start), so the first split",
            body.len(),
            body.dh.bonds.len()
        ),
        2.0 * one,
        body.budget.unwrap_or_else(crate::tangent::factor_budget),
    )
}

/// Solve `p` with adaptive refinement `r` at load factor `load`. A displacement
/// condition's fictitious layer joins the body ([`Body::from_problem`]) and holds `load`
/// times its values.
pub fn run(p: &PdProblem, r: &Refinement, load: f64) -> Result<RefinedRun, PdError> {
    if !load.is_finite() {
        return Err(PdError::invalid(
            "load",
            format!("must be finite, got {load}"),
        ));
    }
    r.validate()?;
    let mut body = Body::from_problem(p)?;
    body.keep_horizon = r.keep_horizon;
    if r.strain_factor.is_some() && body.critical_stretch(0).is_none() {
        return Err(PdError::invalid(
            "refinement.strain_factor",
            "the accumulated-strain criterion (Eq. 16) needs a failure law with a critical stretch",
        ));
    }
    // Set-up: static regions and Eq. 15 on the pre-cracks, level by level.
    let t = Instant::now();
    let split = set_up(&mut body, r)?;
    let split_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let iterations = linear::solve(&mut body, load, r.tolerance, MAX_CG)?;
    let mut rounds = vec![Round {
        split,
        particles: body.len(),
        iterations,
        split_s,
        solve_s: t.elapsed().as_secs_f64(),
    }];
    for _ in 0..r.max_rounds {
        let t = Instant::now();
        let f = flagged(&body, r, false, true);
        if f.is_empty() {
            break;
        }
        let split = body.split(&f)?;
        let split_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let iterations = linear::solve(&mut body, load, r.tolerance, MAX_CG)?;
        rounds.push(Round {
            split,
            particles: body.len(),
            iterations,
            split_s,
            solve_s: t.elapsed().as_secs_f64(),
        });
    }
    Ok(RefinedRun { body, rounds })
}

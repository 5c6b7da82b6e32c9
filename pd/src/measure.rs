//! Measurements on the damage field: crack extension from a pre-crack tip,
//! the load at crack initiation, and the kink angle.
//!
//! Damage $\varphi > 0.38$ marks the macro crack (seed 002 section 2.1).
//! The extension from a tip $T$ with outward direction $d$ is the largest
//! distance $|x - T|$ of a macro-cracked real node ahead of the tip
//! ($(x - T)\cdot d > 0$). The initiation load is the first load step at
//! which the extension grows by more than `run_length` beyond its value at
//! the start (the crack runs, seed 001 section 6.1). The kink angle is the
//! direction of the damaged nodes in an annulus `r_min..r_max` around the
//! tip (volume-weighted mean of unit vectors), measured from `d`.

use serde::Serialize;

use crate::damage::MACRO_CRACK_DAMAGE;
use crate::error::PdError;
use crate::geometry::P2;
use crate::model::PdModel;
use crate::solvers::implicit::{ImplicitParams, Newton};
use crate::solvers::limit::RampEvent;
use crate::solvers::SolveInfo;

/// A pre-crack tip and its outward unit direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tip {
    /// Tip position (m).
    pub at: P2,
    /// Outward unit direction of the crack at the tip.
    pub dir: P2,
}

/// Both tips of an open polyline crack (interior tips are skipped when
/// `edge_start` says the first point lies on the outer boundary).
pub fn crack_tips(line: &[P2], edge_start: bool) -> Vec<Tip> {
    let n = line.len();
    let unit = |a: P2, b: P2| {
        let (x, y) = (b[0] - a[0], b[1] - a[1]);
        let l = x.hypot(y);
        [x / l, y / l]
    };
    let mut tips = vec![Tip {
        at: line[n - 1],
        dir: unit(line[n - 2], line[n - 1]),
    }];
    if !edge_start {
        tips.push(Tip {
            at: line[0],
            dir: unit(line[1], line[0]),
        });
    }
    tips
}

/// Largest extension (m) of the macro crack ahead of any of the tips. Each
/// macro-cracked node counts for its nearest tip only: with several cracks,
/// a node growing ahead of one crack would otherwise count, at the full
/// distance between the cracks, for the tips of the others (two parallel
/// cracks 25 mm apart "ran" at the first broken row).
pub fn crack_extension(model: &PdModel, tips: &[Tip]) -> f64 {
    let n = model.n_real();
    crack_extension_of(&model.positions()[..n], &model.damage()[..n], tips)
}

/// [`crack_extension`] of the particles at `x` with damage `phi` (any particle set, e.g.
/// a refined body's).
pub fn crack_extension_of(x: &[P2], phi: &[f64], tips: &[Tip]) -> f64 {
    let mut ext: f64 = 0.0;
    for (xi, &p) in x.iter().zip(phi) {
        if p <= MACRO_CRACK_DAMAGE {
            continue;
        }
        let nearest = tips
            .iter()
            .map(|t| (t, (xi[0] - t.at[0]).hypot(xi[1] - t.at[1])))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((t, d)) = nearest {
            let r = [xi[0] - t.at[0], xi[1] - t.at[1]];
            if r[0] * t.dir[0] + r[1] * t.dir[1] > 0.0 {
                ext = ext.max(d);
            }
        }
    }
    ext
}

/// Kink angle (degrees, counter-clockwise positive) of the damage in the
/// annulus `r_min..r_max` around `tip`, measured from the tip direction.
/// `None` when no macro-cracked node lies there.
/// On a mixed grid each node weighs its volume over a coarse node's, so the fine cells'
/// four nodes per coarse cell do not outvote the coarse ones (1 on a uniform grid).
pub fn kink_angle(model: &PdModel, tip: Tip, r_min: f64, r_max: f64) -> Option<f64> {
    let n = model.n_real();
    let g = model.grid();
    let w: Vec<f64> = (0..n).map(|k| (g.node_dx(k) / g.dx).powi(2)).collect();
    kink_angle_weighted(
        &model.positions()[..n],
        &model.damage()[..n],
        &w,
        tip,
        r_min,
        r_max,
    )
}

/// [`kink_angle`] of the particles at `x` with damage `phi` and weights `w` (their
/// volumes, or any multiple of them).
pub fn kink_angle_weighted(
    x: &[P2],
    phi: &[f64],
    w: &[f64],
    tip: Tip,
    r_min: f64,
    r_max: f64,
) -> Option<f64> {
    let (mut sx, mut sy) = (0.0, 0.0);
    for ((xi, &p), &wi) in x.iter().zip(phi).zip(w) {
        if p <= MACRO_CRACK_DAMAGE {
            continue;
        }
        let r = [xi[0] - tip.at[0], xi[1] - tip.at[1]];
        let d = r[0].hypot(r[1]);
        if d < r_min || d > r_max || r[0] * tip.dir[0] + r[1] * tip.dir[1] <= 0.0 {
            continue;
        }
        sx += wi * r[0] / d;
        sy += wi * r[1] / d;
    }
    if sx == 0.0 && sy == 0.0 {
        return None;
    }
    let a = sy.atan2(sx) - tip.dir[1].atan2(tip.dir[0]);
    let a =
        (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    Some(a.to_degrees())
}

/// Maximum-circumferential-stress kink angle (degrees) for the ratio
/// `K_II / K_I`: $\theta = 2\arctan[(1 - \sqrt{1 + 8 r^2})/(4 r)]$.
pub fn mts_kink_deg(k2_over_k1: f64) -> f64 {
    if k2_over_k1 == 0.0 {
        return 0.0;
    }
    let r = k2_over_k1;
    (2.0 * ((1.0 - (1.0 + 8.0 * r * r).sqrt()) / (4.0 * r)).atan()).to_degrees()
}

/// Parameters of [`ramp_to_initiation`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RampParams {
    /// First load factor tried.
    pub start: f64,
    /// Load increment.
    pub step: f64,
    /// Give up beyond this load factor.
    pub max_load: f64,
    /// Extension beyond the start value that counts as a running crack (m).
    pub run_length: f64,
    /// Keep breaking at the initiation load until the extension reaches
    /// this length (m), for a kink measurement; 0 stops at initiation.
    pub grow_to: f64,
    /// Cap on break-and-re-solve rounds per load step (a split before the bonds
    /// break, [`SplitStage::BeforeBreaking`], is not a round).
    pub max_rounds: usize,
}

/// Result of [`ramp_to_initiation`].
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Initiation {
    /// Load factor at which the first bond broke.
    pub first_break_load: Option<f64>,
    /// Load factor at which the crack ran (extension past `run_length`).
    pub initiation_load: Option<f64>,
    /// Crack extension at the end (m).
    pub extension: f64,
    /// The equilibrium was lost while bonds broke at the initiation load
    /// (unstable growth under load control, e.g. the plate parted): the
    /// ramp stopped there.
    pub unstable: bool,
    /// Loads whose `max_rounds` ran out with bonds still breaking (or, with a
    /// refinement hook, a split not yet solved): the ramp went on from a state
    /// that was not an equilibrium there.
    pub unsettled_loads: Vec<f64>,
    /// Solver record (one step per equilibrium).
    pub info: SolveInfo,
}

/// Ramp the load with implicit equilibria and brittle breaking (seed 000
/// section 2 with the PMB law of seed 002 Eq. 6): at each load, solve,
/// break every bond past `s0`, and re-solve until no bond breaks. The first
/// load at which the crack extension grows by `run_length` is the
/// initiation load. The model keeps its final state (for damage plots and
/// [`kink_angle`]).
pub fn ramp_to_initiation(
    model: &mut PdModel,
    tips: &[Tip],
    p: &RampParams,
) -> Result<Initiation, PdError> {
    ramp_to_initiation_observed(model, tips, p, &mut |_| {})
}

/// [`ramp_to_initiation`], telling `observe` the load factor of every load step it has
/// settled ([`RampEvent::Converged`]).
pub fn ramp_to_initiation_observed(
    model: &mut PdModel,
    tips: &[Tip],
    p: &RampParams,
    observe: &mut dyn FnMut(&RampEvent),
) -> Result<Initiation, PdError> {
    ramp_to_initiation_with(model, tips, p, &mut |_, _, _| Ok(false), observe)
}

/// When the hook of [`ramp_to_initiation_with`] is asked for a split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplitStage {
    /// After an equilibrium, before its overstretched bonds break.
    BeforeBreaking,
    /// After the bonds broke (and the crack extension was measured).
    AfterBreaking,
}

/// [`ramp_to_initiation`] with a refinement hook: after every equilibrium, before and
/// after its bond breaking, `split(model, load, stage)` may replace the model by a
/// refined one (it returns `true` then), and the same load is solved again on it (seed
/// 004's per-step steps 3-5, [`crate::adapt`]; a split before the breaking leaves the
/// bonds unbroken). The rounds of a load end when no bond breaks and nothing splits, or
/// after `max_rounds` (the load is then listed in
/// [`Initiation::unsettled_loads`]); `observe` hears the load of every step so ended.
pub fn ramp_to_initiation_with(
    model: &mut PdModel,
    tips: &[Tip],
    p: &RampParams,
    split: &mut dyn FnMut(&mut PdModel, f64, SplitStage) -> Result<bool, PdError>,
    observe: &mut dyn FnMut(&RampEvent),
) -> Result<Initiation, PdError> {
    let mut out = Initiation::default();
    let mut newton = Newton::new(model)?;
    // Loose tolerances: one factorisation per break round is enough here.
    let ip = ImplicitParams {
        residual_tol: 1e-6,
        convergence: crate::solvers::Convergence::Displacement { e0: 1e-6 },
        ..Default::default()
    };
    let ext0 = crack_extension(model, tips);
    // Predict the first-break load from one elastic solve at load 1 (the
    // response is linear up to geometric terms of order the strain).
    let saved = model.state();
    model.set_load_factor(1.0);
    newton.equilibrate(model, &ip, &mut out.info)?;
    let s1 = model.stretch_stats().max_stretch;
    let onset = model.law().damage_onset();
    model.restore(&saved);
    let mut lam = p.start;
    if s1 > 0.0 && onset.is_finite() {
        let fb = onset / s1;
        if fb > lam {
            lam += ((fb - lam) / p.step).floor() * p.step;
        }
    }
    while lam <= p.max_load * (1.0 + 1e-12) {
        model.set_load_factor(lam);
        let mut settled = false;
        let mut rounds = 0;
        while rounds < p.max_rounds {
            let it = match newton.equilibrate(model, &ip, &mut out.info) {
                Ok((it, _)) => it,
                // After bonds have broken, a lost equilibrium under load control is
                // unstable growth: the crack ran at this load.
                Err(_) if out.first_break_load.is_some() => {
                    out.unstable = true;
                    out.initiation_load.get_or_insert(lam);
                    settled = true;
                    break;
                }
                Err(e) => return Err(e),
            };
            out.info.iterations += it;
            // Not a round: every split deepens a cell, and the levels are bounded.
            if split(model, lam, SplitStage::BeforeBreaking)? {
                newton = Newton::new(model)?;
                continue;
            }
            rounds += 1;
            let st = model.commit_history();
            if st.newly_broken > 0 && out.first_break_load.is_none() {
                out.first_break_load = Some(lam);
            }
            let ext = crack_extension(model, tips);
            out.extension = ext;
            if ext - ext0 > p.run_length && out.initiation_load.is_none() {
                out.initiation_load = Some(lam);
            }
            if out.initiation_load.is_some() && ext - ext0 >= p.grow_to {
                settled = true;
                break;
            }
            if split(model, lam, SplitStage::AfterBreaking)? {
                newton = Newton::new(model)?;
            } else if st.newly_broken == 0 {
                settled = true;
                break;
            }
        }
        if !settled {
            out.unsettled_loads.push(lam);
        }
        out.info.steps.push(crate::solvers::StepRecord {
            load: lam,
            iterations: out.info.iterations,
            broken_bonds: model.broken_bonds(),
            max_stretch: model.stretch_stats().max_stretch,
            measure: 0.0,
            kind: crate::solvers::PhaseKind::Implicit,
            resultants: model.bc_resultants(),
        });
        observe(&RampEvent::Converged { load: lam });
        if out.initiation_load.is_some() {
            break;
        }
        lam += p.step;
    }
    out.info.final_load = lam.min(p.max_load);
    out.info.bonds_broken = model.broken_bonds();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mts_angle_for_45_degree_crack_is_53_13() {
        // Inclined crack at 45 degrees under uniaxial tension: K_II/K_I = 1.
        assert!((mts_kink_deg(1.0) + 53.13).abs() < 0.01);
    }

    /// A coarse node 30 degrees below the tip direction and the four children of a split
    /// cell 30 degrees above it: by volume (a child a quarter of a coarse node) the two
    /// sides balance at 0 degrees; counted once each the children pull the mean to about
    /// 19.1 degrees.
    #[test]
    fn the_kink_weighs_nodes_by_volume() {
        let tip = Tip {
            at: [0.0, 0.0],
            dir: [1.0, 0.0],
        };
        let at = |deg: f64, r: f64| {
            let a = deg.to_radians();
            [r * a.cos(), r * a.sin()]
        };
        let x = vec![
            at(-30.0, 2.0),
            at(30.0, 1.9),
            at(30.0, 2.0),
            at(30.0, 2.1),
            at(30.0, 2.2),
        ];
        let phi = vec![0.5; 5];
        let w = [1.0, 0.25, 0.25, 0.25, 0.25];
        let by_volume = kink_angle_weighted(&x, &phi, &w, tip, 1.0, 3.0).unwrap();
        assert!(by_volume.abs() < 1e-12, "{by_volume}");
        let counted = kink_angle_weighted(&x, &phi, &[1.0; 5], tip, 1.0, 3.0).unwrap();
        assert!((counted - 19.1).abs() < 0.1, "{counted}");
    }
}

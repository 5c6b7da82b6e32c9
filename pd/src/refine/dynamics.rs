//! Explicit dynamics of a refined dual-horizon body with bond breaking and adaptive
//! splitting during the run (seed 004 Fig. 5, steps 3-5 in every check interval; Eq. 30).
//!
//! **Motion.** Particle $k$ has mass $\rho V_k$ and moves by velocity Verlet (seed 004
//! Eqs. 24-27, as [`crate::dynamics`]) under the dual-horizon force $F_k$ (N, seed 004
//! Eq. 13, [`crate::state_based::dual_horizon::DualHorizon::forces`]) and its load $\lambda b_k V_k$ ($b_k$ the body-force
//! density at load factor 1): $\rho V_k\,\ddot u_k = F_k(u) + \lambda b_k V_k$. Prescribed
//! components keep $\lambda\bar u$ and zero velocity: $u_{k,c}(t) = \lambda\bar u_{k,c}$,
//! $\dot u_{k,c} = \ddot u_{k,c} = 0$ every step, as the uniform grid holds its
//! fictitious layer ([`crate::dynamics`]; seed 000 section 2.3). A displacement condition's
//! fictitious layer is part of the body ([`Body::from_problem`]): its particles bond with
//! the real ones, hold their prescribed components, may split like any particle, and
//! their children hold their parent's prescription ([`Body::split`]). A held component
//! does no work ($\dot u = 0$), so the balance $W = K + U + D$ needs no reaction term.
//!
//! Region velocities ([`crate::dynamics::RegionVelocity`]) start, and with `hold` keep,
//! the particles of a region at a velocity as in [`crate::dynamics`]; children inherit
//! their parent's held components, and the work of the holding constraints joins the
//! work of the loads.
//!
//! **Bond breaking.** Every step, after the position update, the bond $b = k\to j$ of
//! owner $k$ breaks for good when its stretch passes the critical stretch of its owner,
//! $s_b > s_c(\delta_k)$ ([`Body::critical_stretch`]: seed 004 Eq. 11 from $G_c$ with the
//! owner's horizon, so a bond between sizes takes its owner's value and the two directed
//! bonds of a mixed pair may break at different stretches). The particle constants stay
//! as calibrated; a broken bond drops out of the dilatation and the force.
//!
//! **Refinement** every `check_every` steps (at a full step, after the velocity update):
//! the particles the adaptive driver's criteria select (Eq. 15, $\varphi_k > \varphi_c$, and Eq. 16
//! when [`Refinement::strain_factor`] is set; level below [`Refinement::max_level`]) split
//! by [`Body::split`] (Eq. 18 placement, Eq. 30 masses $\rho V_k/4$). The damage and
//! strains the criteria read are measured by the check step's own force pass
//! ([`forces_measuring_into`], the numbers of [`Body::damage_of`] and
//! [`Body::accumulated_strain_of`] to the last bit), so a check costs no pass of its own;
//! a run without Eqs. 15-16 makes no checks. Every child takes
//! its parent's velocity, so mass and momentum are conserved exactly. The accelerations are
//! recomputed at the new state, and a bond of the refined body already past its owner's
//! critical stretch starts broken: a bond between particles whose ancestors were not
//! bonded (a kept particle and a child its horizon now reaches) starts intact
//! ([`Body::split`]) and may span a crack that opened during the run. A split changes $K + U - W$ (the
//! children's displacements follow Eq. 18, changed families' constants are recalibrated); the jump is
//! summed apart so that the recorded fracture energy (the energy balance's dissipation,
//! [`crate::dynamics`]) counts broken bonds only.
//!
//! **The crack the run grows, not the pre-crack.** Eq. 15 reads the damage of Eq. 14,
//! which counts the bonds a pre-crack cuts, but a particle passes it in a run only once a
//! bond of its horizon or dual horizon has broken during the run ([`broke_in_run`]), and
//! the set-up splits the static regions only ([`super::run::set_up_static`]). So the
//! refinement follows the crack the run grows, as seed 004's Tables 5-6 count it (4000
//! particles at the start of both branching cases: the seed's set-up split nothing). A
//! pre-crack's rows sit at damage 11/28 = 0.393, its mouth at 0.41 and, after a
//! neighbour's split, at 0.403-0.406: counted, they split the pre-crack at set-up (66
//! particles on the branching plate, 6 % more bonds for the whole run) and moved the
//! pattern away from the fine grid's: case 1's branches left the right edge at y = 9.7 /
//! 30.3 mm, the fine grid's at 3.9 / 36.1 mm and the coarse grid's at 7.0 / 33.0 mm; with
//! this rule at 4.7 / 35.3 mm, and at 1.4-2.9 mm from the fine grid's when checked every
//! 1-20 steps instead of 10 (`docs/seed004.md`, test
//! `verification_seed004_branching_pattern`). A scene that wants the pre-crack refined
//! says so with a static region.
//!
//! **Stable step.** The Gershgorin bound of [`crate::dynamics`] on the dual-horizon
//! linearised stiffness ([`critical_time_step`]): $\Delta t_c = \min_k\sqrt{4\rho V_k/R_k}$
//! over the particles with a free component. A uniform grid's bound scales with its
//! spacing at a fixed horizon factor, so the run's bound is the start body's divided by
//! $2^{L}$, $L$ the levels the run may still add (the smallest particles it can make);
//! a `dt` above it is refused before a step is taken, and after every split the actual
//! bound is checked again (a `dt` above it ends the run with an error). Children keep
//! the horizon factor (`keep_horizon` is refused here).

use std::time::Instant;

use rayon::prelude::*;

pub use super::pass::{
    critical_time_step, forces_breaking, forces_breaking_into, forces_measuring_into, Measures,
    PassBuffers,
};
use super::run::flagged_measured;
use super::{Body, Refinement};
use crate::dynamics::crack::CrackTracker;
use crate::dynamics::{region_velocities, DynamicRecord, DynamicsInfo, ExplicitParams};
use crate::error::PdError;
use crate::geometry::{segment_crosses_crack, P2};
use crate::problem::PdProblem;

/// One refinement during a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SplitEvent {
    /// Step after which the particles split.
    pub step: usize,
    /// Time (s).
    pub time: f64,
    /// Particles split.
    pub split: usize,
    /// Particles after the split.
    pub particles: usize,
    /// Stable step bound of the refined body (s).
    pub dt_c: f64,
    /// Wall time of the criterion check, the split and the new accelerations (s).
    pub wall_s: f64,
}

/// Receives the records, splits and snapshots of an adaptive run (never prints).
pub trait AdaptiveObserver {
    /// A record, every output interval and at the last step.
    fn record(&mut self, _r: &DynamicRecord) {}
    /// A refinement.
    fn split(&mut self, _e: &SplitEvent) {}
    /// The body at the step nearest a requested snapshot time `time` (s).
    fn snapshot(&mut self, _time: f64, _body: &Body) {}
}

impl AdaptiveObserver for () {}

/// Collects the records and the splits.
impl AdaptiveObserver for (Vec<DynamicRecord>, Vec<SplitEvent>) {
    fn record(&mut self, r: &DynamicRecord) {
        self.0.push(*r);
    }
    fn split(&mut self, e: &SplitEvent) {
        self.1.push(*e);
    }
}

/// What an adaptive run did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AdaptiveInfo {
    /// The run as the uniform dynamics reports it.
    pub dynamics: DynamicsInfo,
    /// Particles at the first step (after the set-up refinement) and the most during
    /// the run.
    pub particles: (usize, usize),
    /// Directed bonds at the first step.
    pub bonds: usize,
    /// Refinements (split events).
    pub refinements: usize,
    /// Wall time of the criterion checks and splits (s); the measuring of the criteria's
    /// inputs is part of the check steps' force passes, counted in the stepping.
    pub refine_s: f64,
}

/// The moving state of a body: velocities, accelerations and the per-body caches.
struct State {
    v: Vec<P2>,
    a: Vec<P2>,
    /// Components whose velocity is held ([`crate::dynamics::RegionVelocity::hold`]).
    held: Vec<[bool; 2]>,
    /// Work of the constraints holding them since t = 0 (J).
    held_work: f64,
    /// Forces (N) at the current state.
    f: Vec<P2>,
    /// The force pass's buffers.
    buf: PassBuffers,
    /// The criteria's inputs of the last measuring pass ([`Self::step`]).
    measures: Measures,
    sc: Option<Vec<f64>>,
    rho: f64,
    load: f64,
}

impl State {
    fn critical_stretches(body: &Body) -> Option<Vec<f64>> {
        (0..body.len())
            .map(|k| body.critical_stretch(k))
            .collect::<Option<Vec<f64>>>()
    }

    /// Forces at `body.u` into `self.f` after breaking (`breaking`) the bonds past their
    /// owners' critical stretches, and the criteria's inputs into `self.measures` when
    /// `measure`; returns the directed bonds broken.
    fn update_forces(&mut self, body: &mut Body, breaking: bool, measure: bool) -> usize {
        let sc = if breaking { self.sc.as_deref() } else { None };
        let (dh, u, buf, f) = (&mut body.dh, &body.u, &mut self.buf, &mut self.f);
        if measure {
            forces_measuring_into(dh, u, sc, buf, f, &mut self.measures)
        } else {
            forces_breaking_into(dh, u, sc, buf, f)
        }
    }

    /// Accelerations at the forces `self.f`.
    fn accelerate(&mut self, body: &Body) {
        let f = &self.f;
        for (k, a) in self.a.iter_mut().enumerate() {
            let m = self.rho * body.dh.volume[k];
            for c in 0..2 {
                a[c] = if body.fixed[k][c] || self.held[k][c] {
                    0.0
                } else {
                    (f[k][c] + self.load * body.body[k][c] * body.dh.volume[k]) / m
                };
            }
        }
    }

    fn half_kick(&mut self, dt: f64) {
        for (v, a) in self.v.iter_mut().zip(&self.a) {
            v[0] += 0.5 * dt * a[0];
            v[1] += 0.5 * dt * a[1];
        }
    }

    /// One velocity-Verlet step with bond breaking, measuring the criteria's inputs at
    /// its end when `measure`; returns the directed bonds broken.
    fn step(&mut self, body: &mut Body, dt: f64, measure: bool) -> usize {
        let p0 = self.held_power(body, &self.f);
        self.half_kick(dt);
        for (u, v) in body.u.iter_mut().zip(&self.v) {
            u[0] += dt * v[0];
            u[1] += dt * v[1];
        }
        let broken = self.update_forces(body, true, measure);
        self.accelerate(body);
        self.half_kick(dt);
        self.held_work += 0.5 * dt * (p0 + self.held_power(body, &self.f));
        broken
    }

    /// Power (W) of the constraint forces holding the held components at forces `f`.
    fn held_power(&self, body: &Body, f: &[P2]) -> f64 {
        let mut p = 0.0;
        for (k, h) in self.held.iter().enumerate() {
            for c in 0..2 {
                if h[c] {
                    let load = self.load * body.body[k][c] * body.dh.volume[k];
                    p -= (f[k][c] + load) * self.v[k][c];
                }
            }
        }
        p
    }

    fn kinetic(&self, body: &Body) -> f64 {
        0.5 * self.rho
            * self
                .v
                .iter()
                .zip(&body.dh.volume)
                .map(|(v, m)| m * (v[0] * v[0] + v[1] * v[1]))
                .sum::<f64>()
    }

    /// Split `parents` (sorted, unique): children take their parent's velocity.
    fn split(&mut self, body: &mut Body, parents: &[usize]) -> Result<usize, PdError> {
        let mut is_parent = vec![false; body.len()];
        for &k in parents {
            is_parent[k] = true;
        }
        // As `Body::split` orders them: a parent's four children in its place.
        let mut v: Vec<P2> = Vec::with_capacity(body.len() + 3 * parents.len());
        let mut held: Vec<[bool; 2]> = Vec::with_capacity(v.capacity());
        for k in 0..body.len() {
            let copies = if is_parent[k] { 4 } else { 1 };
            v.extend(std::iter::repeat_n(self.v[k], copies));
            held.extend(std::iter::repeat_n(self.held[k], copies));
        }
        let split = body.split(parents)?;
        for (u, (f, b)) in body.u.iter_mut().zip(body.fixed.iter().zip(&body.base)) {
            for c in 0..2 {
                if f[c] {
                    u[c] = self.load * b[c];
                }
            }
        }
        self.v = v;
        self.held = held;
        self.a = vec![[0.0; 2]; body.len()];
        self.sc = Self::critical_stretches(body);
        // Bonds born past their critical stretch start broken (part of the split).
        self.update_forces(body, true, false);
        self.accelerate(body);
        Ok(split)
    }
}

/// Work of the constant loads from u = 0 (J).
fn external_work(body: &Body, load: f64) -> f64 {
    load * body
        .u
        .iter()
        .zip(&body.body)
        .zip(&body.dh.volume)
        .map(|((u, b), v)| v * (u[0] * b[0] + u[1] * b[1]))
        .sum::<f64>()
}

/// Whether a bond of particle `k`'s horizon or dual horizon has broken during the run: a
/// bond flagged broken that crosses no pre-crack (module docs; a bond a split started
/// broken, past its owner's critical stretch, counts as broken by the run).
pub fn broke_in_run(body: &Body, k: usize) -> bool {
    let dh = &body.dh;
    let own = dh
        .bonds
        .row(k)
        .any(|b| dh.intact[b] == 0 && !crosses_precrack(body, k, dh.bonds.nbr[b] as usize));
    let duals = dh.dual_offsets[k]..dh.dual_offsets[k + 1];
    own || dh.dual[duals.clone()]
        .iter()
        .zip(&dh.dual_owner[duals])
        .any(|(&b, &o)| dh.intact[b as usize] == 0 && !crosses_precrack(body, o as usize, k))
}

/// Whether the bond between particles `i` and `j` crosses a pre-crack (to a millionth of
/// the smaller spacing).
fn crosses_precrack(body: &Body, i: usize, j: usize) -> bool {
    let tol = 1e-6 * body.size[i].min(body.size[j]);
    body.cracks
        .iter()
        .any(|c| segment_crosses_crack(body.dh.pos[i], body.dh.pos[j], c, tol))
}

/// Directed bonds cut by the pre-cracks.
fn precut(body: &Body) -> usize {
    let dh = &body.dh;
    let owner = dh.owners();
    (0..dh.bonds.len())
        .into_par_iter()
        .filter(|&b| {
            dh.intact[b] == 0 && crosses_precrack(body, owner[b] as usize, dh.bonds.nbr[b] as usize)
        })
        .count()
}

/// The run's step and its bound (module docs), the steps and the record interval:
/// [`crate::dynamics::plan_with`] with the bound of the smallest particles refinement can
/// make and the body's bond count at the start.
fn plan(
    body: &Body,
    p: &ExplicitParams,
    r: &Refinement,
) -> Result<(f64, f64, usize, usize), PdError> {
    let lmin = body.level.iter().copied().min().unwrap_or(r.max_level);
    let dt_c =
        critical_time_step(body, p.density) / f64::from(1u32 << r.max_level.saturating_sub(lmin));
    let bound = format!(
        "the stable step {dt_c:.4e} s of the smallest particles refinement can make (level {})",
        r.max_level
    );
    let plan = crate::dynamics::plan_with(p, dt_c, &bound, body.dh.bonds.len())?;
    Ok((plan.dt, plan.dt_c, plan.steps, plan.record_every))
}

/// Refinement settings adaptive dynamics cannot run: invalid ones, and kept horizons.
fn refuse_settings(r: &Refinement) -> Result<(), PdError> {
    r.validate()?;
    if r.keep_horizon {
        return Err(PdError::invalid(
            "refinement.keep_horizon",
            "explicit dynamics needs children with halved horizons (the stable step scales with the spacing at a fixed horizon factor)",
        ));
    }
    Ok(())
}

/// What [`run_dynamic`] refuses before its first step, on `body` set up as it sets it up
/// ([`super::run::set_up_static`] with `r`): the settings, the plan (the step against the
/// bound of the smallest particles, the work) and the region velocities (each box must
/// hold a particle). For a caller that checks a scene before it runs it.
pub fn check_plan(body: &Body, ex: &ExplicitParams, r: &Refinement) -> Result<(), PdError> {
    refuse_settings(r)?;
    plan(body, ex, r)?;
    let delta_max = body.dh.delta.iter().fold(0.0f64, |a, &b| a.max(b));
    region_velocities(&ex.velocities, body.positions(), &body.fixed, delta_max)?;
    Ok(())
}

/// Run the explicit dynamics of `p`'s refined body from rest with adaptive refinement
/// `r` checked every `check_every` steps (module docs), reporting through `obs`. Set-up:
/// the static regions of `r` ([`super::run::set_up_static`]; Eq. 15 fires during the run,
/// where bonds break: module docs). Returns the final body.
pub fn run_dynamic(
    p: &PdProblem,
    ex: &ExplicitParams,
    r: &Refinement,
    check_every: usize,
    obs: &mut dyn AdaptiveObserver,
) -> Result<(Body, AdaptiveInfo), PdError> {
    refuse_settings(r)?;
    if check_every == 0 {
        return Err(PdError::invalid("check_every", "must be at least 1 step"));
    }
    let mut body = Body::from_problem(p)?;
    super::run::set_up_static(&mut body, r)?;
    let (dt, dt_c, steps, record_every) = plan(&body, ex, r)?;
    let t0 = Instant::now();
    for k in 0..body.len() {
        for c in 0..2 {
            body.u[k][c] = if body.fixed[k][c] {
                ex.load * body.base[k][c]
            } else {
                0.0
            };
        }
    }
    let sc = State::critical_stretches(&body);
    let fixed = body.fixed.clone();
    let delta_max = body.dh.delta.iter().fold(0.0f64, |a, &b| a.max(b));
    let (v, held) = region_velocities(&ex.velocities, body.positions(), &fixed, delta_max)?;
    let mut st = State {
        v,
        a: vec![[0.0; 2]; body.len()],
        held,
        held_work: 0.0,
        f: Vec::new(),
        buf: PassBuffers::default(),
        measures: Measures::default(),
        sc,
        rho: ex.density,
        load: ex.load,
    };
    st.update_forces(&mut body, false, false);
    st.accelerate(&body);
    let (dx0, delta0) = (
        body.size.iter().fold(0.0f64, |a, &b| a.max(b)),
        body.dh.delta.iter().fold(0.0f64, |a, &b| a.max(b)),
    );
    let tracker_of =
        |b: &Body| CrackTracker::for_points(&b.dh.pos, &b.cracks, ex.damage_threshold, dx0, delta0);
    let mut tracker = tracker_of(&body);
    let mut cut = precut(&body);
    let e0 = st.kinetic(&body) + body.dh.energy(&body.u);
    let w0 = external_work(&body, ex.load);
    let mut jump = 0.0;
    let mut info = AdaptiveInfo {
        dynamics: DynamicsInfo {
            dt,
            dt_c,
            end_time: steps as f64 * dt,
            ..Default::default()
        },
        particles: (body.len(), body.len()),
        bonds: body.dh.bonds.len(),
        ..Default::default()
    };
    let mut snaps: Vec<(usize, f64)> = ex
        .snapshots
        .iter()
        .map(|&t| (((t / dt).round() as usize).min(steps), t))
        .collect();
    snaps.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut next_snap = 0;
    // Without Eq. 15 or 16 nothing splits during the run: no checks.
    let criteria = r.critical_damage.is_some() || r.strain_factor.is_some();
    for step in 0..=steps {
        let check = criteria && step > 0 && step % check_every == 0 && step != steps;
        if step > 0 {
            st.step(&mut body, dt, check);
        }
        let time = step as f64 * dt;
        if check {
            let t = Instant::now();
            let parents = flagged_measured(&body, r, &st.measures, |k| broke_in_run(&body, k));
            if !parents.is_empty() {
                let before =
                    st.kinetic(&body) + body.dh.energy(&body.u) - external_work(&body, ex.load);
                let split = st.split(&mut body, &parents)?;
                jump += st.kinetic(&body) + body.dh.energy(&body.u)
                    - external_work(&body, ex.load)
                    - before;
                tracker = tracker_of(&body);
                cut = precut(&body);
                let bound = critical_time_step(&body, ex.density);
                if dt > bound {
                    return Err(PdError::invalid(
                        "dt",
                        format!("time step {dt:.4e} s exceeds the refined body's stable step {bound:.4e} s at t = {time:.4e} s"),
                    ));
                }
                info.refinements += 1;
                info.particles.1 = info.particles.1.max(body.len());
                let e = SplitEvent {
                    step,
                    time,
                    split,
                    particles: body.len(),
                    dt_c: bound,
                    wall_s: t.elapsed().as_secs_f64(),
                };
                obs.split(&e);
            }
            info.refine_s += t.elapsed().as_secs_f64();
        }
        while next_snap < snaps.len() && snaps[next_snap].0 == step {
            obs.snapshot(snaps[next_snap].1, &body);
            next_snap += 1;
        }
        if step % record_every != 0 && step != steps {
            continue;
        }
        if !body.u.iter().all(|u| u[0].is_finite() && u[1].is_finite()) {
            return Err(PdError::NonFinite {
                solver: "explicit dynamics (refined body)",
                iteration: step,
                load: ex.load,
            });
        }
        let (kinetic, strain) = (st.kinetic(&body), body.dh.energy(&body.u));
        let work = external_work(&body, ex.load) - w0 + st.held_work;
        let phi = body.damage();
        let crack = tracker.measure_points(&body.dh.pos, &phi, &body.dh.bonds);
        let zeros = body.dh.intact.iter().filter(|&&f| f == 0).count();
        let rec = DynamicRecord {
            step,
            time,
            kinetic,
            strain,
            external_work: work,
            fracture: work - (kinetic + strain) + e0 + jump,
            broken_bonds: (zeros - cut.min(zeros)) / 2,
            tip: crack.tip,
            branched: crack.branch.is_some(),
        };
        let d = &mut info.dynamics;
        if d.branch_time.is_none() && crack.branch.is_some() {
            d.branch_time = Some(time);
            d.branch_point = crack.branch;
        }
        if d.boundary_time.is_none() && crack.at_boundary {
            d.boundary_time = Some(time);
        }
        obs.record(&rec);
        d.records += 1;
    }
    info.dynamics.steps = steps;
    info.dynamics.wall_time_s = t0.elapsed().as_secs_f64();
    Ok((body, info))
}

#[cfg(test)]
#[path = "dynamics_tests.rs"]
pub(super) mod tests;

//! Explicit dynamics of a [`PdModel`] (PMB or state-based): velocity Verlet with bond
//! breaking every step (seed 004 section 2.3, Eqs. 24-29; seed 002 Eq. 2 with inertia).
//!
//! **Equation of motion.** $\rho\,\ddot u_i = F_i(u) + \lambda\, b_i$ with $F_i$ the
//! internal force density of the model (N/m^3), $b_i$ the body force density of the
//! boundary data at load factor 1 and $\lambda$ the load factor, held constant from
//! $t = 0$ (a step load, "applied continuously", seed 004 section 4.2). Prescribed
//! components keep their value $\lambda \bar u$ and zero velocity (Eqs. 28-29).
//!
//! **Velocity Verlet** (Eqs. 24-27), from rest at $u = 0$ (prescribed components at
//! their values):
//! $$v^{n+1/2} = v^n + \tfrac{\Delta t}{2} a^n,\qquad u^{n+1} = u^n + \Delta t\, v^{n+1/2},$$
//! $$a^{n+1} = \big(F(u^{n+1}) + \lambda b\big)/\rho,\qquad
//!   v^{n+1} = v^{n+1/2} + \tfrac{\Delta t}{2} a^{n+1}.$$
//! The force pass at $u^{n+1}$ commits the bond history ([`History::Update`]): every
//! bond past its critical stretch breaks in that step and carries no force from it on.
//!
//! **Region velocities** ([`RegionVelocity`], the impact of seed 004 section 4.3): the
//! free components of the real nodes in a region start with $v^0 = \bar v$ instead of
//! rest; with `hold` they keep it for the whole run (their acceleration is set to zero,
//! so $u = \bar v\,t$: a prescribed velocity, the rigid impactor of Silling's 2003
//! Kalthoff-Winkler model). A node in several regions takes the last one's. The work of
//! the loads $W$ below then includes the work of the constraint forces that hold them,
//! $-\int \sum V (F + \lambda b)\cdot\bar v\,dt$ (trapezoidal rule over the steps).
//!
//! **Stable time step.** Central differences are stable for $\Delta t \le 2/\omega_{max}$
//! with $\omega_{max}^2$ the largest eigenvalue of $K/\rho$ ($K = -\partial F/\partial u$,
//! linearised at the reference configuration). Gershgorin's theorem bounds it by the
//! largest absolute row sum $R_i = \sum_m\sum_q |K_{(i,p),(m,q)}|$
//! ([`crate::solvers::adr::row_bounds`], the bound ADR's fictitious density uses), so
//! $$\Delta t_c = \min_i \sqrt{4\rho / R_i}$$
//! is stable. For PMB, where $R_i = 2\sum_j (c_{ij}/|\xi_{ij}|)\,(n_x^2 + |n_x n_y|) V_j$
//! (the bond's diagonal and off-diagonal blocks), this is Silling & Askari's (2005)
//! $\Delta t_c = \sqrt{2\rho / \sum_j V_j C_{ij}}$ with the bond stiffness
//! $C_{ij} = c/|\xi|$ projected on the axes instead of taken whole (so ours is the
//! larger, still a Gershgorin bound). A given `dt` above $\Delta t_c$ or above the end
//! time $T$ is refused (the run ends at the first step at or past $T$); without one, `dt`
//! is the largest step of at most `safety_factor * dt_c` that divides $T$ (so the run
//! ends on $T$).
//!
//! **Energies** (J, recorded per output interval): kinetic $K = \tfrac12\sum_i \rho V
//! |v_i|^2$, strain $U$ ([`PdModel::energy`]), work of the loads
//! $W = \lambda \sum_i V\, b_i\cdot u_i$ (constant loads from $u = 0$), and the
//! *fracture energy* as the energy balance's dissipation
//! $$D(t) = W(t) - \big(K(t) + U(t)\big) + \big(K(0) + U(0)\big):$$
//! the energy the broken bonds took with them (seed 004 Figs. 10b and 13b "total
//! fracture energy"). It is exact for the discrete system up to the integrator's energy
//! error, which the elastic tests bound (`tests.rs`).
//!
//! **Work bound.** A run takes $\lceil T/\Delta t\rceil$ steps of one force pass over
//! every directed bond; [`plan`] refuses more than [`MAX_STEPS`] steps, more than
//! [`MAX_BOND_STEPS`] bond updates in all, more than [`MAX_RECORDS`] records and more
//! than [`MAX_SNAPSHOTS`] snapshots, before a step is taken.
//!
//! Crack measures (tip, branching) come from [`crack::CrackTracker`], the deflection
//! angle of a crack grown from a pre-crack tip from [`angle::deflection_angle`].

pub mod angle;
#[cfg(any(test, feature = "bench"))]
pub mod bench;
pub mod crack;
mod impact;
#[cfg(test)]
mod tests;

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::error::PdError;
use crate::forces::History;
use crate::geometry::P2;
use crate::model::PdModel;
use crate::solvers::adr::row_bounds;
use crack::CrackTracker;
pub(crate) use impact::region_velocities;
pub use impact::RegionVelocity;

/// Most time steps of a run.
pub const MAX_STEPS: usize = 10_000_000;
/// Most directed-bond updates of a run (steps times directed bonds): about an hour of
/// force passes on two cores.
pub const MAX_BOND_STEPS: f64 = 2e11;
/// Most records (output intervals) of a run.
pub const MAX_RECORDS: usize = 1_000_000;
/// Most damage snapshots of a run.
pub const MAX_SNAPSHOTS: usize = 100;

/// Explicit dynamics parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExplicitParams {
    /// Mass density rho (kg/m^3), > 0.
    pub density: f64,
    /// Simulated time (s), > 0.
    pub end_time: f64,
    /// Time step (s), at most the stable `dt_c` and `end_time`; `None`: the largest step
    /// of at most `safety_factor * dt_c` that divides `end_time`.
    pub dt: Option<f64>,
    /// Fraction of `dt_c` taken when `dt` is `None`, in (0, 1]. Default 0.8.
    pub safety_factor: f64,
    /// Time between records (s); `None`: `end_time / 200`.
    pub output_every: Option<f64>,
    /// Times (s) of the damage snapshots handed to the observer, in [0, end_time].
    pub snapshots: Vec<f64>,
    /// Load factor applied from t = 0 and held (a step load). Default 1.
    pub load: f64,
    /// Damage above which a node counts as cracked for the tip and branch measures
    /// ([`crack::CrackTracker`]). Default 0.4 (seed 004's phi_c).
    pub damage_threshold: f64,
    /// Velocities given to the nodes of regions at t = 0 (module docs). Default none.
    pub velocities: Vec<RegionVelocity>,
}

impl Default for ExplicitParams {
    fn default() -> Self {
        ExplicitParams {
            density: 0.0,
            end_time: 0.0,
            dt: None,
            safety_factor: 0.8,
            output_every: None,
            snapshots: Vec::new(),
            load: 1.0,
            damage_threshold: 0.4,
            velocities: Vec::new(),
        }
    }
}

/// One record of the time history.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct DynamicRecord {
    /// Step index (0 = initial state).
    pub step: usize,
    /// Time (s).
    pub time: f64,
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Strain energy (J).
    pub strain: f64,
    /// Work of the loads (J).
    pub external_work: f64,
    /// Fracture energy: the energy balance's dissipation (J, module docs).
    pub fracture: f64,
    /// Broken bond pairs (pre-crack cuts not counted).
    pub broken_bonds: usize,
    /// Crack tip (m): the farthest cracked node along the crack direction.
    pub tip: Option<P2>,
    /// Whether the crack has branched (two separate damaged bands).
    pub branched: bool,
}

/// Receives the records and snapshots of a run (never prints).
pub trait DynamicsObserver {
    /// A record, every output interval and at the last step.
    fn record(&mut self, _r: &DynamicRecord) {}
    /// The model at the step nearest a requested snapshot time `time` (s).
    fn snapshot(&mut self, _time: f64, _model: &PdModel) {}
}

impl DynamicsObserver for () {}

/// Collects every record in memory.
impl DynamicsObserver for Vec<DynamicRecord> {
    fn record(&mut self, r: &DynamicRecord) {
        self.push(*r);
    }
}

/// What a run did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DynamicsInfo {
    /// Time steps taken.
    pub steps: usize,
    /// Time step (s).
    pub dt: f64,
    /// Stable time step bound (s).
    pub dt_c: f64,
    /// Simulated time (s).
    pub end_time: f64,
    /// First record time at which the crack had branched (s).
    pub branch_time: Option<f64>,
    /// Where along the crack it branched: the first branched column (m).
    pub branch_point: Option<P2>,
    /// First record time at which the tip reached the far boundary (s).
    pub boundary_time: Option<f64>,
    /// Records handed to the observer.
    pub records: usize,
    /// Wall time of the stepping (s).
    pub wall_time_s: f64,
}

/// The checked sizes of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Time step (s).
    pub dt: f64,
    /// Stable bound (s).
    pub dt_c: f64,
    /// Steps.
    pub steps: usize,
    /// Steps between records.
    pub record_every: usize,
    /// Snapshot steps with their requested times, in step order.
    pub snapshots: Vec<(usize, f64)>,
}

/// The stable time step bound $\min_i \sqrt{4\rho/R_i}$ (module docs) over the nodes
/// with a free component (s); infinite when no node moves.
pub fn critical_time_step(model: &PdModel, density: f64) -> f64 {
    let fixed = &model.boundary().fixed;
    row_bounds(model)
        .iter()
        .zip(fixed)
        .filter(|(_, f)| !(f[0] && f[1]))
        .map(|(r, _)| r[0].max(r[1]))
        .filter(|&r| r > 0.0)
        .map(|r| (4.0 * density / r).sqrt())
        .fold(f64::INFINITY, f64::min)
}

fn positive(field: &str, v: f64) -> Result<(), PdError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(PdError::invalid(
            field,
            format!("must be positive and finite, got {v}"),
        ))
    }
}

/// Validate `p` against `model` and size the run: the time step, its bound and the
/// work, and the region velocities (each box must hold a node). The errors name the
/// field (`density`, `end_time`, `dt`, `velocities[k].region`, ...). [`run`] starts with
/// it, so a caller that checks a scene before running it refuses what the run would.
pub fn plan(model: &PdModel, p: &ExplicitParams) -> Result<Plan, PdError> {
    positive("density", p.density)?;
    if model.grid.is_mixed() {
        return Err(PdError::invalid(
            "refine_zones",
            "explicit dynamics needs a uniform grid (lumped masses of the coarse volume); use pd::refine for dynamics on mixed sizes",
        ));
    }
    let dt_c = critical_time_step(model, p.density);
    let bound = format!(
        "the stable step dt_c = {dt_c:.4e} s (sqrt(4 rho / max row sum of the stiffness), rho = {} kg/m^3)",
        p.density
    );
    let plan = plan_with(p, dt_c, &bound, model.n_bonds())?;
    let n = model.n_real();
    region_velocities(
        &p.velocities,
        &model.positions()[..n],
        &model.bc.fixed[..n],
        model.grid.delta,
    )?;
    Ok(plan)
}

/// [`plan`] for a body whose stable step `dt_c` (described by `bound` in the errors) and
/// directed bond count `n_bonds` the caller knows (the refined body of
/// [`crate::refine::run_dynamic`]: its bond count at the start).
pub(crate) fn plan_with(
    p: &ExplicitParams,
    dt_c: f64,
    bound: &str,
    n_bonds: usize,
) -> Result<Plan, PdError> {
    positive("density", p.density)?;
    positive("end_time", p.end_time)?;
    if !(p.load.is_finite()) {
        return Err(PdError::invalid(
            "load",
            format!("must be finite, got {}", p.load),
        ));
    }
    if !(p.damage_threshold > 0.0 && p.damage_threshold < 1.0) {
        return Err(PdError::invalid(
            "damage_threshold",
            format!("must lie in (0, 1), got {}", p.damage_threshold),
        ));
    }
    let dt = match p.dt {
        Some(dt) => {
            positive("dt", dt)?;
            if dt > dt_c {
                return Err(PdError::invalid(
                    "dt",
                    format!(
                        "time step {dt:.4e} s exceeds {bound}: take dt <= dt_c or leave dt out for {} dt_c",
                        p.safety_factor
                    ),
                ));
            }
            if dt > p.end_time {
                return Err(PdError::invalid(
                    "dt",
                    format!(
                        "time step {dt:.4e} s exceeds end_time = {:.4e} s: the run would take one step and end at {dt:.4e} s; take dt <= end_time, or leave dt out",
                        p.end_time
                    ),
                ));
            }
            dt
        }
        None => {
            if !(p.safety_factor > 0.0 && p.safety_factor <= 1.0) {
                return Err(PdError::invalid(
                    "safety_factor",
                    format!("must lie in (0, 1], got {}", p.safety_factor),
                ));
            }
            if !dt_c.is_finite() {
                return Err(PdError::invalid(
                    "dt",
                    "nothing moves (every component prescribed): nothing to integrate",
                ));
            }
            // The largest step of at most safety_factor dt_c that ends on end_time.
            let most = p.safety_factor * dt_c;
            p.end_time / (p.end_time / most).ceil()
        }
    };
    let steps_f = (p.end_time / dt * (1.0 - 1e-12)).ceil();
    if steps_f > MAX_STEPS as f64 {
        return Err(PdError::invalid(
            "end_time",
            format!(
                "{steps_f:.3e} time steps (end_time {:.4e} s / dt {dt:.4e} s) exceed the limit {MAX_STEPS}: shorten end_time or coarsen dx",
                p.end_time
            ),
        ));
    }
    let steps = (steps_f as usize).max(1);
    let work = steps as f64 * n_bonds as f64;
    if work > MAX_BOND_STEPS {
        return Err(PdError::invalid(
            "end_time",
            format!(
                "{steps} steps x {n_bonds} directed bonds = {work:.3e} bond updates exceed the limit {MAX_BOND_STEPS:.0e}: shorten end_time or coarsen dx"
            ),
        ));
    }
    let every = p.output_every.unwrap_or(p.end_time / 200.0);
    positive("output_every", every)?;
    let record_every = ((every / dt).round() as usize).clamp(1, steps);
    if steps / record_every > MAX_RECORDS {
        return Err(PdError::invalid(
            "output_every",
            format!(
                "{} records exceed the limit {MAX_RECORDS}: raise output_every",
                steps / record_every
            ),
        ));
    }
    if p.snapshots.len() > MAX_SNAPSHOTS {
        return Err(PdError::invalid(
            "snapshots",
            format!(
                "{} snapshots exceed the limit {MAX_SNAPSHOTS}",
                p.snapshots.len()
            ),
        ));
    }
    let mut snapshots = Vec::with_capacity(p.snapshots.len());
    for (k, &t) in p.snapshots.iter().enumerate() {
        if !(t.is_finite() && (0.0..=p.end_time * (1.0 + 1e-9)).contains(&t)) {
            return Err(PdError::invalid(
                format!("snapshots[{k}]"),
                format!("time {t} s lies outside [0, end_time = {}]", p.end_time),
            ));
        }
        snapshots.push((((t / dt).round() as usize).min(steps), t));
    }
    snapshots.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    Ok(Plan {
        dt,
        dt_c,
        steps,
        record_every,
        snapshots,
    })
}

/// Velocity-Verlet state of a model: velocities and accelerations.
pub(crate) struct Verlet {
    pub(crate) v: Vec<P2>,
    a: Vec<P2>,
    /// Components whose velocity is held (zero acceleration).
    held: Vec<[bool; 2]>,
    /// Work done by the constraints holding them since t = 0 (J, trapezoidal rule).
    held_work: f64,
    dt: f64,
    rho: f64,
}

impl Verlet {
    /// At rest, with the accelerations of the current state (no history change).
    pub(crate) fn new(model: &mut PdModel, density: f64, dt: f64) -> Self {
        let n = model.n_nodes();
        let mut s = Verlet {
            v: vec![[0.0; 2]; n],
            a: vec![[0.0; 2]; n],
            held: vec![[false; 2]; n],
            held_work: 0.0,
            dt,
            rho: density,
        };
        model.compute_forces(History::Frozen);
        s.accelerate(model);
        s
    }

    fn accelerate(&mut self, model: &PdModel) {
        let lam = model.load;
        let (f, b, fixed) = (&model.force, &model.bc.body, &model.bc.fixed);
        for i in 0..self.a.len() {
            for d in 0..2 {
                self.a[i][d] = if fixed[i][d] || self.held[i][d] {
                    0.0
                } else {
                    (f[i][d] + lam * b[i][d]) / self.rho
                };
            }
        }
    }

    fn half_kick(&mut self) {
        let h = 0.5 * self.dt;
        for (v, a) in self.v.iter_mut().zip(&self.a) {
            v[0] += h * a[0];
            v[1] += h * a[1];
        }
    }

    /// One step (Eqs. 24-27); returns the directed bonds broken in it.
    pub(crate) fn step(&mut self, model: &mut PdModel) -> usize {
        let p0 = self.held_power(model);
        self.half_kick();
        for (u, v) in model.u.iter_mut().zip(&self.v) {
            u[0] += self.dt * v[0];
            u[1] += self.dt * v[1];
        }
        let stats = model.compute_forces(History::Update);
        self.accelerate(model);
        self.half_kick();
        self.held_work += 0.5 * self.dt * (p0 + self.held_power(model));
        stats.newly_broken
    }

    /// Power (W) of the constraint forces that hold the held components' velocities:
    /// $-\sum V (F + \lambda b)\cdot\bar v$ over the held components.
    fn held_power(&self, model: &PdModel) -> f64 {
        let lam = model.load;
        let (f, b) = (&model.force, &model.bc.body);
        let mut p = 0.0;
        for (i, h) in self.held.iter().enumerate() {
            for d in 0..2 {
                if h[d] {
                    p -= (f[i][d] + lam * b[i][d]) * self.v[i][d];
                }
            }
        }
        p * model.grid.volume
    }

    /// Kinetic energy (J).
    pub(crate) fn kinetic(&self, model: &PdModel) -> f64 {
        let m = self.rho * model.grid.volume;
        0.5 * m
            * self
                .v
                .iter()
                .map(|v| v[0] * v[0] + v[1] * v[1])
                .sum::<f64>()
    }
}

/// Work of the constant loads from u = 0 (J).
pub(crate) fn external_work(model: &PdModel) -> f64 {
    let v = model.grid.volume * model.load;
    model
        .u
        .iter()
        .zip(&model.bc.body)
        .map(|(u, b)| v * (u[0] * b[0] + u[1] * b[1]))
        .sum()
}

/// Run the explicit dynamics of `model` from rest (u = 0, prescribed components at
/// `p.load` times their values) to `p.end_time`, reporting through `obs`; `cracks` are
/// the pre-crack polylines for the tip and branch measures (may be empty).
pub fn run(
    model: &mut PdModel,
    p: &ExplicitParams,
    cracks: &[Vec<P2>],
    obs: &mut dyn DynamicsObserver,
) -> Result<DynamicsInfo, PdError> {
    let plan = plan(model, p)?;
    let t0 = Instant::now();
    let zero = vec![[0.0; 2]; model.n_nodes()];
    model.set_displacements(&zero)?;
    model.set_load_factor(p.load);
    let tracker = CrackTracker::new(model, cracks, p.damage_threshold);
    let mut vv = Verlet::new(model, p.density, plan.dt);
    let n = model.n_real();
    let (v, held) = region_velocities(
        &p.velocities,
        &model.positions()[..n],
        &model.bc.fixed[..n],
        model.grid.delta,
    )?;
    vv.v[..n].copy_from_slice(&v);
    vv.held[..n].copy_from_slice(&held);
    vv.accelerate(model);
    let e0 = vv.kinetic(model) + model.energy();
    let w0 = external_work(model);
    let mut info = DynamicsInfo {
        dt: plan.dt,
        dt_c: plan.dt_c,
        end_time: plan.steps as f64 * plan.dt,
        ..Default::default()
    };
    let mut next_snap = 0;
    for step in 0..=plan.steps {
        if step > 0 {
            vv.step(model);
        }
        while next_snap < plan.snapshots.len() && plan.snapshots[next_snap].0 == step {
            obs.snapshot(plan.snapshots[next_snap].1, model);
            next_snap += 1;
        }
        if step % plan.record_every != 0 && step != plan.steps {
            continue;
        }
        let time = step as f64 * plan.dt;
        if !model.u.iter().all(|u| u[0].is_finite() && u[1].is_finite()) {
            return Err(PdError::NonFinite {
                solver: "explicit dynamics",
                iteration: step,
                load: p.load,
            });
        }
        let (kinetic, strain) = (vv.kinetic(model), model.energy());
        let work = external_work(model) - w0 + vv.held_work;
        let crack = tracker.measure(model);
        let r = DynamicRecord {
            step,
            time,
            kinetic,
            strain,
            external_work: work,
            fracture: work - (kinetic + strain) + e0,
            broken_bonds: model.broken_bonds(),
            tip: crack.tip,
            branched: crack.branch.is_some(),
        };
        if info.branch_time.is_none() && crack.branch.is_some() {
            info.branch_time = Some(time);
            info.branch_point = crack.branch;
        }
        if info.boundary_time.is_none() && crack.at_boundary {
            info.boundary_time = Some(time);
        }
        obs.record(&r);
        info.records += 1;
    }
    info.steps = plan.steps;
    info.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(info)
}

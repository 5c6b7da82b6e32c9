//! Rules of `pd` and `coupling` (`growth`: [`super::growth`]).

use super::limits::relative_tolerance;
use super::strain::MAX_NOMINAL_STRAIN;
use super::Checker;
use crate::geometry::{bounding_box, direction, p2, point_in_polygon, P2};
use crate::scene::shapes::outline_loop;
use crate::scene::{
    CouplingOrdering, Failure, GrowthMode, PdSolver, PdTraction, Placement, Relaxation, Scene,
};

/// Smallest horizon factor m = delta / dx where the PD calibration holds.
pub const MIN_HORIZON_FACTOR: f64 = 2.0;
/// Smallest iteration cap of ADR, implicit Newton and the coupling: each measures
/// convergence from its second iteration (the first has nothing to compare with), so a
/// cap of 1 always failed at run time ("did not converge in 1 iterations: measure inf").
/// The switching solver's caps may be 1 (a Newton step that does not converge hands
/// the increment over).
pub const MIN_ITERATIONS: usize = 2;
/// What [`MIN_ITERATIONS`] bounds, in messages.
const CAP: &str = "iteration cap (convergence is measured from the second iteration)";
/// Largest horizon factor m = delta / dx accepted.
pub const MAX_HORIZON_FACTOR: f64 = 6.0;
/// Largest coupling tolerance psi (a relative change of the interface displacements).
pub const MAX_PSI: f64 = 0.1;
/// Smallest psi of a static coupled solve: the interface change settles at round-off
/// of about 1e-12 (`coupled_sent_a5`: 9.7e-12 after 50 iterations at psi = 1e-12, where
/// 1e-10 converged in 20).
pub const MIN_PSI: f64 = 1e-10;
/// Smallest psi of PD-BEM growth: its windows solve each equilibrium to a relative
/// residual of 1e-9 and break bonds between iterations, so the change stalls near 1e-10
/// to 1e-9 (`growth_tension_edge`: 3.3e-10 after 50 iterations at psi = 1e-10 and 1.0e-9
/// at 1e-11, the back-off's retries diverging; 1e-8 ran as 1e-4 does).
pub const MIN_GROWTH_PSI: f64 = 1e-8;
/// Checks the PD and coupling sections.
pub fn check(c: &mut Checker, scene: &Scene) {
    if let Some(pd) = &scene.pd {
        check_pd(c, scene, pd);
    }
    if let Some(co) = &scene.coupling {
        check_coupling(c, scene, co);
    }
}

fn check_pd(c: &mut Checker, scene: &Scene, pd: &crate::scene::PdSettings) {
    match (pd.dx, pd.nx) {
        (Some(dx), None) => {
            c.positive("pd.dx", dx, "grid spacing dx");
        }
        (None, Some(nx)) => {
            c.at_least("pd.nx", nx, 1, "nodes across the body");
        }
        (Some(_), Some(_)) => c.fail_at("pd", "give `dx` or `nx`, not both"),
        (None, None) if scene.coupling.is_none() => c.fail_at(
            "pd",
            "give the grid spacing `dx` (m) or the node count `nx`",
        ),
        (None, None) => {}
    }
    let m = pd.horizon_factor;
    if c.finite("pd.horizon_factor", m) && !(MIN_HORIZON_FACTOR..=MAX_HORIZON_FACTOR).contains(&m) {
        c.fail(
            "pd.horizon_factor",
            m,
            format!("the horizon factor m = delta/dx must lie in [{MIN_HORIZON_FACTOR}, {MAX_HORIZON_FACTOR}] (default 3.015): the PD micromodulus calibration and the surface and crack-face corrections hold there (m = 1 gives K about 23 % high; beyond 6 the boundary layers and bond counts grow as m^2 for no accuracy)"),
        );
    }
    if scene.coupling.is_none() && scene.body.outline.remote_stress().is_some() {
        c.fail_at(
            "pd",
            "stand-alone PD needs a finite body: an Infinite outline has no region to fill",
        );
    }
    if scene.coupling.is_none() {
        check_body_spans_horizons(c, scene, pd);
    }
    check_state_based_nu(c, scene, pd);
    check_solver(c, &pd.solver);
    if let PdSolver::Explicit(p) = &pd.solver {
        check_explicit(c, scene, p);
    }
    check_failure(c, scene, &pd.failure);
    let full_pd = scene
        .growth
        .as_ref()
        .is_some_and(|g| g.mode == GrowthMode::FullPd);
    if pd.traction == PdTraction::TransferFunction && scene.coupling.is_some() && !full_pd {
        c.fail_at(
            "pd.traction",
            "TransferFunction loads the scene's tractions on a stand-alone (or full-PD growth) PD body; PD-BEM windows take their loads from the BEM (as displacements, or as tractions through the transfer functions with `coupling.ordering: TractionToPd`), so drop `coupling` or the field",
        );
    }
    if let Some(r) = &pd.refinement {
        super::pd_refinement::check(c, scene, pd, r);
    }
    super::pd_zones::check(c, scene, pd);
    if let Some(names) = &pd.pre_cracks {
        for (i, n) in names.iter().enumerate() {
            if !scene.cracks.iter().any(|cr| &cr.name == n) {
                c.fail(
                    format!("pd.pre_cracks.{i}"),
                    format!("{n:?}"),
                    "no crack of this name in `cracks`",
                );
            }
        }
    }
}

/// `pd.solver: Explicit`: stand-alone PD (no coupling or growth), a mass
/// density, and its times in range (the stable step and the work bound are checked
/// against the grid by `crate::run_dynamic::check`).
fn check_explicit(c: &mut Checker, scene: &Scene, p: &crate::scene::ExplicitParams) {
    if scene.coupling.is_some() || scene.growth.is_some() {
        c.fail_at(
            "pd.solver",
            "Explicit dynamics runs in stand-alone PD only (not in PD-BEM windows or growth): drop `coupling`/`growth` or choose Adr, Implicit or Switching",
        );
    }
    if scene.material.density.is_none() {
        c.fail_at(
            "material.density",
            "Explicit dynamics needs the mass density (kg/m^3), e.g. `density: 2450`",
        );
    }
    if c.positive("pd.solver.end_time", p.end_time, "simulated time") {
        for (i, &t) in p.snapshots.iter().enumerate() {
            if c.finite(&format!("pd.solver.snapshots.{i}"), t) && !(0.0..=p.end_time).contains(&t)
            {
                c.fail(
                    format!("pd.solver.snapshots.{i}"),
                    t,
                    format!("snapshot time must lie in [0, end_time = {}]", p.end_time),
                );
            }
        }
    }
    if let Some(dt) = p.dt {
        if c.positive("pd.solver.dt", dt, "time step") && p.end_time > 0.0 && dt > p.end_time {
            c.fail(
                "pd.solver.dt",
                dt,
                format!(
                    "the time step exceeds end_time = {}: the run would take one step and end at dt; take dt <= end_time, or leave dt out",
                    p.end_time
                ),
            );
        }
    }
    check_velocities(c, scene, &p.velocities);
    if let Some(e) = p.output_every {
        c.positive("pd.solver.output_every", e, "record interval");
    }
    if c.finite("pd.solver.safety_factor", p.safety_factor)
        && !(p.safety_factor > 0.0 && p.safety_factor <= 1.0)
    {
        c.fail(
            "pd.solver.safety_factor",
            p.safety_factor,
            "fraction of the stable time step must lie in (0, 1]",
        );
    }
}

/// Stand-alone PD: the body's bounding box spans at least one horizon across each side
/// (`pd.dx`, or its width / `pd.nx`, times the horizon factor). In a thinner body every
/// family is cut by both faces: the PD calibration holds nowhere, and solves of such a
/// grid fail to converge (`nx: 2` on a square: the implicit solve stalled at 2e-2). A
/// strip of 1.7 horizons, as `pd_bar_tension` (5 nodes across), still converges to the
/// bar's u = F x / (A E) with the surface correction.
fn check_body_spans_horizons(c: &mut Checker, scene: &Scene, pd: &crate::scene::PdSettings) {
    let Some(outline) = outline_loop(&scene.body.outline) else {
        return;
    };
    let (lo, hi) = bounding_box(&outline.points);
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let (dx, field, given) = match (pd.dx, pd.nx) {
        (Some(dx), None) => (dx, "pd.dx", dx.to_string()),
        (None, Some(nx)) if nx > 0 => (w / nx as f64, "pd.nx", nx.to_string()),
        _ => return,
    };
    let delta = pd.horizon_factor * dx;
    if !(delta.is_finite() && delta > 0.0 && w.is_finite() && h.is_finite()) {
        return;
    }
    if w.min(h) < delta {
        c.fail(
            field,
            given,
            format!(
                "the horizon {delta:.4e} m (dx {dx:.4e} m times {}) must fit across the body's {:.4e} m: in a thinner body every family is cut by both faces; refine the grid",
                pd.horizon_factor,
                w.min(h)
            ),
        );
    }
}

/// `pd.model: StateBased` (stand-alone or in the windows, which take the body's nu):
/// nu from [`pdbem_pd::problem::MIN_STATE_BASED_NU`] = 0 on, where the discrete energy
/// is positive definite.
fn check_state_based_nu(c: &mut Checker, scene: &Scene, pd: &crate::scene::PdSettings) {
    let nu = scene.material.nu;
    let min = pdbem_pd::problem::MIN_STATE_BASED_NU;
    if pd.model == crate::scene::PdModelKind::StateBased && nu.is_finite() && nu < min {
        c.fail(
            "material.nu",
            nu,
            format!("state-based PD (pd.model: StateBased) takes a Poisson ratio from {min} on: below, its discrete energy is not positive definite (negative tangent eigenvalues on free plates from nu = -0.1 at some horizon factors; solves there diverge or return no equilibrium); the BEM alone takes any nu in (-1, 0.5)"),
        );
    }
}

/// `pd.solver.velocities`: finite boxes with `min` below `max` that overlap the body's
/// bounding box, finite velocities (that a box holds a particle is checked by the run)
/// below the bar wave speed c = sqrt(E / rho): a velocity v sent into a bar strains it by
/// v / c (sigma = rho c v), so from [`MAX_NOMINAL_STRAIN`] times c on an impact is outside
/// small-strain elasticity, as a load is (1e6 m/s on the steel Kalthoff plate: a fracture
/// energy of -6.6e4 J).
fn check_velocities(c: &mut Checker, scene: &Scene, v: &[crate::scene::RegionVelocity]) {
    let bbox = outline_loop(&scene.body.outline).map(|o| bounding_box(&o.points));
    let wave = scene
        .material
        .density
        .map(|rho| (scene.material.e / rho).sqrt())
        .filter(|c| c.is_finite() && *c > 0.0);
    for (i, r) in v.iter().enumerate() {
        let path = |f: &str| format!("pd.solver.velocities.{i}.{f}");
        let finite = [r.min.0, r.min.1, r.max.0, r.max.1]
            .iter()
            .all(|x| c.finite(&path("min"), *x));
        let moving =
            c.finite(&path("velocity"), r.velocity.0) & c.finite(&path("velocity"), r.velocity.1);
        if moving && r.velocity == (0.0, 0.0) && !r.hold {
            c.fail(
                path("velocity"),
                format!("{:?}", r.velocity),
                "a zero initial velocity changes nothing (the body starts at rest): drop the entry, or set `hold: true` to hold the box still",
            );
        }
        let strain = wave.map_or(0.0, |w| r.velocity.0.hypot(r.velocity.1) / w);
        if moving && strain >= MAX_NOMINAL_STRAIN {
            c.fail(
                path("velocity"),
                format!("{:?}", r.velocity),
                format!(
                    "the impact strains the body by about {strain:.3e} (|v| / c, c = sqrt(E / rho) = {:.4e} m/s the bar wave speed): from {MAX_NOMINAL_STRAIN} on it is outside the small-strain elasticity PD solves (check the units, m/s)",
                    wave.unwrap_or(f64::NAN)
                ),
            );
        }
        if !finite {
            continue;
        }
        if !(r.min.0 < r.max.0 && r.min.1 < r.max.1) {
            c.fail(
                path("max"),
                format!("{:?}", r.max),
                format!(
                    "the box's upper corner must lie above and right of min = {:?}",
                    r.min
                ),
            );
        } else if let Some((lo, hi)) = bbox {
            if r.max.0 < lo.x || r.min.0 > hi.x || r.max.1 < lo.y || r.min.1 > hi.y {
                c.fail(
                    path("min"),
                    format!("{:?}", r.min),
                    "the box lies outside the body: it holds no particle",
                );
            }
        }
    }
}

fn check_solver(c: &mut Checker, solver: &PdSolver) {
    match solver {
        PdSolver::Explicit(_) => {}
        PdSolver::Adr(p) => {
            relative_tolerance(c, "pd.solver.tolerance", p.tolerance);
            c.at_least("pd.solver.max_iter", p.max_iter, MIN_ITERATIONS, CAP);
            if c.finite("pd.solver.safety_factor", p.safety_factor) && p.safety_factor < 1.0 {
                c.fail(
                    "pd.solver.safety_factor",
                    p.safety_factor,
                    "safety factor must be >= 1",
                );
            }
        }
        PdSolver::Implicit(p) => {
            relative_tolerance(c, "pd.solver.tolerance", p.tolerance);
            c.at_least("pd.solver.max_iter", p.max_iter, MIN_ITERATIONS, CAP);
        }
        PdSolver::Switching(p) => {
            relative_tolerance(c, "pd.solver.tolerance", p.tolerance);
            c.at_least("pd.solver.max_newton", p.max_newton, 1, "iteration cap");
            c.at_least("pd.solver.max_adr", p.max_adr, 1, "iteration cap");
            c.at_least(
                "pd.solver.implicit_steps",
                p.implicit_steps,
                1,
                "loading steps",
            );
            c.at_least(
                "pd.solver.explicit_steps",
                p.explicit_steps,
                1,
                "loading steps",
            );
        }
    }
}

fn check_failure(c: &mut Checker, scene: &Scene, failure: &Failure) {
    match failure {
        Failure::Elastic => {}
        Failure::CriticalStretch(s0) => {
            c.positive("pd.failure", *s0, "critical stretch s0");
        }
        Failure::FromGc => {
            let has = scene
                .material
                .fracture
                .as_ref()
                .and_then(|f| f.g_c)
                .is_some();
            if !has {
                c.fail_at("pd.failure", "FromGc needs material.fracture.g_c");
            }
        }
        Failure::Degradation { s_m, s_c, beta } => {
            let ok = c.positive("pd.failure.s_m", *s_m, "s_m")
                & c.positive("pd.failure.s_c", *s_c, "s_c");
            if ok && s_m >= s_c {
                c.fail(
                    "pd.failure.s_m",
                    s_m,
                    format!("s_m must be below s_c = {s_c}"),
                );
            }
            c.positive("pd.failure.beta", *beta, "degradation steepness beta");
        }
    }
}

fn check_coupling(c: &mut Checker, scene: &Scene, co: &crate::scene::Coupling) {
    if scene.pd.is_none() {
        c.fail_at(
            "coupling",
            "a coupled solve needs a `pd` section (material model of the windows)",
        );
    }
    if !c.positive("coupling.side", co.side, "window side") {
        return;
    }
    // Full-PD growth takes only its grid spacing from the coupling section: no window.
    let windows = scene
        .growth
        .as_ref()
        .is_none_or(|g| g.mode != GrowthMode::FullPd);
    if windows {
        check_window_nodes(c, scene, co);
    }
    if let Some(r) = &co.refine {
        super::window_refine::check(c, scene, co, r);
    }
    let pd_bem_growth = scene
        .growth
        .as_ref()
        .is_some_and(|g| g.mode == GrowthMode::PdBem);
    check_psi(c, co.psi, pd_bem_growth);
    c.at_least("coupling.max_iter", co.max_iter, MIN_ITERATIONS, CAP);
    if co.ordering == CouplingOrdering::TractionToPd && pd_bem_growth {
        c.fail_at(
            "coupling.ordering",
            "TractionToPd solves static windows only (no staggered bond breaking): PD-BEM growth needs DisplacementToPd, so drop the field or the `growth` section",
        );
    }
    check_relaxation(c, &co.relaxation);
    let Some(outline) = outline_loop(&scene.body.outline) else {
        return;
    };
    let (lo, hi) = bounding_box(&outline.points);
    let limit = (hi - lo).min();
    // A `Region` window's width is `side` (checked below); it may span the body.
    let region = matches!(co.placement, crate::scene::Placement::Region { .. });
    if co.side >= limit && !region {
        c.fail("coupling.side", co.side, format!("coupling window larger than the body: side must be below the body's smaller extent {limit} m"));
        return;
    }
    let corners = match &co.placement {
        Placement::AtTips if windows => return check_tip_windows(c, scene, co, &outline.points),
        Placement::AtTips => return,
        Placement::Centered { center, angle_deg } => {
            square_corners(p2(*center), co.side, *angle_deg)
        }
        Placement::Region {
            x0,
            y0,
            width,
            height,
        } => {
            c.positive("coupling.placement.width", *width, "region width");
            c.positive("coupling.placement.height", *height, "region height");
            // dx = side / n everywhere (`Coupling::dx`): the region's width must be `side`.
            if (co.side - width).abs() > 1e-9 * width.abs() {
                c.fail(
                    "coupling.side",
                    co.side,
                    format!("a Region window is `side` wide: set side to the region width {width} m (dx = side / n)"),
                );
            }
            vec![
                P2::new(*x0, *y0),
                P2::new(x0 + width, *y0),
                P2::new(x0 + width, y0 + height),
                P2::new(*x0, y0 + height),
            ]
        }
    };
    let tol = 1e-9 * (hi - lo).norm();
    let inside = |p: &P2| {
        point_in_polygon(p, &outline.points)
            || crate::geometry::polygon_distance(p, &outline.points) <= tol
    };
    if !corners.iter().all(inside) {
        c.fail_at("coupling.placement", "window reaches outside the body");
    }
}

pub(super) fn square_corners(center: P2, side: f64, angle_deg: f64) -> Vec<P2> {
    let (e1, e2) = (
        direction(angle_deg) * side * 0.5,
        direction(angle_deg + 90.0) * side * 0.5,
    );
    vec![
        center - e1 - e2,
        center + e1 - e2,
        center + e1 + e2,
        center - e1 + e2,
    ]
}

fn check_relaxation(c: &mut Checker, r: &Relaxation) {
    let w = match r {
        Relaxation::Constant(w) | Relaxation::Aitken(w) => *w,
        Relaxation::IqnIls { w0 } => *w0,
    };
    if c.finite("coupling.relaxation", w) && !(w > 0.0 && w <= 1.0) {
        c.fail(
            "coupling.relaxation",
            w,
            "relaxation factor must lie in (0, 1]",
        );
    }
}

/// `coupling.n`: a window is at least two horizons wide (the coupling crate's
/// `TooFewNodes`: n >= 2 m, m = `pd.horizon_factor`, 7 at the default 3.015), and even
/// with `AtTips` windows (with an odd n every coupled run stopped at run time with
/// "interface mismatch"; the cause is not fixed here, the scene is refused), and a
/// `Region` at least two horizons high.
fn check_window_nodes(c: &mut Checker, scene: &Scene, co: &crate::scene::Coupling) {
    let m = scene
        .pd
        .as_ref()
        .map(|p| p.horizon_factor)
        .filter(|m| m.is_finite() && *m >= 1.0 && *m <= MAX_HORIZON_FACTOR)
        .unwrap_or(crate::scene::pd::default_horizon_factor());
    let needed = (2.0 * m).ceil() as usize;
    if co.n < needed {
        c.fail(
            "coupling.n",
            co.n,
            format!("PD nodes per window side must be at least {needed}: a window must be at least 2 horizons wide (n >= 2 m, m = pd.horizon_factor = {m})"),
        );
    } else if let Placement::Region { height, .. } = co.placement {
        let ny = (height / co.dx()).round();
        if ny.is_finite() && ny < needed as f64 {
            c.fail(
                "coupling.placement.height",
                height,
                format!("the region is {ny} nodes high at dx = side / n = {}: it must be at least {needed} (2 horizons, as coupling.n)", co.dx()),
            );
        }
    } else if co.placement == Placement::AtTips && co.n % 2 == 1 {
        c.fail(
            "coupling.n",
            co.n,
            format!("AtTips windows need an even number of nodes per side (with an odd n the coupled solve ends in an interface mismatch): use {} or {}", co.n - 1, co.n.saturating_add(1)),
        );
    }
}

/// `coupling.psi`: a relative tolerance in [[`MIN_PSI`], [`MAX_PSI`]], from
/// [`MIN_GROWTH_PSI`] in PD-BEM growth (`growth`): below, the iteration cannot settle
/// that far and ends unconverged.
fn check_psi(c: &mut Checker, psi: f64, growth: bool) {
    if !c.finite("coupling.psi", psi) {
        return;
    }
    if !(psi > 0.0 && psi <= MAX_PSI) {
        c.fail(
            "coupling.psi",
            psi,
            format!("convergence tolerance psi is a relative change of the interface displacements: it must lie in (0, {MAX_PSI}] (default 1e-4; psi = 1 stops after one iteration with K off by +148 %)"),
        );
        return;
    }
    let (least, why) = if growth {
        (MIN_GROWTH_PSI, "in PD-BEM growth the windows solve each equilibrium to a relative residual of 1e-9 and break bonds between iterations, so the change stalls near 1e-10 to 1e-9 and the steps end unconverged")
    } else {
        (MIN_PSI, "the change settles at round-off of about 1e-12, and the solve ends unconverged below that")
    };
    if psi < least {
        c.fail(
            "coupling.psi",
            psi,
            format!("a relative change of the interface displacements below {least:e} cannot mean convergence: {why}; take psi of at least {least:e} (the default 1e-4 gives K within 0.2 %)"),
        );
    }
}

/// `AtTips` windows: the scene has a crack tip inside the body, and the square of side
/// `coupling.side` centred on each tip, axes along the crack, lies inside the outline.
fn check_tip_windows(c: &mut Checker, scene: &Scene, co: &crate::scene::Coupling, outline: &[P2]) {
    use crate::scene::shapes::SceneGeometry;
    let geo = SceneGeometry::of(scene);
    let tips: Vec<(String, P2, P2)> = geo
        .cracks
        .iter()
        .flat_map(|cr| cr.tip_directions())
        .collect();
    if tips.is_empty() {
        c.fail_at("coupling.placement", "AtTips places one window on each crack tip, but the scene has no crack: add a crack or use Centered / Region");
        return;
    }
    let (lo, hi) = bounding_box(outline);
    let tol = 1e-9 * (hi - lo).norm();
    for (name, tip, d) in tips {
        let angle = d.y.atan2(d.x).to_degrees();
        let corners = square_corners(tip, co.side, angle);
        let inside = |p: &P2| {
            point_in_polygon(p, outline) || crate::geometry::polygon_distance(p, outline) <= tol
        };
        if !corners.iter().all(inside) {
            c.fail(
                "coupling.side",
                co.side,
                format!("the window on tip {name} reaches outside the body: use a smaller side or move the crack"),
            );
        }
    }
}

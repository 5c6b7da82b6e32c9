//! Upper bounds on counts and magnitudes (issue 17, "trust at the extremes"), and the
//! range of a PD solve's relative tolerance ([`relative_tolerance`]): every
//! integer field that sizes an allocation or a loop, and every coordinate that feeds a
//! sampling grid, has a bound here, so no scene can ask for 2^64 load steps, a grid of
//! 10^16 points or a sampling line from -1e308. The memory of the models themselves is
//! bounded by the size budget ([`crate::setup::estimate`]), not here.
//!
//! Names used in output file names (cracks: `path_<tip>.csv`; grids: `grid_<name>.csv`;
//! lines: `line_<name>.csv`) are safe file names.

use super::Checker;
use crate::scene::{PdSolver, Scene};

/// Smallest relative tolerance of a PD solver (`pd.solver.tolerance`): f64 resolves
/// relative changes of 2.2e-16 and a solve's round-off floor lies some tens of times
/// above (Newton's residual meets 1e-14 on `pd_cantilever`; ADR's displacement change
/// reaches 2.2e-16), so a smaller tolerance cannot mean convergence.
pub const MIN_PD_TOLERANCE: f64 = 1e-14;

/// A relative tolerance of a PD solver at `path`: in [[`MIN_PD_TOLERANCE`], 1).
pub(super) fn relative_tolerance(c: &mut Checker, path: &str, v: f64) {
    tolerance_from(c, path, v, MIN_PD_TOLERANCE);
}

/// `pd.refinement.tolerance`: in [[`pdbem_pd::refine::MIN_TOLERANCE`], 1), the floor of
/// the refined particles' conjugate gradients, which stall in round-off above
/// [`MIN_PD_TOLERANCE`].
pub(super) fn refinement_tolerance(c: &mut Checker, path: &str, v: f64) {
    tolerance_from(c, path, v, pdbem_pd::refine::MIN_TOLERANCE);
}

fn tolerance_from(c: &mut Checker, path: &str, v: f64, floor: f64) {
    if c.finite(path, v) && !(floor..1.0).contains(&v) {
        c.fail(
            path,
            v,
            format!("a relative tolerance must lie in [{floor:e}, 1): below it the solve's measure is round-off (f64 resolves 2.2e-16; the solve stalls above it), from 1 on the first iterate passes"),
        );
    }
}

/// Most load steps (`load.count`): every step is a solve.
pub const MAX_LOAD_STEPS: usize = 100_000;
/// Most elements per circular hole (`bem.elements_per_circle`).
pub const MAX_ELEMENTS_PER_CIRCLE: usize = 100_000;
/// Most contour points of the J integral (`bem.j_contour.points`).
pub const MAX_CONTOUR_POINTS: usize = 100_000;
/// Most PD nodes across the body (`pd.nx`).
pub const MAX_PD_NX: usize = 100_000;
/// Most real PD nodes per window side (`coupling.n`).
pub const MAX_WINDOW_N: usize = 5_000;
/// Most coupling iterations (`coupling.max_iter`).
pub const MAX_COUPLING_ITER: usize = 100_000;
/// Most iterations of a PD solver (`pd.solver.max_iter`, `max_adr`, `max_newton`).
pub const MAX_SOLVER_ITER: usize = 100_000_000;
/// Most loading steps of a PD solver phase (`pd.solver.implicit_steps`, `explicit_steps`).
pub const MAX_SOLVER_STEPS: usize = 1_000_000;
/// Most elements per growth extension (`growth.elements_per_extension`).
pub const MAX_ELEMENTS_PER_EXTENSION: usize = 10_000;
/// Most points of one output grid (`outputs.grids.<i>.nx * ny`).
pub const MAX_GRID_POINTS: usize = 1_000_000;
/// Most points of one output line (`outputs.lines.<i>.n`).
pub const MAX_LINE_POINTS: usize = 1_000_000;
/// Largest coordinate magnitude of an output grid or line (m).
pub const MAX_COORDINATE: f64 = 1e12;

/// Checks every bound of this module.
pub fn check(c: &mut Checker, scene: &Scene) {
    at_most(
        c,
        "load.count",
        scene.load.count,
        MAX_LOAD_STEPS,
        "load steps (each is a solve)",
    );
    if let Some(n) = scene.bem.elements_per_circle {
        at_most(
            c,
            "bem.elements_per_circle",
            n,
            MAX_ELEMENTS_PER_CIRCLE,
            "elements per circle",
        );
    }
    at_most(
        c,
        "bem.j_contour.points",
        scene.bem.j_contour.points,
        MAX_CONTOUR_POINTS,
        "contour points",
    );
    if let Some(pd) = &scene.pd {
        if let Some(nx) = pd.nx {
            at_most(c, "pd.nx", nx, MAX_PD_NX, "PD nodes across the body");
        }
        check_solver(c, &pd.solver);
    }
    if let Some(co) = &scene.coupling {
        at_most(
            c,
            "coupling.n",
            co.n,
            MAX_WINDOW_N,
            "PD nodes per window side",
        );
        at_most(
            c,
            "coupling.max_iter",
            co.max_iter,
            MAX_COUPLING_ITER,
            "coupling iterations",
        );
    }
    if let Some(g) = &scene.growth {
        at_most(
            c,
            "growth.elements_per_extension",
            g.elements_per_extension,
            MAX_ELEMENTS_PER_EXTENSION,
            "elements per extension",
        );
    }
    for (i, cr) in scene.cracks.iter().enumerate() {
        file_name(c, &format!("cracks.{i}.name"), &cr.name, "path_<tip>.csv");
    }
    check_samplers(c, scene);
}

fn check_solver(c: &mut Checker, solver: &PdSolver) {
    let iters: Vec<(&str, usize)> = match solver {
        PdSolver::Adr(p) => vec![("max_iter", p.max_iter)],
        PdSolver::Implicit(p) => vec![("max_iter", p.max_iter)],
        PdSolver::Switching(p) => vec![("max_newton", p.max_newton), ("max_adr", p.max_adr)],
        PdSolver::Explicit(p) => {
            at_most(
                c,
                "pd.solver.snapshots",
                p.snapshots.len(),
                pdbem_pd::dynamics::MAX_SNAPSHOTS,
                "damage snapshots",
            );
            Vec::new()
        }
    };
    for (f, v) in iters {
        at_most(
            c,
            &format!("pd.solver.{f}"),
            v,
            MAX_SOLVER_ITER,
            "iteration cap",
        );
    }
    if let PdSolver::Switching(p) = solver {
        for (f, v) in [
            ("implicit_steps", p.implicit_steps),
            ("explicit_steps", p.explicit_steps),
        ] {
            at_most(
                c,
                &format!("pd.solver.{f}"),
                v,
                MAX_SOLVER_STEPS,
                "loading steps",
            );
        }
    }
}

/// Grids and lines: bounded point counts, coordinates within [`MAX_COORDINATE`], safe names.
fn check_samplers(c: &mut Checker, scene: &Scene) {
    let o = &scene.outputs;
    for (i, g) in o.grids.iter().enumerate() {
        let path = format!("outputs.grids.{i}");
        file_name(c, &format!("{path}.name"), &g.name, "grid_<name>.csv");
        let points = g.nx.saturating_mul(g.ny);
        if points > MAX_GRID_POINTS {
            c.fail(
                format!("{path}.ny"),
                g.ny,
                format!(
                    "grid of {} x {} points: nx * ny must be at most {MAX_GRID_POINTS}",
                    g.nx, g.ny
                ),
            );
        }
        coordinates(c, &format!("{path}.from"), g.from);
        coordinates(c, &format!("{path}.to"), g.to);
    }
    for (i, l) in o.lines.iter().enumerate() {
        let path = format!("outputs.lines.{i}");
        file_name(c, &format!("{path}.name"), &l.name, "line_<name>.csv");
        at_most(
            c,
            &format!("{path}.n"),
            l.n,
            MAX_LINE_POINTS,
            "points on a line",
        );
        coordinates(c, &format!("{path}.from"), l.from);
        coordinates(c, &format!("{path}.to"), l.to);
    }
}

fn coordinates(c: &mut Checker, path: &str, p: crate::scene::Pt) {
    if !(p.0.abs() <= MAX_COORDINATE && p.1.abs() <= MAX_COORDINATE) {
        c.fail(
            path,
            format!("({}, {})", p.0, p.1),
            format!("coordinates must be finite and at most {MAX_COORDINATE:e} m in magnitude"),
        );
    }
}

/// Requires `v <= max`.
pub fn at_most(c: &mut Checker, path: &str, v: usize, max: usize, what: &str) -> bool {
    if v > max {
        c.fail(path, v, format!("{what} must be at most {max}"));
        return false;
    }
    true
}

/// A name that becomes part of an output file name (`pattern`): letters, digits, '_'
/// and '-' (cracks also may not use '.', faces are `<crack>.upper`), not empty.
fn file_name(c: &mut Checker, path: &str, name: &str, pattern: &str) {
    let ok = super::safe_file_name(name);
    if !ok {
        c.fail(
            path,
            format!("{name:?}"),
            format!("use letters, digits, '_', '-', '.' only, not empty and not starting with '.' (it names the output file {pattern})"),
        );
    }
}

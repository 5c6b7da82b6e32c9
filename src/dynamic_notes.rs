//! The notes of an explicit-dynamics run ([`crate::run_dynamic`], [`crate::run_adaptive`]):
//! damage by loaded edges without the surface correction, an energy balance that does not
//! close, and pieces that carry loads they cannot (loaded layers torn off, a body cut
//! apart; [`pdbem_pd::pieces`]).

use pdbem_pd::dynamics::crack::{damaged_near_edges, EDGE_DAMAGE};
use pdbem_pd::dynamics::{DynamicRecord, ExplicitParams};
use pdbem_pd::geometry::dist_point_polyline;
use pdbem_pd::pieces::Piece;
use pdbem_pd::{BoundaryCondition, PdProblem};

/// The note of a run without `pd.surface_correction` whose traction-loaded edges took
/// damage: the nodes past [`EDGE_DAMAGE`] within a horizon of a `Traction` condition's
/// edge at the end. Without the correction the rows by a free edge are softer than the
/// bulk, and under a load held on that edge they can break in bands that are no part of
/// the crack (seed 004's coarse branching plate at 2 MPa: 46 such nodes, 4 with the
/// correction, the corners of the loaded layers; `docs/seed004.md`).
pub(crate) fn loaded_edge_damage_note(
    problem: &PdProblem,
    x: &[[f64; 2]],
    phi: &[f64],
) -> Option<String> {
    if problem.surface_correction {
        return None;
    }
    let edges = traction_edges(problem);
    let near = damaged_near_edges(x, phi, &edges, problem.horizon());
    (near > 0).then(|| {
        format!(
            "{near} nodes past damage {EDGE_DAMAGE} lie within a horizon of the traction-loaded edges at the end; without pd.surface_correction the rows by a free edge are softer than the bulk and can break there in bands that are no part of the crack (seed 004's coarse branching plate at 2 MPa: 46 such nodes, 4 with the correction): look at the damage plot, or run with `surface_correction: true`"
        )
    })
}

/// The edges of the problem's `Traction` conditions.
fn traction_edges(problem: &PdProblem) -> Vec<&[[f64; 2]]> {
    problem
        .boundary
        .iter()
        .filter_map(|bc| match bc {
            BoundaryCondition::Traction { edge, .. } => Some(edge.as_slice()),
            _ => None,
        })
        .collect()
}

/// Largest negative dissipation, as a fraction of the run's largest energy, that passes
/// without a note: the integrator's energy error (1.3e-2 of the energy over 4000 steps at
/// 0.5 dt_c in the free-vibration test, second order in dt) with a margin.
pub const NEGATIVE_FRACTURE_LIMIT: f64 = 0.05;

/// The note of a run whose energy balance's dissipation (the fracture energy of the
/// records) fell below zero by more than [`NEGATIVE_FRACTURE_LIMIT`] of the largest energy
/// of the run (work of the loads, kinetic or strain energy): fracture cannot create
/// energy, so the balance did not close (a step too large for the run's stiffness, or
/// strains beyond the small-strain model).
pub(crate) fn energy_balance_note(records: &[DynamicRecord]) -> Option<String> {
    let scale = records
        .iter()
        .map(|r| r.external_work.abs().max(r.kinetic).max(r.strain))
        .fold(0.0f64, f64::max);
    let worst = records
        .iter()
        .min_by(|a, b| a.fracture.total_cmp(&b.fracture))?;
    (scale > 0.0 && worst.fracture < -NEGATIVE_FRACTURE_LIMIT * scale).then(|| {
        format!(
            "the energy balance does not close: its dissipation (the fracture energy) is {:.3e} J at {:.3e} s, negative by {:.1} % of the run's largest energy {scale:.3e} J; fracture cannot create energy, so the time step is too large for the run or its strains leave the small-strain model: take a smaller dt and check the loads",
            worst.fracture,
            worst.time,
            -100.0 * worst.fracture / scale
        )
    })
}

/// Share of the loads' total magnitude that a piece must carry unbalanced to count as
/// loose in [`loose_pieces`] (round-off of a balanced body is about 1e-15 of it).
pub(crate) const LOOSE_LOAD_SHARE: f64 = 1e-6;

/// What [`loose_pieces`] found.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Loose {
    /// Loose pieces wholly within a horizon and a cell of a traction-loaded edge: loaded
    /// layers torn off the body (count, nodes, share of the loads unbalanced).
    pub layers: (usize, usize, f64),
    /// The other loose pieces: parts of a body cut apart (count, share).
    pub parts: (usize, f64),
    /// Pieces in all.
    pub pieces: usize,
}

/// Share of the loads that torn layers must carry away for [`loose_pieces_notes`] to
/// take the run's crack measures as those of a body the loads let go.
pub(crate) const TORN_MOST: f64 = 0.5;

impl Loose {
    /// Whether torn layers carry more than [`TORN_MOST`] of the loads away.
    pub fn torn_most(&self) -> bool {
        self.layers.2 > TORN_MOST
    }
}

/// Sorts the pieces whose unbalanced load passes [`LOOSE_LOAD_SHARE`] of the loads'
/// total magnitude into torn layers and cut parts. `x` holds the nodes' reference
/// positions (indexed as the pieces' nodes) and `held(i)` says whether node `i` has its
/// velocity held (an impactor: its piece is not free).
pub(crate) fn loose_pieces(
    pieces: &[Piece],
    x: &[[f64; 2]],
    problem: &PdProblem,
    held: impl Fn(usize) -> bool,
) -> Loose {
    let total: f64 = pieces.iter().map(|p| p.load).sum();
    let edges = traction_edges(problem);
    let reach = problem.horizon() + problem.dx;
    let mut out = Loose {
        pieces: pieces.len(),
        ..Default::default()
    };
    if total.is_nan() || total <= 0.0 {
        return out;
    }
    for p in pieces {
        let share = p.unbalanced() / total;
        if share.is_nan() || share <= LOOSE_LOAD_SHARE || p.nodes.iter().any(|&i| held(i)) {
            continue;
        }
        let layer = p.nodes.iter().all(|&i| {
            x.get(i)
                .is_some_and(|&q| edges.iter().any(|e| dist_point_polyline(q, e) <= reach))
        });
        if layer {
            out.layers.0 += 1;
            out.layers.1 += p.nodes.len();
            out.layers.2 += share;
        } else {
            out.parts.0 += 1;
            out.parts.1 += share;
        }
    }
    out
}

/// The notes on [`Loose`] pieces at the end of a run (none without any): torn layers,
/// whose wording turns into the run's refusal when they carry most of the loads away
/// ([`Loose::torn_most`]), and parts of a body cut apart. `s0` is the bonds' critical
/// stretch (unbreakable: `None`), `load` the run's load factor and `last` its last
/// record (the kinetic energy's share of the loads' work).
pub(crate) fn loose_pieces_notes(
    loose: &Loose,
    problem: &PdProblem,
    s0: Option<f64>,
    load: f64,
    last: &DynamicRecord,
) -> Vec<String> {
    let kinetic = if last.external_work > 0.0 {
        format!(
            " (kinetic energy {:.1} % of the loads' work at the end)",
            100.0 * last.kinetic / last.external_work
        )
    } else {
        String::new()
    };
    let mut notes = Vec::new();
    let (n, nodes, share) = loose.layers;
    if n > 0 {
        let strain = nominal_strain(problem) * load.abs();
        let cause = match s0 {
            Some(s0) if s0 > 0.0 => format!(
                "the loads' nominal strain |t| / E = {strain:.3e} is {:.3} times the bonds' critical stretch s0 = {s0:.3e} (a step load's first waves strain the body to about twice |t| / E)",
                strain / s0
            ),
            _ => format!("the loads' nominal strain |t| / E is {strain:.3e}"),
        };
        let torn = format!(
            "{n} piece(s) of {nodes} node(s), each within a horizon and a cell of a traction-loaded edge, hold no intact bond to the rest of the body and carry {:.1} % of the loads away unbalanced",
            100.0 * share
        );
        notes.push(if loose.torn_most() {
            format!(
                "the loads tore off the layers they act on: at the end {torn}, so they accelerate away{kinetic} and the loads no longer reach the crack. The crack measures (tip, branch and boundary times) are those of a body the loads let go, and the deflection angles are left out. {}: check material.fracture.g_c or the failure law, and the loads' units (Pa)",
                capitalised(&cause)
            )
        } else {
            format!(
                "parts of the loaded layers tore off: at the end {torn}; the loads on them no longer reach the body. Loaded edges break so where the waves of the step load meet at corners or where a crack reaches them, and on a grid too coarse for the load (seed 004's 2 MPa plate on its coarse grid, dx = 1 mm); {cause}: look at the damage plot"
            )
        });
    }
    let (n, share) = loose.parts;
    if n == 1 && loose.pieces == loose.layers.0 + 1 {
        // No crack cut the body: the one piece besides torn layers is the body itself.
        notes.push(format!(
            "the loads on the body do not balance: at the end it carries {:.1} % of the loads unbalanced and moves away as a whole under them{kinetic}; the crack measures are those of a body in flight (`pdbem check` gives the loads' resultant)",
            100.0 * share
        ));
    } else if n > 0 {
        notes.push(format!(
            "the body is cut apart: at the end {n} of its {} pieces carry {:.1} % of the loads unbalanced and move away under the loads held on them{kinetic}; from when the crack cut through, the run follows pieces in flight, not a crack in a loaded body",
            loose.pieces,
            100.0 * share
        ));
    }
    notes
}

/// `s` with its first letter in upper case.
fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
}

/// Per node at reference position `x`, whether a region velocity with `hold` keeps its
/// velocity (a prescribed motion: its piece is not free).
pub(crate) fn held_by_velocity(p: &ExplicitParams, x: &[[f64; 2]], delta: f64) -> Vec<bool> {
    x.iter()
        .map(|&q| {
            // A node in several boxes takes the last one's velocity.
            p.velocities
                .iter()
                .rev()
                .find(|r| r.region.contains(q, delta))
                .is_some_and(|r| r.hold)
        })
        .collect()
}

/// `pdbem check`'s note on an explicit run whose step load strains the body past its
/// bonds' critical stretch `s0` (the largest traction's |t| / E at load factor `load`):
/// then the bonds along the load break wherever it reaches, before any crack grows, and
/// the loaded layers tear off (the run notes that, [`loose_pieces_notes`]). `None` below
/// it, without tractions or with unbreakable bonds.
pub(crate) fn overload_note(problem: &PdProblem, s0: f64, load: f64) -> Option<String> {
    let strain = nominal_strain(problem) * load.abs();
    (s0.is_finite() && s0 > 0.0 && strain >= s0).then(|| {
        format!(
            "pd.solver: the step load's nominal strain |t| / E = {strain:.3e} is {:.3} times the bonds' critical stretch s0 = {s0:.3e}: the bonds along the load break wherever it reaches before a crack can grow, and the loaded layers tear off; check material.fracture.g_c or the failure law, and the loads' units (Pa)",
            strain / s0
        )
    })
}

/// The largest `Traction` condition's |t| / E at load factor 1.
fn nominal_strain(problem: &PdProblem) -> f64 {
    problem
        .boundary
        .iter()
        .filter_map(|bc| match bc {
            BoundaryCondition::Traction { traction, .. } => Some(traction[0].hypot(traction[1])),
            _ => None,
        })
        .fold(0.0, f64::max)
        / problem.youngs_modulus
}

#[cfg(test)]
#[path = "dynamic_notes_tests.rs"]
mod tests;

//! Refined windows in growth (`coupling.refine`, seed 004 section 3 applied to the tip
//! window): the crack grows only through the window's finest cells, and the window moves
//! on before its tip leaves them.
//!
//! - [`protect_coarse`]: in a window with a refinement zone, every bond between two nodes
//!   coarser than the finest level is unbreakable (the no-fail flag of the interface
//!   band, [`super::tips::protect_band`]), so no crack grows through coarse cells. Bonds
//!   between a fine and a coarse node still break: on dual horizons a coarse node's
//!   family reaches a coarse horizon into the zone, and its bonds across the crack line
//!   must open for the tip to reach the end of the fine cells (protecting them was
//!   measured to arrest the tension plate's crack 0.175 m short of the zone's end). The
//!   crack behind the tip is the window's pre-crack cut.
//! - [`leaves_fine_zone`]: the tip is within [`ZONE_MARGIN`] finest spacings (measured to
//!   the cell edge, `|x_j - tip| - dx_j / 2`) of a coarser node ahead of it (on the side
//!   its path points to). That triggers the window move like the interface margin does;
//!   the moved window centres its zone on the tip again ([`crate::pd_window::zone_centre`]).
//! - [`precrack_in_fine_cells`]: after a move the window's pre-crack (the path up to one
//!   coarse dx short of the tip, [`super::relocate::extend_crack`]) must end inside the
//!   new zone's fine cells: the ligament between its end and the tip then has no bond
//!   between two coarse nodes (those would seal the crack, unbreakable and not copied as
//!   broken). Otherwise the move is refused with the largest move distance that works
//!   ([`max_move_distance`], which `pdbem check` also applies).
//! - [`follow_tip`]: a window moves along the growth direction, so it keeps its lateral
//!   place, and its sides hold its zone within [`crate::pd_window::zone_room`] of its
//!   centre; a moved refined window whose tip lies further aside than that also moves
//!   sideways to the tip (whole cells), so a tip drifting off a window's centre line stays
//!   in the fine cells.
//! - Windows against the outline whose outer sides are free
//!   ([`crate::pd_window::open_sides`]) keep the rules, with three differences: their
//!   zone may reach those sides (the crack must run through fine cells to the edge); the
//!   fine-zone trigger rebuilds the window where it is with its pre-crack extended and its
//!   zone re-centred on the tip ([`zone_moves_on`], `Growth::rezone_in_place`), since the
//!   window cannot move on; and a window placed with its tip short of its zone (its
//!   interface sides keep the zone two horizons away) lets the crack grow through coarse
//!   cells into the zone first (no protection, no trigger while coarser cells lie within
//!   the margin behind the tip). Measured on `cases/growth_tension_edge_refined.ron`: the
//!   last 0.4 m to the bottom edge stayed within 0.001 m of the line (0.021 m through
//!   coarse cells before).
//! - Windows with a loaded or held outer side, and windows holding several tips (merged
//!   windows, a central crack), keep neither rule: their zone cannot reach that side, or
//!   sits on one tip ([`crate::pd_window::tip_of`]) while the others must grow through
//!   coarse cells.
//!
//! Why: measured on `growth_tension_edge` (straight mode-I path along x = 10 m), a 2 m
//! window with a 0.3 m level-1 zone whose tip ran on past the zone into the coarse cells
//! before the window moved drifted 0.16-0.28 m (3-6 fine dx) off the line, while a 3 m
//! window whose zone held the tip's whole run stayed within 0.021 m
//! (docs/coupled_refined.md). A crack crossing the size jump meets the jump's spurious
//! forces and the coarse cells' lower resolution; a crack kept inside the fine cells does
//! not.

use pdbem_bem::V2;
use pdbem_pd::crack_path::CrackPath;

use crate::growth::relocate::{snap, thin_strips};
use crate::growth::tips::{margins, near_interface_side};
use crate::pd_window::{open_sides, tip_of, zone_centre, zone_room, WindowRefine};
use crate::setup::WindowModel;
use crate::window::{Body, SideKind, Window, WindowSpec};

/// Distance (in finest spacings, to the nearest coarser cell's edge) at which a tip has
/// reached the end of its fine zone: the tip node is the farthest node with phi above the
/// threshold, one or two fine rows behind the true tip, and the breaking rounds of one
/// coupling iteration advance it a few fine rows; 2.5 keeps the tip's own cell and its
/// neighbours fine.
pub const ZONE_MARGIN: f64 = 2.5;

/// The finest node spacing of a mixed window grid that holds one crack tip and whose
/// outer sides, if any, are free ([`crate::pd_window::open_sides`]: the zone can follow
/// the tip up to them); `None` for a uniform grid, a window with a loaded or held outer
/// side, or one holding several tips (module docs) (m).
pub fn finest_spacing(wm: &WindowModel) -> Option<f64> {
    let g = wm.model.grid();
    if !g.is_mixed() || tips_inside(wm) != 1 {
        return None;
    }
    let open = open_sides(&wm.window, &wm.problem.boundary);
    (0..4)
        .all(|k| wm.window.sides[k] == SideKind::Interface || open[k])
        .then(|| g.spacing.iter().copied().fold(f64::INFINITY, f64::min))
}

/// Whether window `wm` has an outer side: its fine-zone trigger re-zones it in place
/// when the zone can move on ([`zone_moves_on`]), and moves it otherwise.
pub fn against_outline(wm: &WindowModel) -> bool {
    wm.window.sides.contains(&SideKind::Outer)
}

/// Where the refinement zone of `wm` (setting `r`) goes when the window is rebuilt in
/// place for a tip whose traced path is `path` and whose pre-crack then ends one window
/// spacing short of the tip ([`super::relocate::extend_crack`]), if that is at least one
/// finest spacing from where it is now; `None` when it would stay (or the window has no
/// zone, or the path no point).
pub fn zone_moves_on(wm: &WindowModel, r: WindowRefine, path: &[V2]) -> Option<V2> {
    if path.is_empty() {
        return None;
    }
    let fine = finest_spacing(wm)?;
    let now = wm.problem.refine_zones.first()?.centre;
    let total = pdbem_geometry::polyline_length(path);
    let end = pdbem_geometry::point_at(path, (total - wm.window.spec.dx).max(0.0));
    let open = open_sides(&wm.window, &wm.problem.boundary);
    let c = zone_centre(&wm.window, end, r, open);
    ((c - V2::new(now[0], now[1])).norm() >= fine).then_some(c)
}

/// The window `moved` (window `old` moved along the growth direction `dir`,
/// [`super::relocate::moved_spec`]) also moved sideways to its tip at `tip`, when the tip
/// lies further off the window's centre line than the zone `r` can follow it
/// ([`zone_room`]) by half a cell or more, and the window so moved still fits (in the body,
/// the tip clear of its interface margin, no strip of BEM body thinner than
/// [`super::relocate::MIN_STRIP`] sides that `moved` did not leave). A move along the growth direction alone keeps
/// the window's lateral place (each move's sideways part rounds to no cell), so a tip
/// drifting sideways left a zone that its sides hold at the window centre: on
/// `growth_hole_edge` with a 4 mm window of 20 cells and a 0.6 mm zone, the tip 0.36 mm
/// off the line ran the window on without the zone until the run ended at load step 72.
pub fn follow_tip(
    old: &Window,
    moved: WindowSpec,
    tip: V2,
    dir: V2,
    r: WindowRefine,
    body: &Body,
    ratio: f64,
) -> WindowSpec {
    let dx = old.spec.dx;
    let across = V2::new(-dir.y, dir.x);
    let off = (tip - moved.center).dot(&across);
    if off.abs() < zone_room(old, r) + 0.5 * dx {
        return moved;
    }
    let (e1, e2) = old.axes();
    let mut spec = moved.clone();
    spec.center += snap(off * across, e1, e2, dx);
    let strips = |s: &WindowSpec| thin_strips(s, &body.outline).len();
    match Window::place(0, spec.clone(), body) {
        Ok(w)
            if w.contains(tip, -0.5 * dx)
                && !near_interface_side(&w, tip, margins(&w, ratio).1)
                && strips(&spec) <= strips(&moved) =>
        {
            spec
        }
        _ => moved,
    }
}

/// Why the pre-crack of a moved window `w` (zone `r`, moved by `move_distance`) ends at
/// `end`, outside its fine cells ([`precrack_in_fine_cells`]): a move longer than
/// [`max_move_distance`], or else a tip where the zone cannot reach from where the
/// window's sides hold it.
pub fn outside_reason(w: &Window, end: V2, r: WindowRefine, move_distance: f64) -> String {
    let max = max_move_distance(
        w.spec.nx.min(w.spec.ny),
        w.spec.dx,
        w.delta(),
        r.half_size,
        r.levels,
    );
    let cause = if move_distance > max {
        format!(
            "move_distance {move_distance} m is too long for coupling.refine (half_size {} m, levels {}); at most {max:.4} m for this window",
            r.half_size, r.levels
        )
    } else {
        format!(
            "the zone (coupling.refine half_size {} m, levels {}) cannot reach it from where the window's sides hold it; a larger window (coupling.side, n) gives the zone room",
            r.half_size, r.levels
        )
    };
    format!(
        "the moved window's pre-crack ends at ({:.4}, {:.4}), outside its refinement zone's fine cells, so unbreakable coarse bonds would seal the crack behind the tip: {cause}",
        end.x, end.y
    )
}

/// Pre-crack ends of `wm` more than half a spacing inside the window: its crack tips.
fn tips_inside(wm: &WindowModel) -> usize {
    let w = &wm.window;
    let (lx, ly) = w.size();
    let m = 0.5 * w.spec.dx;
    wm.problem
        .cracks
        .iter()
        .flat_map(|c| [c.first(), c.last()])
        .flatten()
        .filter(|p| {
            let q = w.to_local(V2::new(p[0], p[1]));
            q.x > m && q.x < lx - m && q.y > m && q.y < ly - m
        })
        .count()
}

/// Whether node `i` of window `wm` (finest spacing `fine`) is coarser than the finest level.
fn coarse(wm: &WindowModel, i: usize, fine: f64) -> bool {
    wm.model.grid().node_dx(i) > 1.5 * fine
}

/// Marks every intact bond between two nodes coarser than the finest level unbreakable
/// (module docs), once the window's pre-crack ends in its fine cells (a window against
/// the outline may hold its tip short of a zone that its interface sides keep away from
/// it: its crack grows into the zone first, [`leaves_fine_zone`]). Returns the directed
/// bonds marked (0 on a uniform grid).
pub fn protect_coarse(wm: &mut WindowModel) -> usize {
    let Some(fine) = finest_spacing(wm) else {
        return 0;
    };
    let cracks: Vec<Vec<V2>> = wm
        .problem
        .cracks
        .iter()
        .map(|c| c.iter().map(|p| V2::new(p[0], p[1])).collect())
        .collect();
    if !in_fine_cells(wm, fine, tip_of(&wm.window, &cracks)) {
        return 0;
    }
    let flags: Vec<bool> = (0..wm.model.grid().len())
        .map(|i| coarse(wm, i, fine))
        .collect();
    wm.model.protect_pairs(|i, j| flags[i] && flags[j])
}

/// Whether a coarser node of `wm` lies within `reach` (m, to its cell edge) of `tip` on the
/// side of `dir` (`ahead`) or the other side.
fn coarse_within(wm: &WindowModel, fine: f64, tip: V2, dir: V2, reach: f64, ahead: bool) -> bool {
    let g = wm.model.grid();
    (0..g.n_real).any(|j| {
        let d = V2::new(g.pos[j][0], g.pos[j][1]) - tip;
        coarse(wm, j, fine) && (d.dot(&dir) > 0.0) == ahead && d.norm() - 0.5 * g.node_dx(j) < reach
    })
}

/// Whether the tip at `tip`, growing along the unit vector `dir`, has reached the end of
/// the finest cells of window `wm` (module docs); always false on a uniform grid, and in
/// a window against the outline while the tip is still growing into its fine cells
/// (coarser cells within the margin behind it too).
pub fn leaves_fine_zone(wm: &WindowModel, tip: V2, dir: V2) -> bool {
    let Some(fine) = finest_spacing(wm) else {
        return false;
    };
    let reach = ZONE_MARGIN * fine;
    coarse_within(wm, fine, tip, dir, reach, true)
        && !(against_outline(wm) && coarse_within(wm, fine, tip, dir, reach, false))
}

/// Whether `p` lies in the fine cells of `wm` (finest spacing `fine`), more than half a
/// fine spacing from every coarser cell (window axes).
fn in_fine_cells(wm: &WindowModel, fine: f64, p: V2) -> bool {
    let (g, w) = (wm.model.grid(), &wm.window);
    let p = w.to_local(p);
    !(0..g.n_real).any(|j| {
        let d = w.to_local(V2::new(g.pos[j][0], g.pos[j][1])) - p;
        coarse(wm, j, fine) && d.x.abs().max(d.y.abs()) - 0.5 * g.node_dx(j) < 0.5 * fine
    })
}

/// Whether the pre-crack end `macro_tip` of a freshly moved window `wm` lies in its fine
/// cells ([`in_fine_cells`]); true where the rule does not apply (module docs), and for a
/// window against the outline, whose crack may first grow into its zone.
pub fn precrack_in_fine_cells(wm: &WindowModel, macro_tip: V2) -> bool {
    match finest_spacing(wm) {
        Some(fine) => against_outline(wm) || in_fine_cells(wm, fine, macro_tip),
        None => true,
    }
}

/// The largest move distance (m) for which a refined window of `n` x `n` cells of spacing
/// `dx`, horizon `delta` and zone `(half_size, levels)` keeps its tip in the fine cells
/// from one move to the next (module docs), for a straight crack through the window
/// centre along a window axis: the zone centre sits on the cell corner nearest the tip
/// within the room the window leaves it ([`crate::pd_window::zone_centre`]), its finest
/// cells are those whose centres lie within `half_size / levels`, the tip triggers the
/// move [`ZONE_MARGIN`] fine spacings short of their end (or later), and the pre-crack,
/// one coarse dx shorter, must end half a fine spacing inside the next zone. Zero when no
/// move works or `levels` is out of range.
pub fn max_move_distance(n: usize, dx: f64, delta: f64, half_size: f64, levels: u32) -> f64 {
    if !(1..=pdbem_pd::mixed::MAX_LEVELS).contains(&levels) {
        return 0.0;
    }
    let fine = dx / f64::from(1u32 << levels);
    let extent = dx * (half_size / f64::from(levels) / dx + 0.5 + 1e-9).floor();
    // Corner lattice relative to the window centre: k dx (n even) or (k + 1/2) dx.
    let offset = if n.is_multiple_of(2) { 0.0 } else { 0.5 * dx };
    let room = 0.5 * n as f64 * dx - (half_size + 0.5 * dx + 2.0 * delta);
    let lattice = |v: f64| ((v - offset) / dx).round() * dx + offset;
    let centre = |t: f64| {
        let lo = ((-room - offset) / dx - 1e-9).ceil() * dx + offset;
        let hi = ((room - offset) / dx + 1e-9).floor() * dx + offset;
        if lo > hi {
            0.0
        } else {
            lattice(t).clamp(lo, hi)
        }
    };
    // The earliest trigger (a tip that overshoots it lands deeper in the next zone).
    let stop = extent - ZONE_MARGIN * fine;
    let back = dx + 0.5 * fine;
    let fits = |d: f64| {
        let mut c = centre(0.0);
        (0..16).all(|_| {
            let t = c - stop + d;
            c = centre(t);
            t <= c + extent - back && t >= c - stop - 1e-12 * dx
        })
    };
    if extent <= back || !fits(0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 2.0 * extent);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// [`leaves_fine_zone`] for a traced `path` in `wm`, growing along the chord of its last
/// `direction_length` window spacings; false for an empty path or one of zero length.
pub fn path_leaves_fine_zone(wm: &WindowModel, path: &CrackPath, direction_length: f64) -> bool {
    if path.is_empty() || finest_spacing(wm).is_none() {
        return false;
    }
    let t = path.tip();
    path.tip_direction(direction_length * wm.window.spec.dx)
        .is_some_and(|d| leaves_fine_zone(wm, V2::new(t[0], t[1]), V2::new(d[0], d[1])))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::plate_setup;
    use crate::pd_window::WindowRefine;
    use crate::setup::build;

    /// The windows (dx = 0.05, side 1 m, on the tips) of the crack `points` in the seed's
    /// plate, refined by a level-1 zone of half side 0.15 m when `refined`.
    fn windows(points: Vec<V2>, refined: bool) -> Vec<WindowModel> {
        let mut s = plate_setup((20.0, 10.0), vec![], vec![points], None);
        s.layout.pd.refine = refined.then_some(WindowRefine {
            half_size: 0.15,
            levels: 1,
        });
        build(&s.layout, |_, _| Vec::new()).unwrap().windows
    }

    /// The 1 m window on the tip (10, 8) of a crack from the top edge, refined: fine cells
    /// (dx 0.025) over [9.85, 10.15] x [7.85, 8.15].
    fn window() -> WindowModel {
        windows(vec![V2::new(10.0, 10.0), V2::new(10.0, 8.0)], true).remove(0)
    }

    #[test]
    fn bonds_between_coarse_nodes_do_not_break() {
        let mut wm = window();
        assert!(protect_coarse(&mut wm) > 0);
        let m = &wm.model;
        let (g, intact) = (m.grid(), m.bond_intact());
        let mut fine_pairs = 0;
        for i in 0..g.len() {
            for b in m.bonds().row(i) {
                let j = m.bonds().nbr[b] as usize;
                let both_coarse = g.node_dx(i) > 0.03 && g.node_dx(j) > 0.03;
                if intact[b] == 0 {
                    continue; // the pre-crack cut
                }
                let protected = intact[b] == pdbem_pd::forces::NO_FAIL;
                assert_eq!(protected, both_coarse, "bond {i}-{j}");
                fine_pairs += usize::from(!both_coarse);
            }
        }
        assert!(fine_pairs > 0);
    }

    #[test]
    fn the_tip_triggers_before_it_reaches_the_coarse_cells_ahead() {
        let wm = window();
        let down = V2::new(0.0, -1.0);
        // Nearest coarse cell ahead: centre (10.025, 7.825), edge 0.1 m below the tip.
        assert!(!leaves_fine_zone(&wm, V2::new(10.0, 7.95), down));
        // 0.054 m (2.2 fine dx) from that cell's edge: within the margin of 2.5.
        assert!(leaves_fine_zone(&wm, V2::new(10.0, 7.9), down));
        // The same point growing away from the edge does not trigger.
        assert!(!leaves_fine_zone(&wm, V2::new(10.0, 7.9), -down));
        // A uniform window never does.
        let uniform = windows(vec![V2::new(10.0, 10.0), V2::new(10.0, 8.0)], false).remove(0);
        assert!(!leaves_fine_zone(&uniform, V2::new(10.0, 7.6), down));
        // Nor a window holding two tips (a central crack from (9.8, 8) to (10.2, 8)):
        // the zone sits on one of them, the other grows through coarse cells.
        let mut two = windows(vec![V2::new(9.8, 8.0), V2::new(10.2, 8.0)], true);
        assert_eq!(two.len(), 1, "one window for both tips");
        let two = &mut two[0];
        assert!(two.model.grid().is_mixed());
        assert_eq!(protect_coarse(two), 0);
        assert!(!leaves_fine_zone(
            two,
            V2::new(10.3, 8.0),
            V2::new(1.0, 0.0)
        ));
        // A pre-crack ending in the fine cells, at their edge, in a coarse cell.
        assert!(precrack_in_fine_cells(&wm, V2::new(10.0, 8.13)));
        assert!(!precrack_in_fine_cells(&wm, V2::new(10.0, 8.145)));
        assert!(!precrack_in_fine_cells(&wm, V2::new(10.0, 8.2)));
    }

    #[test]
    fn the_largest_move_keeps_the_tip_in_the_fine_cells() {
        // 2 m window (20 cells of 0.1 m), delta 0.3015, zone 0.3 m level 1: fine cells
        // reach 0.3 m from the centre, which has 0.047 m of room, less than a cell: the
        // zone stays at the window centre. The tip triggers 0.175 m past it and its
        // pre-crack, 0.1 m shorter, must end 0.025 m inside the 0.3 m: at most 0.35 m.
        let d = max_move_distance(20, 0.1, 0.3015, 0.3, 1);
        assert!((d - 0.35).abs() < 1e-6, "{d}");
        // A zone of one cell: no move keeps the pre-crack's end in it.
        assert_eq!(max_move_distance(20, 0.1, 0.3015, 0.05, 1), 0.0);
        // 3 m window, zone 0.55 m (fine cells to 0.6 m, 0.3 m of room): the 0.5 m move of
        // the tension plate fits.
        assert!(max_move_distance(30, 0.1, 0.3015, 0.55, 1) > 0.5);
        // Levels the mixed grid does not build: none (and no overflowing shift).
        assert_eq!(max_move_distance(30, 0.1, 0.3015, 0.55, 0), 0.0);
        assert_eq!(max_move_distance(30, 0.1, 0.3015, 0.55, 40), 0.0);
    }

    /// The 1 m window [9.5, 10.5] x [0, 1] against the bottom edge of the seed's plate on a
    /// crack from the top edge to (10, 0.8), refined by a level-1 zone of half side 0.15 m,
    /// with `outer` on its outer side.
    fn outline_window(outer: Vec<crate::pd_window::EdgeCondition>) -> WindowModel {
        let pts = vec![V2::new(10.0, 10.0), V2::new(10.0, 0.8)];
        let mut s = plate_setup((20.0, 10.0), vec![], vec![pts], None);
        s.layout.windows[0].center = V2::new(10.0, 0.5);
        s.layout.pd.refine = Some(WindowRefine {
            half_size: 0.15,
            levels: 1,
        });
        build(&s.layout, |_, _| outer.clone())
            .unwrap()
            .windows
            .remove(0)
    }

    #[test]
    fn a_zone_against_a_free_edge_follows_the_tip_to_it() {
        let mut wm = outline_window(Vec::new());
        let r = WindowRefine {
            half_size: 0.15,
            levels: 1,
        };
        assert!(against_outline(&wm));
        assert_eq!(
            open_sides(&wm.window, &wm.problem.boundary),
            [true, false, false, false]
        );
        assert_eq!(finest_spacing(&wm), Some(0.025));
        // The top interface side holds the zone's centre at y <= 0.525 (cells reach 0.175
        // from it, two horizons 0.3015 more): it sits at (10, 0.5), short of the
        // pre-crack's end at 0.8, so no coarse bond is protected until the crack has grown
        // into it, and a tip still growing towards it does not trigger.
        assert_eq!(wm.problem.refine_zones[0].centre, [10.0, 0.5]);
        assert_eq!(protect_coarse(&mut wm), 0);
        let down = V2::new(0.0, -1.0);
        assert!(!leaves_fine_zone(&wm, V2::new(10.0, 0.7), down));
        // In the zone (fine cells over [0.35, 0.65]), 0.05 m from its lower end: trigger.
        assert!(!leaves_fine_zone(&wm, V2::new(10.0, 0.45), down));
        assert!(leaves_fine_zone(&wm, V2::new(10.0, 0.4), down));
        // Re-zoned in place on the pre-crack end one window spacing behind the tip.
        let path = [V2::new(10.0, 1.0), V2::new(10.0, 0.4)];
        let c = zone_moves_on(&wm, r, &path).expect("the zone moves on");
        assert!((c - V2::new(10.0, 0.45)).norm() < 1e-9, "{c:?}");
        // Towards the free edge the zone reaches the side itself; towards an interface
        // side it keeps its two horizons.
        let open = [true, false, false, false];
        let low = zone_centre(&wm.window, V2::new(10.0, 0.1), r, open);
        assert!((low.y - 0.1).abs() < 1e-9, "{low:?}");
        let closed = zone_centre(&wm.window, V2::new(10.0, 0.1), r, [false; 4]);
        assert!((closed.y - 0.5).abs() < 1e-9, "{closed:?}");
        // A zone that would not move by a fine spacing stays.
        let short = [V2::new(10.0, 1.0), V2::new(10.0, 0.56)];
        assert!(zone_moves_on(&wm, r, &short).is_none());
        assert!(zone_moves_on(&wm, r, &[]).is_none());
    }

    #[test]
    fn a_held_outer_side_keeps_the_rule_off() {
        let held = crate::pd_window::EdgeCondition {
            from: V2::new(9.5, 0.0),
            to: V2::new(10.5, 0.0),
            traction: [None, None],
            displacement: [None, Some(0.0)],
            continues: [true, true],
        };
        let mut wm = outline_window(vec![held]);
        assert_eq!(open_sides(&wm.window, &wm.problem.boundary), [false; 4]);
        assert_eq!(finest_spacing(&wm), None);
        assert_eq!(protect_coarse(&mut wm), 0);
        assert!(!leaves_fine_zone(
            &wm,
            V2::new(10.0, 0.4),
            V2::new(0.0, -1.0)
        ));
    }
}

#[cfg(test)]
mod follow_tests {
    use super::*;
    use crate::growth::fixtures::{body, plate_setup};
    use crate::setup::build;

    /// A window moved along the growth direction keeps its lateral place; when the zone
    /// cannot follow the tip (the 1 m window of 20 cells leaves a 0.15 m zone no room) the
    /// window moves sideways to the tip, by whole cells.
    #[test]
    fn a_moved_window_follows_a_tip_that_drifts_sideways() {
        let pts = vec![V2::new(10.0, 10.0), V2::new(10.0, 8.0)];
        let mut s = plate_setup((20.0, 10.0), vec![], vec![pts], None);
        let r = WindowRefine {
            half_size: 0.15,
            levels: 1,
        };
        s.layout.pd.refine = Some(r);
        let w = build(&s.layout, |_, _| Vec::new())
            .unwrap()
            .windows
            .remove(0)
            .window;
        assert_eq!(zone_room(&w, r), 0.0);
        let down = V2::new(0.0, -1.0);
        let mut moved = w.spec.clone();
        moved.center += V2::new(0.0, -0.4);
        let at = |x: f64| follow_tip(&w, moved.clone(), V2::new(x, 7.7), down, r, &body(), 0.9);
        // Within half a cell of the centre line: the window stays on it.
        assert_eq!(at(w.spec.center.x + 0.024).center, moved.center);
        // 0.12 m (2.4 cells) aside: the window follows by 2 cells, to either side.
        let c = at(w.spec.center.x + 0.12).center - moved.center;
        assert!((c - V2::new(0.1, 0.0)).norm() < 1e-12, "{c:?}");
        let c = at(w.spec.center.x - 0.12).center - moved.center;
        assert!((c - V2::new(-0.1, 0.0)).norm() < 1e-12, "{c:?}");
        // A zone with room to follow (a 0.05 m zone in the same window) leaves it.
        let small = WindowRefine {
            half_size: 0.05,
            levels: 1,
        };
        let room = zone_room(&w, small);
        assert!(room > 0.09, "{room}");
        let stay = follow_tip(
            &w,
            moved.clone(),
            V2::new(w.spec.center.x + 0.12, 7.7),
            down,
            small,
            &body(),
            0.9,
        );
        assert_eq!(stay.center, moved.center);
        // Following would leave 0.2 m of BEM body (a fifth of the side, below MIN_STRIP)
        // between the window and the left edge: the window stays where its move put it.
        let mut near = w.spec.clone();
        near.center = V2::new(1.0, 7.6);
        let kept = follow_tip(&w, near.clone(), V2::new(0.7, 7.7), down, r, &body(), 0.9);
        assert_eq!(kept.center, near.center);
        // Away from the edge the same sideways drift is followed.
        near.center.x = 3.0;
        let c = follow_tip(&w, near.clone(), V2::new(2.7, 7.7), down, r, &body(), 0.9).center;
        assert!((c - V2::new(2.7, 7.6)).norm() < 1e-12, "{c:?}");
    }
}

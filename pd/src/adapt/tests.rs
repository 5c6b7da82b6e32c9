use std::collections::BTreeMap;

use super::measure::{child_displacement, node_measures};
use super::ramp::ramp_to_limit;
use super::transfer::{origins, refined_model, Origin};
use super::*;
use crate::cases::bar_tension;
use crate::geometry::P2;
use crate::problem::{Failure, Region};
use crate::solvers::implicit::ImplicitParams;
use crate::solvers::limit::tests::notched_bar;
use crate::solvers::limit_solvers::{solve_to_limit, QuasiStatic};

/// A free 40 mm square plate on a 2 mm grid, PMB.
fn square() -> PdProblem {
    let mut p = bar_tension(0.002).problem;
    p.region = Region::rectangle([0.0, 0.0], [0.04, 0.04]);
    p.boundary.clear();
    p
}

/// `u = H x + c`: a stretch, a shear and a rotation.
const H: [[f64; 2]; 2] = [[2e-3, 7e-4], [-3e-4, -5e-4]];
const C: P2 = [1e-5, -2e-5];

fn homogeneous(x: P2) -> P2 {
    [
        C[0] + H[0][0] * x[0] + H[0][1] * x[1],
        C[1] + H[1][0] * x[0] + H[1][1] * x[1],
    ]
}

fn with_field(p: &PdProblem) -> PdModel {
    let mut m = PdModel::new(p).unwrap();
    let u: Vec<P2> = m.positions().iter().map(|&x| homogeneous(x)).collect();
    m.set_displacements(&u).unwrap();
    m
}

fn zoned(p: &PdProblem, cells: &[(Cell, u32)]) -> (AdaptiveCells, PdProblem) {
    let mut a = AdaptiveCells::new(p);
    a.raise(&cells.iter().copied().collect());
    let q = a.problem();
    (a, q)
}

#[test]
fn measures_give_the_gradient_of_a_homogeneous_field_on_uniform_and_mixed_grids() {
    let p = square();
    let (_, q) = zoned(
        &p,
        &[((9, 9), 2), ((10, 9), 1), ((9, 10), 1), ((10, 10), 1)],
    );
    for problem in [&p, &q] {
        let m = with_field(problem);
        let ms = node_measures(&m);
        let delta = problem.horizon();
        for (k, me) in ms.iter().enumerate() {
            for r in 0..2 {
                for c in 0..2 {
                    let err = (me.gradient[r][c] - H[r][c]).abs();
                    assert!(err < 1e-12, "node {k}: H[{r}][{c}] off by {err:e}");
                }
            }
            // Eq. 17 is exact on symmetric families: nodes a horizon inside the edges
            // (and off the size jumps, where a family is one-sided).
            let x = m.positions()[k];
            let inside = [x[0], x[1], 0.04 - x[0], 0.04 - x[1]]
                .iter()
                .all(|&d| d > delta);
            if inside && !m.grid().is_mixed() {
                for i in 0..2 {
                    assert!(
                        (me.strain[i] - H[i][i]).abs() < 1e-12,
                        "node {k}: eps_{i}{i}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_split_places_children_on_the_homogeneous_field() {
    let p = square();
    let old = with_field(&p);
    let (_, q) = zoned(
        &p,
        &[
            ((9, 9), 2),
            ((10, 9), 1),
            ((9, 10), 1),
            ((10, 10), 1),
            ((0, 0), 1),
        ],
    );
    let new = refined_model(&old, &q).unwrap();
    assert!(new.n_real() == old.n_real() + 15 + 3 * 3 + 3);
    let from = origins(&old, &new, &q);
    let children = from
        .iter()
        .filter(|o| matches!(o, Origin::Child(_)))
        .count();
    assert_eq!(children, 16 + 3 * 4 + 4);
    for (k, &x) in new.positions()[..new.n_real()].iter().enumerate() {
        let want = homogeneous(x);
        let u = new.displacements()[k];
        let err = (u[0] - want[0]).hypot(u[1] - want[1]);
        assert!(err < 1e-15, "node {k} at {x:?}: off by {err:e}");
    }
    // A child's parent holds it in its cell.
    for (k, o) in from.iter().enumerate() {
        if let Origin::Child(o) = *o {
            let (xp, xc) = (old.positions()[o], new.positions()[k]);
            let h = 0.5 * old.grid().node_dx(o);
            assert!((xp[0] - xc[0]).abs() < h && (xp[1] - xc[1]).abs() < h);
        }
    }
    // Eq. 18's form: the offset by the gradient.
    let m = node_measures(&old)[0];
    let xp = old.positions()[0];
    let moved = child_displacement(xp, [0.0; 2], &m, [xp[0] + 1e-3, xp[1]]);
    assert!((moved[0] - H[0][0] * 1e-3).abs() < 1e-18 && (moved[1] - H[1][0] * 1e-3).abs() < 1e-18);
}

#[test]
fn split_bonds_keep_their_ancestors_flags_and_history() {
    // Break every bond crossing the line y = 20 mm (a cell boundary), set a history on
    // the others, then split cells on both sides of it.
    let mut p = square();
    p.failure = Failure::Degradation {
        s_m: 1e-3,
        s_c: 1e-2,
        beta: 3.0,
    };
    let mut old = PdModel::new(&p).unwrap();
    let crosses = |a: P2, b: P2| (a[1] - 0.02) * (b[1] - 0.02) < 0.0;
    for k in 0..old.n_nodes() {
        for e in old.bonds.row(k) {
            let j = old.bonds.nbr[e] as usize;
            let (a, b) = (old.positions()[k], old.positions()[j]);
            if crosses(a, b) {
                old.intact[e] = 0;
            } else {
                old.s_hist[e] = 1e-4 * (k + j) as f64;
            }
        }
    }
    let cells: Vec<(Cell, u32)> = (5..15).flat_map(|i| [((i, 9), 1), ((i, 10), 1)]).collect();
    let (_, q) = zoned(&p, &cells);
    let new = refined_model(&old, &q).unwrap();
    let from = origins(&old, &new, &q);
    let mut checked = 0;
    for k in 0..new.n_nodes() {
        for e in new.bonds.row(k) {
            let j = new.bonds.nbr[e] as usize;
            let (a, b) = (new.positions()[k], new.positions()[j]);
            let across = crosses(a, b);
            match (from[k], from[j]) {
                (Origin::Child(x), Origin::Child(y)) if x == y => {
                    assert_eq!(new.intact[e], 1, "siblings start intact");
                    assert_eq!(new.s_hist[e], 0.0);
                }
                (fk, fj) => {
                    let (x, y) = (fk.source(), fj.source());
                    let old_bond = old.bonds.row(x).find(|&f| old.bonds.nbr[f] as usize == y);
                    match old_bond {
                        Some(f) => {
                            assert_eq!(new.intact[e], u8::from(!across), "bond {k}->{j}");
                            assert_eq!(new.s_hist[e], old.s_hist[f]);
                            checked += 1;
                        }
                        // Reach a coarse family did not have: starts intact (elastic
                        // history), across the line too.
                        None => assert_eq!(new.intact[e], 1),
                    }
                }
            }
        }
    }
    assert!(checked > 10_000, "{checked}");
    // The split nodes next to the line see the break as their parents did.
    let d = new.damage();
    let n_line = (0..new.n_real())
        .filter(|&k| (new.positions()[k][1] - 0.02).abs() < 0.001 && d[k] > 0.3)
        .count();
    assert!(n_line >= 40, "{n_line}");
}

#[test]
fn criteria_flag_damaged_and_strained_cells_graded_and_never_a_held_cell() {
    // Damage: the pre-crack's rows pass phi_c = 0.3.
    let mut p = square();
    p.failure = Failure::CriticalStretch { s0: 1e-3 };
    p.cracks = vec![vec![[-0.001, 0.0201], [0.0201, 0.0201]]];
    let m = PdModel::new(&p).unwrap();
    let crit = CellCriteria {
        critical_damage: Some(0.3),
        strain_factor: None,
        max_level: 2,
        near_cracks: None,
        circles: vec![],
        before_breaking: false,
    };
    let f = flagged_cells(&m, &p, &crit);
    let d = m.damage();
    let lattice = Lattice::of(&p);
    for k in 0..m.n_real() {
        let c = lattice.cell_of(m.positions()[k]);
        let held = m.boundary().fixed[k][0] || m.boundary().fixed[k][1];
        assert_eq!(f.get(&c) == Some(&1), d[k] > 0.3 && !held, "node {k}");
    }
    assert!(f.len() >= 18, "{}", f.len());
    // Strain: a biaxial stretch past alpha s_c splits every cell, one below does not.
    for (e, fires) in [(6e-4, true), (4e-4, false)] {
        let mut m = PdModel::new(&p).unwrap();
        let u: Vec<P2> = m.positions().iter().map(|x| [e * x[0], e * x[1]]).collect();
        m.set_displacements(&u).unwrap();
        let crit = CellCriteria {
            critical_damage: None,
            strain_factor: Some(0.5),
            ..crit.clone()
        };
        let f = flagged_cells(&m, &p, &crit);
        let interior = (3..17).flat_map(|i| (3..17).map(move |j| (i, j)));
        for c in interior {
            assert_eq!(f.contains_key(&c), fires, "cell {c:?} at strain {e}");
        }
    }
    // Grading: a level-2 cell splits its neighbours once.
    let mut want = BTreeMap::new();
    want.insert((10, 10), 2);
    let (current, _) = cell_levels(&m, &lattice);
    let g = settle(want, &current, &Default::default());
    assert_eq!(g.len(), 9);
    assert!(g
        .iter()
        .all(|(&c, &l)| l == if c == (10, 10) { 2 } else { 1 }));
}

/// The split before breaking flags the cells of nodes with a bond the next commit would
/// break, and the ring around them: under a uniform biaxial stretch past s0 every cell,
/// below s0 none, none when the bonds are protected (they do not break) or the criterion
/// is off.
#[test]
fn breaking_cells_flag_the_bonds_the_commit_would_break() {
    let mut p = square();
    p.failure = Failure::CriticalStretch { s0: 1e-3 };
    let crit = CellCriteria {
        before_breaking: true,
        ..never()
    };
    let stretched = |e: f64| {
        let mut m = PdModel::new(&p).unwrap();
        let u: Vec<P2> = m.positions().iter().map(|x| [e * x[0], e * x[1]]).collect();
        m.set_displacements(&u).unwrap();
        m
    };
    let interior: Vec<Cell> = (3..17).flat_map(|i| (3..17).map(move |j| (i, j))).collect();
    let past = stretched(1.2e-3);
    let f = breaking_cells(&past, &p, &crit);
    assert!(interior.iter().all(|c| f.get(c) == Some(&1)), "{f:?}");
    assert!(breaking_cells(&stretched(0.8e-3), &p, &crit).is_empty());
    let off = CellCriteria {
        before_breaking: false,
        ..crit.clone()
    };
    assert!(breaking_cells(&past, &p, &off).is_empty());
    let mut protected = stretched(1.2e-3);
    protected.protect_bonds(|_| true);
    assert!(breaking_cells(&protected, &p, &crit).is_empty());
    // One node moved along +x stretches its own bonds to the nodes behind it (those ahead
    // are compressed): the cells of their ends (within a horizon, 3 cells, of the node's
    // cell) and the ring around them, so the cell 4 cells behind splits by the ring
    // alone, the one 5 behind does not.
    let mut one = stretched(0.0);
    let lattice = Lattice::of(&p);
    let k = (0..one.n_real())
        .find(|&k| lattice.cell_of(one.positions()[k]) == (10, 10))
        .unwrap();
    let mut u = one.displacements().to_vec();
    u[k][0] += 0.1e-3;
    one.set_displacements(&u).unwrap();
    let f = breaking_cells(&one, &p, &crit);
    for (c, split) in [
        ((10, 10), true),
        ((7, 10), true),
        ((6, 10), true),
        ((5, 10), false),
    ] {
        assert_eq!(f.get(&c) == Some(&1), split, "cell {c:?}: {f:?}");
    }
    assert!(f
        .keys()
        .all(|c| (c.0 - 10).abs() <= 4 && (c.1 - 10).abs() <= 4));
}

fn newton(last: f64, steps: usize) -> QuasiStatic {
    QuasiStatic::Implicit(ImplicitParams {
        target_load: last,
        steps,
        max_iters: 25,
        ..Default::default()
    })
}

fn never() -> CellCriteria {
    CellCriteria {
        critical_damage: None,
        strain_factor: None,
        max_level: 1,
        near_cracks: None,
        circles: vec![],
        before_breaking: false,
    }
}

#[test]
fn a_ramp_whose_criteria_never_fire_is_the_plain_ramp_bit_for_bit() {
    let p = notched_bar(0.004, 0.006);
    let solver = newton(4.0, 8);
    let mut plain = PdModel::new(&p).unwrap();
    let want = solve_to_limit(&mut plain, &solver, 4, &mut |_| {}).unwrap();
    let got = ramp_to_limit(&p, &solver, 8, &never(), 4, &mut |_| {}).unwrap();
    assert!(got.rounds.is_empty());
    assert_eq!(got.model.displacements(), plain.displacements());
    assert_eq!(got.model.bond_intact(), plain.bond_intact());
    let loads = |s: &crate::SolveInfo| s.steps.iter().map(|r| r.load).collect::<Vec<_>>();
    assert_eq!(loads(&got.solve.info), loads(&want.info));
    assert_eq!(
        got.solve.stop.as_ref().map(|s| s.last_load),
        want.stop.as_ref().map(|s| s.last_load)
    );
    assert_eq!(got.solve.info.iterations, want.info.iterations);
}

/// A 60 x 20 mm bar with 6 mm notches from both sides at mid-length, tanh bonds with
/// the stretches `(4e-5, 4e-4)` times `scale` at the grid's horizon, its right column
/// pulled by `ux = lambda 3e-6 m` and its left side held.
fn pulled_notched_bar(dx: f64, scale: f64) -> PdProblem {
    use crate::problem::{BoundaryCondition, Layer, Selection};
    let mut p = notched_bar(dx, 0.006);
    p.region = Region::rectangle([0.0, 0.0], [0.06, 0.02]);
    p.cracks = vec![
        vec![[0.03, -0.001], [0.03, 0.006]],
        vec![[0.03, 0.014], [0.03, 0.021]],
    ];
    p.failure = Failure::Degradation {
        s_m: 4e-5 * scale,
        s_c: 4e-4 * scale,
        beta: 3.0,
    };
    p.boundary[1] = BoundaryCondition::Displacement {
        on: Selection::Box {
            min: [0.06 - dx, -1.0],
            max: [0.06, 1.0],
        },
        ux: Some(3e-6),
        uy: None,
        layer: Layer::Real,
    };
    p
}

/// The largest force on the pulled column along a Newton ramp to the snap-back.
fn peak_force(p: &PdProblem, crit: &CellCriteria) -> (f64, usize, usize) {
    let r = ramp_to_limit(p, &newton(4.0, 80), 80, crit, 4, &mut |_| {}).unwrap();
    let peak = r
        .solve
        .info
        .steps
        .iter()
        .map(|s| s.resultants[1].force[0])
        .fold(0.0, f64::max);
    (peak, r.model.n_real(), r.rounds.len())
}

#[test]
fn refined_cells_carry_the_peak_load_of_the_finer_grid() {
    // Children halve the horizon and scale the tanh stretches by sqrt 2 (G_c held,
    // crate::mixed), so the finer grid they are compared with has its stretches scaled
    // likewise.
    let (coarse, n_coarse, _) = peak_force(&pulled_notched_bar(0.002, 1.0), &never());
    let (fine, n_fine, _) = peak_force(&pulled_notched_bar(0.001, 2f64.sqrt()), &never());
    let crit = CellCriteria {
        critical_damage: Some(0.25),
        ..never()
    };
    let (adaptive, n_adaptive, rounds) = peak_force(&pulled_notched_bar(0.002, 1.0), &crit);
    eprintln!("peak force: coarse {coarse:.1} N ({n_coarse} nodes), fine {fine:.1} N ({n_fine}), adaptive {adaptive:.1} N ({n_adaptive}, {rounds} rounds)");
    assert!(rounds >= 1);
    assert!(
        (coarse - fine).abs() > 0.03 * fine,
        "the test must tell the grids apart"
    );
    assert!((adaptive - fine).abs() < 0.015 * fine);
    assert!(n_adaptive < n_fine / 2);
}

use super::*;
use pdbem_pd::cases::branching_plate;

#[test]
fn damage_by_a_loaded_edge_is_noted_without_the_surface_correction() {
    // The 100 x 40 mm plate, horizon 3.015 mm, tractions on y = 0 and y = 40 mm.
    let mut p = branching_plate(1e-3, 2e6).problem;
    let x = [
        [0.05, 0.001],
        [0.05, 0.0385],
        [0.05, 0.02],
        [0.08, 0.0031],
        [0.02, 0.039],
    ];
    // Past 0.4 within a horizon of an edge: the first two; the third is mid-plate, the
    // fourth 3.1 mm from the bottom edge, the fifth at 0.4 exactly.
    let phi = [0.5, 0.9, 1.0, 0.8, 0.4];
    let note = loaded_edge_damage_note(&p, &x, &phi).expect("a note");
    assert!(note.starts_with("2 nodes past damage 0.4"), "{note}");
    assert!(loaded_edge_damage_note(&p, &x, &[0.0; 5]).is_none());
    p.surface_correction = true;
    assert!(loaded_edge_damage_note(&p, &x, &phi).is_none());
}

/// A dissipation below zero by more than 5 % of the largest energy is noted; the
/// integrator's small error and a positive fracture energy are not.
#[test]
fn a_negative_dissipation_is_noted() {
    let rec = |time: f64, work: f64, kinetic: f64, strain: f64| DynamicRecord {
        time,
        external_work: work,
        kinetic,
        strain,
        fracture: work - kinetic - strain,
        ..Default::default()
    };
    let good = [rec(0.0, 0.0, 0.0, 0.0), rec(1e-6, 10.0, 6.0, 3.5)];
    assert!(energy_balance_note(&good).is_none());
    let round_off = [rec(0.0, 0.0, 0.0, 0.0), rec(1e-6, 10.0, 6.0, 4.3)];
    assert!(energy_balance_note(&round_off).is_none());
    let bad = [rec(0.0, 0.0, 0.0, 0.0), rec(2e-6, 10.0, 8.0, 3.0)];
    let note = energy_balance_note(&bad).expect("a note");
    assert!(
        note.contains("-1.000e0 J at 2.000e-6 s, negative by 10.0 %"),
        "{note}"
    );
    assert!(energy_balance_note(&[]).is_none());
}

fn piece(nodes: Vec<usize>, net_force: [f64; 2], load: f64) -> Piece {
    Piece {
        nodes,
        net_force,
        load,
        held: [false; 2],
    }
}

/// On the branching plate (tractions on its top and bottom edges, horizon 3.015 mm):
/// a loose piece within a horizon and a cell of a loaded edge is a torn layer, one that
/// reaches further in is a part of a body cut apart; balanced pieces, pieces held by an
/// impactor's velocity and round-off imbalances are not loose.
#[test]
fn loose_pieces_are_told_apart_as_torn_layers_and_cut_parts() {
    let p = branching_plate(1e-3, 2e6).problem;
    // Node 0 by the top edge (1 mm below it), node 1 by the bottom one, node 2
    // mid-plate, node 3 3.9 mm below the top edge (within 4.015 mm), node 4 4.1 mm.
    let x = [
        [0.05, 0.039],
        [0.02, 0.001],
        [0.05, 0.02],
        [0.06, 0.0361],
        [0.07, 0.0359],
    ];
    let pieces = [
        piece(vec![0, 3], [0.0, 10.0], 10.0),
        piece(vec![1], [0.0, -10.0], 10.0),
        piece(vec![2, 4], [0.0, 0.0], 80.0),
    ];
    let l = loose_pieces(&pieces, &x, &p, |_| false);
    assert_eq!(l.layers.0, 2);
    assert_eq!(l.layers.1, 3);
    assert!((l.layers.2 - 0.2).abs() < 1e-12);
    assert_eq!(l.parts, (0, 0.0));
    assert!(!l.torn_most(), "20 % of the loads");
    // The second piece holds node 4 (4.1 mm in): a part, not a layer.
    let cut = [
        piece(vec![0, 4], [0.0, 10.0], 50.0),
        piece(vec![1, 2], [0.0, -10.0], 50.0),
    ];
    let l = loose_pieces(&cut, &x, &p, |_| false);
    assert_eq!(l.layers.0, 0);
    assert_eq!(l.parts.0, 2);
    assert!(!l.torn_most());
    // Held by an impactor's velocity, or unbalanced by round-off only: not loose.
    assert_eq!(loose_pieces(&cut, &x, &p, |i| i == 4).parts.0, 1);
    let balanced = [piece(vec![0, 1, 2], [0.0, 1e-13], 100.0)];
    assert_eq!(loose_pieces(&balanced, &x, &p, |_| false).parts.0, 0);
}

/// The notes' wording carries the numbers: the torn layers' share, the nominal strain
/// against s0 and the kinetic energy's share; layers carrying most of the loads away
/// make the note a refusal of the crack measures; no loose piece, no note.
#[test]
fn the_loose_pieces_notes_name_the_cause() {
    let p = branching_plate(1e-3, 1e6).problem;
    let last = DynamicRecord {
        external_work: 2.0,
        kinetic: 1.9,
        ..Default::default()
    };
    let torn = Loose {
        layers: (2, 200, 0.999),
        parts: (0, 0.0),
        pieces: 3,
    };
    assert!(torn.torn_most());
    let notes = loose_pieces_notes(&torn, &p, Some(1e-5), 1.0, &last);
    assert_eq!(notes.len(), 1);
    let note = &notes[0];
    assert!(note.starts_with("the loads tore off the layers"), "{note}");
    assert!(note.contains("2 piece(s) of 200 node(s)"), "{note}");
    assert!(note.contains("carry 99.9 % of the loads"), "{note}");
    assert!(note.contains("kinetic energy 95.0 %"), "{note}");
    assert!(note.contains("deflection angles are left out"), "{note}");
    // |t| / E = 1e6 / 32e9.
    assert!(
        note.contains("left out. The loads' nominal strain |t| / E = 3.125e-5 is 3.125 times"),
        "{note}"
    );
    let both = Loose {
        layers: (4, 4, 0.04),
        parts: (2, 0.96),
        pieces: 7,
    };
    assert!(!both.torn_most());
    let notes = loose_pieces_notes(&both, &p, Some(1e-5), 1.0, &last);
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(
        notes[0]
            .starts_with("parts of the loaded layers tore off: at the end 4 piece(s) of 4 node(s)"),
        "{}",
        notes[0]
    );
    assert!(
        notes[0].contains("carry 4.0 % of the loads"),
        "{}",
        notes[0]
    );
    assert!(
        notes[1].starts_with("the body is cut apart: at the end 2 of its 7 pieces carry 96.0 %"),
        "{}",
        notes[1]
    );
    assert!(loose_pieces_notes(&Loose::default(), &p, None, 1.0, &last).is_empty());
}

//! A crack whose flank runs close along another boundary leaves a thin strip the BEM crack
//! faces do not resolve, and the error estimate does not see it
//! (`pdbem::setup::thin_ligament`). Before, an edge crack 0.03 m under the free top edge
//! of a plate reported a CMOD more than 92 % low with an estimate of 6 % and exit 0, and
//! nothing said why. Now every run whose K comes from the BEM, and `pdbem check`, note
//! such a ligament, unless the crack's own elements resolve it (then the CMOD lies within
//! its estimate of the beam's bound); cracks away from other boundaries, tips that
//! approach one, and inclined edge cracks (the wedge at the mouth) get no note. Tips near
//! another boundary (`close_tips`) and holes nearer another loop than the elements at the
//! gap (`close_holes`) get notes too, and so do necks of the outline narrower than their
//! elements (`outline_necks`).

use std::path::Path;

use pdbem::runner::plausibility::thin_ligaments;
use pdbem::runner::RunSummary;
use pdbem::scene::Scene;
use pdbem::setup::thin_ligament::{self, RESOLVING_FRACTION, SLENDERNESS_LIMIT};

/// A 2 m x 1 m plate pulled by `top` on its top edge and `bottom` on its bottom edge
/// (Pa), with cracks (RON list entries).
fn plate(cracks: &str, extra: &str) -> Scene {
    let text = format!(
        r#"(
    name: "strip",
    description: "cracks near the top edge",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 2, height: 1)),
    cracks: [{cracks}],
    boundary: [
        (on: "top", y: Traction(1)),
        (on: "bottom", y: Traction(-1)),
    ],
    {extra}
)"#
    );
    Scene::parse(&text, Path::new("strip.ron")).expect("parses")
}

/// An edge crack from the left edge, parallel to the top edge, `w` below it, 0.5 m long.
fn under_the_edge(w: f64) -> Scene {
    under_the_edge_with(w, "")
}

/// [`under_the_edge`] with `extra` scene fields.
fn under_the_edge_with(w: f64, extra: &str) -> Scene {
    plate(
        &format!(
            r#"(name: "c", start: (0, {}), angle_deg: 0, length: 0.5)"#,
            1.0 - w
        ),
        extra,
    )
}

/// The strip's end (0.5 m long, `w` thick, pulled by 1 Pa, E = 1e4 Pa) lies at least
/// q l^4 / (8 E I) above the bulk: Euler-Bernoulli with a rigid root (the root's
/// compliance and shear only add). The CMOD is that opening.
fn beam_bound(w: f64) -> f64 {
    let (q, len, e): (f64, f64, f64) = (1.0, 0.5, 1e4);
    q * len.powi(4) / (8.0 * e * w.powi(3) / 12.0)
}

fn run(scene: &Scene, tag: &str) -> RunSummary {
    let out =
        std::env::temp_dir().join(format!("pdbem-thin-ligament-{}-{tag}", std::process::id()));
    let s = pdbem::runner::run_scene(scene, &out, true).expect("runs");
    let _ = std::fs::remove_dir_all(&out);
    s
}

#[test]
fn a_crack_under_an_edge_is_noted_and_its_estimate_misses_the_strip() {
    let w = 0.03;
    let scene = under_the_edge(w);
    let ligaments = thin_ligament::of_scene(&scene);
    assert_eq!(ligaments.len(), 1, "{ligaments:?}");
    let l = &ligaments[0];
    assert!(
        (l.width - w).abs() < 1e-12 && (l.length - 0.5).abs() < 1e-12,
        "{l:?}"
    );
    assert_eq!(l.other, "'top'");

    let s = run(&scene, "default");
    assert!(
        s.notes
            .iter()
            .any(|n| n.starts_with("thin ligament: cracks.0 ('c')")),
        "{:?}",
        s.notes
    );
    // Why the note: the BEM's CMOD at the default sizes lies far below the beam's bound,
    // and its estimate covers a few per cent.
    let beam = beam_bound(w);
    let crack = &s.cracks[0];
    let (cmod, est) = (crack.cmod.unwrap(), crack.cmod_err_est.unwrap());
    assert!(
        cmod + 3.0 * est < 0.5 * beam,
        "CMOD {cmod} (estimate {est}) against the beam's bound {beam}: if the BEM resolves \
         the strip now, the note (and this test) should go"
    );
}

#[test]
fn crack_elements_of_a_64th_of_the_strip_resolve_it_and_the_note_goes() {
    let w = 0.03;
    let h = RESOLVING_FRACTION * w;
    let scene = under_the_edge_with(w, &format!(r#"bem: (group_sizes: {{"c": {h}}}),"#));
    assert!(thin_ligament::of_scene(&scene).is_empty());
    let s = run(&scene, "resolved");
    assert!(
        !s.notes.iter().any(|n| n.starts_with("thin ligament")),
        "{:?}",
        s.notes
    );
    // Within its estimate of the bound (measured 0.383 m, estimate 0.164 m, bound 0.347
    // m; at w / 128 0.431 m), and not far above it.
    let crack = &s.cracks[0];
    let (cmod, est) = (crack.cmod.unwrap(), crack.cmod_err_est.unwrap());
    let beam = beam_bound(w);
    assert!(
        cmod + est >= beam && cmod < 1.5 * beam,
        "CMOD {cmod} (estimate {est}), bound {beam}"
    );
    // A strip three times more slender is not resolved by the same fraction: noted.
    let slender = under_the_edge_with(
        0.01,
        &format!(
            r#"bem: (group_sizes: {{"c": {}}}),"#,
            RESOLVING_FRACTION * 0.01
        ),
    );
    assert_eq!(thin_ligament::of_scene(&slender).len(), 1);
}

#[test]
fn the_limit_separates_stout_and_slender_strips() {
    // Length / thickness 0.5 / 0.1 = 5 is noted, 0.5 / 0.2 = 2.5 is not.
    let noted = |w: f64| !thin_ligament::of_scene(&under_the_edge(w)).is_empty();
    const { assert!(SLENDERNESS_LIMIT > 2.5 && SLENDERNESS_LIMIT < 5.0) };
    assert!(noted(0.1));
    assert!(!noted(0.2));
    // The note names the crack and the strip's size.
    let notes = thin_ligaments(&under_the_edge(0.1));
    assert_eq!(notes.len(), 1);
    assert!(
        notes[0].contains("runs 5.000e-1 m alongside 'top' at 1.000e-1 m"),
        "{}",
        notes[0]
    );
}

#[test]
fn overlapping_parallel_cracks_are_noted_at_both() {
    let s = plate(
        r#"(name: "a", start: (0.7, 0.5), angle_deg: 0, length: 0.4),
           (name: "b", start: (0.9, 0.51), angle_deg: 0, length: 0.4)"#,
        "",
    );
    let ligaments = thin_ligament::of_scene(&s);
    assert_eq!(ligaments.len(), 2, "{ligaments:?}");
    for (l, other) in ligaments.iter().zip(["crack 'b'", "crack 'a'"]) {
        assert_eq!(l.other, other);
        assert!((l.width - 0.01).abs() < 1e-9, "{l:?}");
        // The overlap is 0.2 m; sampling at half gaps ends within one gap of it.
        assert!((l.length - 0.2).abs() < 0.015, "{l:?}");
    }
}

#[test]
fn tips_near_boundaries_inclined_edge_cracks_and_shipped_cases_pass() {
    // Colinear tips 0.01 m apart: gaps grow behind each tip, a strip as long as thick.
    let colinear = plate(
        r#"(name: "a", start: (0.5, 0.5), angle_deg: 0, length: 0.5),
           (name: "b", start: (1.01, 0.5), angle_deg: 0, length: 0.5)"#,
        "",
    );
    // A tip 0.01 m under the top edge, the crack running up to it.
    let towards = plate(
        r#"(name: "c", start: (1, 0.2), angle_deg: 90, length: 0.79)"#,
        "",
    );
    // An edge crack at 10 degrees to the bottom edge: the wedge at its mouth is a corner.
    let wedge = plate(
        r#"(name: "c", start: (0.5, 0), angle_deg: 10, length: 0.8)"#,
        "",
    );
    for (name, s) in [
        ("colinear", colinear),
        ("towards", towards),
        ("wedge", wedge),
    ] {
        let l = thin_ligament::of_scene(&s);
        assert!(l.is_empty(), "{name}: {l:?}");
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    assert!(files.len() > 50);
    for f in files {
        let s = Scene::load(&f).expect("loads");
        let notes = thin_ligaments(&s);
        assert!(notes.is_empty(), "{}: {notes:?}", f.display());
    }
}

#[test]
fn the_ligament_is_the_same_after_rotation_and_scaling() {
    // The strip of the first test turned by 30 degrees about the origin and scaled by
    // 1e3: a polygon plate with the crack from its left edge.
    let (c, s, k) = (30f64.to_radians().cos(), 30f64.to_radians().sin(), 1e3);
    let p = |x: f64, y: f64| format!("({:.12}, {:.12})", k * (c * x - s * y), k * (s * x + c * y));
    let text = format!(
        r#"(
    name: "turned",
    description: "the strip turned and scaled",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: Polygon(points: [{}, {}, {}, {}], edge_names: ["bottom", "right", "top", "left"])),
    cracks: [(name: "c", start: {}, angle_deg: 30, length: {})],
    boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
)"#,
        p(0.0, 0.0),
        p(2.0, 0.0),
        p(2.0, 1.0),
        p(0.0, 1.0),
        p(0.0, 0.97),
        0.5 * k
    );
    let turned = Scene::parse(&text, Path::new("turned.ron")).expect("parses");
    let a = &thin_ligament::of_scene(&under_the_edge(0.03))[0];
    let b = &thin_ligament::of_scene(&turned)[0];
    assert_eq!(b.other, "'top'");
    assert!(
        (b.width / k - a.width).abs() < 1e-9 * a.width,
        "{a:?} {b:?}"
    );
    assert!(
        (b.length / k - a.length).abs() < 1e-9 * a.length,
        "{a:?} {b:?}"
    );
}

/// A tip nearer another boundary than 1e-5 of the body's size gets a note, in `run` and
/// `check`: there the two-level estimate missed the error (an edge crack in a 10 m x 40 m
/// strip with a ligament of 1e-5 m, 2.5e-7 of its size: K_I 31 % high with an estimate of
/// 4.7 %, exit 0). A ligament of 1e-3 m, a short crack (its length sets the scale) and
/// stand-alone PD get none.
#[test]
fn a_tip_within_1e_5_of_the_body_size_of_a_boundary_gets_a_note() {
    let strip = |ligament: f64, length: f64, extra: &str| {
        let text = format!(
            r#"(
    name: "deep",
    description: "deep edge crack",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 10, height: 40)),
    cracks: [(name: "c", start: (0, 20), angle_deg: 0, length: {})],
    boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
    {extra}
)"#,
            if length > 0.0 {
                length
            } else {
                10.0 - ligament
            }
        );
        Scene::parse(&text, Path::new("deep.ron")).expect("parses")
    };
    let close = pdbem::runner::plausibility::close_tips(&strip(1e-5, 0.0, ""));
    assert_eq!(close.len(), 1, "{close:?}");
    assert!(
        close[0].contains("its end tip lies 1.000e-5 m from 'right', 2.5e-7 of the body's size"),
        "{}",
        close[0]
    );
    assert!(pdbem::runner::plausibility::close_tips(&strip(1e-3, 0.0, "")).is_empty());
    assert!(pdbem::runner::plausibility::close_tips(&strip(0.0, 1e-5, "")).is_empty());
    let pd = strip(1e-5, 0.0, "pd: (dx: 0.5)");
    assert!(pdbem::runner::plausibility::close_tips(&pd).is_empty());
}

/// A 0.2 m x 0.1 m plate pulled along its length by 1 Pa, with a hole of radius 0.01 m
/// centred 0.0105 m under its top edge (a gap of 5e-4 m) and `bem` settings. The top edge
/// is three pieces, `top_mid` the 0.04 m above the hole.
fn hole_under_the_edge(bem: &str) -> Scene {
    let text = format!(
        r#"(
    name: "hole_gap",
    description: "a hole near an edge",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (
        outline: Edges(edges: [
            (name: "bottom", points: [(0, 0), (0.2, 0)]),
            (name: "right", points: [(0.2, 0), (0.2, 0.1)]),
            (name: "top_r", points: [(0.2, 0.1), (0.12, 0.1)]),
            (name: "top_mid", points: [(0.12, 0.1), (0.08, 0.1)]),
            (name: "top_l", points: [(0.08, 0.1), (0, 0.1)]),
            (name: "left", points: [(0, 0.1), (0, 0)]),
        ]),
        holes: [Circle(center: (0.1, 0.0895), radius: 0.01, name: "hole")],
    ),
    boundary: [(on: "left", x: Traction(-1)), (on: "right", x: Traction(1))],
    bem: ({bem}),
    outputs: (boundary_stress: ["hole"]),
)"#
    );
    Scene::parse(&text, Path::new("hole_gap.ron")).expect("parses")
}

fn hoop_peak(s: &RunSummary) -> (f64, f64) {
    let get = |k: &str| s.extra.get(k).and_then(|v| v.as_f64()).expect(k);
    (get("hoop_peak"), get("hoop_peak_err_est"))
}

/// A hole whose gap to an edge is narrower than the elements there gets a note naming the
/// sizes that resolve it (`pdbem::setup::close_holes`); with those sizes the note goes and
/// the hoop peak lies within its estimate of the value at half those sizes. Measured: the
/// default mesh (gap 0.5 of the edge's 1e-3 m elements) 25.4 Pa, the advised sizes (503
/// elements on the hole, 1.25e-4 m on `top_mid`) 16.44 (estimate 2.28), half of them
/// 15.97 (0.47): the default 59 % high.
#[test]
fn a_hole_nearer_an_edge_than_its_elements_is_noted_and_the_advised_sizes_resolve_it() {
    let coarse = hole_under_the_edge("");
    let gaps = pdbem::setup::close_holes::unresolved(&coarse);
    assert_eq!(gaps.len(), 1, "{gaps:?}");
    let g = &gaps[0];
    assert_eq!((g.hole, g.other.as_str()), (0, "top_mid"));
    assert!((g.gap - 5e-4).abs() < 1e-9, "{g:?}");
    assert!((g.h_other - 1e-3).abs() < 1e-9, "{g:?}");
    assert!((g.h_hole - 0.02 * (std::f64::consts::PI / 128.0).sin()).abs() < 1e-9);
    let default = pdbem::run_bem::solve(&coarse).unwrap().0;
    let note = pdbem::setup::close_holes::note(&coarse, g);
    assert!(
        note.contains("bem.elements_per_circle >= 503")
            && note.contains("bem.group_sizes.top_mid <= 1.250e-4 m"),
        "{note}"
    );
    let run = pdbem::runner::plausibility::close_holes(&coarse);
    assert_eq!(run, vec![note]);

    let advised =
        hole_under_the_edge(r#"elements_per_circle: 503, group_sizes: {"top_mid": 1.25e-4}"#);
    assert!(pdbem::setup::close_holes::unresolved(&advised).is_empty());
    let finer =
        hole_under_the_edge(r#"elements_per_circle: 1006, group_sizes: {"top_mid": 6.25e-5}"#);
    let (p, e) = hoop_peak(&pdbem::run_bem::solve(&advised).unwrap().0);
    let (p_ref, _) = hoop_peak(&pdbem::run_bem::solve(&finer).unwrap().0);
    let (p0, _) = hoop_peak(&default);
    println!("default {p0:.3}, advised {p:.3} ({e:.3}), finer {p_ref:.3}");
    assert!((p - p_ref).abs() <= e, "advised {p} ({e}) against {p_ref}");
    assert!((p / p_ref - 1.0).abs() < 0.07);
    assert!(
        p0 / p_ref - 1.0 > 0.3,
        "the default mesh was measured 59 % high"
    );
}

/// Two holes closer than their elements: one note, on the first, naming the second; a
/// polygon hole is advised a group size. Holes a few elements apart get none.
#[test]
fn two_close_holes_get_one_note() {
    let scene = |gap: f64| {
        let text = format!(
            r#"(
    name: "holes",
    description: "two close holes",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (
        outline: Rectangle(x0: 0, y0: 0, width: 1, height: 1),
        holes: [
            Polygon(points: [(0.3, 0.4), (0.5, 0.4), (0.5, 0.6), (0.3, 0.6)], name: "square"),
            Circle(center: ({}, 0.5), radius: 0.1, name: "round"),
        ],
    ),
    boundary: [(on: "left", x: Traction(-1)), (on: "right", x: Traction(1))],
)"#,
            0.6 + gap
        );
        Scene::parse(&text, Path::new("holes.ron")).expect("parses")
    };
    let notes = pdbem::runner::plausibility::close_holes(&scene(1e-4));
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].starts_with("holes.0 ('square'): its gap to hole 'round'")
            && notes[0].contains("bem.group_sizes.square <= 2.500e-5 m")
            && notes[0].contains("the same for 'round'"),
        "{}",
        notes[0]
    );
    assert!(pdbem::runner::plausibility::close_holes(&scene(0.05)).is_empty());
}

/// A crack passing 1e-3 m above a hole of radius 1 m runs along it in several stretches
/// (the gap doubles every few samples away from the closest point): one note, on the
/// thinnest, counting the others. Before, 4 notes (5 with 2048 elements on the hole).
#[test]
fn a_crack_passing_a_hole_gets_one_ligament_note() {
    let text = r#"(
    name: "passing",
    description: "a crack passing just above a hole",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (
        outline: Rectangle(x0: 0, y0: 0, width: 20, height: 10),
        holes: [Circle(center: (10, 4), radius: 1, name: "h")],
    ),
    cracks: [(name: "crack", start: (0, 5.001), angle_deg: 0, length: 12)],
    boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
)"#;
    let scene = Scene::parse(text, Path::new("passing.ron")).expect("parses");
    let stretches = thin_ligament::of_scene(&scene);
    assert!(stretches.len() > 1, "{stretches:?}");
    let notes = thin_ligaments(&scene);
    assert_eq!(notes.len(), 1, "{notes:?}");
    let more = format!(
        "({} more stretches of the crack run alongside 'h'",
        stretches.len() - 1
    );
    assert!(notes[0].contains(&more), "{}", notes[0]);
}

/// A 0.2 m x 0.1 m bar held on its left edge and pulled by 1e-4 Pa on its right, with
/// slots 0.01 m wide from its top and bottom edges leaving a neck `g` wide at mid-length
/// (E = 1 Pa); `bem` is the scene's `bem` section body.
fn necked_bar(g: f64, bem: &str) -> Scene {
    let (w, yb, yt) = (0.005, 0.05 - g / 2.0, 0.05 + g / 2.0);
    let pts = [
        (0.0, 0.0),
        (0.1 - w, 0.0),
        (0.1 - w, yb),
        (0.1 + w, yb),
        (0.1 + w, 0.0),
        (0.2, 0.0),
        (0.2, 0.1),
        (0.1 + w, 0.1),
        (0.1 + w, yt),
        (0.1 - w, yt),
        (0.1 - w, 0.1),
        (0.0, 0.1),
    ];
    let points: Vec<String> = pts.iter().map(|(x, y)| format!("({x:?}, {y:?})")).collect();
    let text = format!(
        r#"(
    name: "necked_bar",
    material: (E: 1.0, nu: 0.3, plane: Stress),
    body: (outline: Polygon(points: [{}], edge_names: ["b0", "s1", "s2", "s3", "b1", "right", "t1", "s4", "s5", "s6", "t0", "left"])),
    boundary: [
        (on: "left", x: Displacement(0.0), y: Displacement(0.0)),
        (on: "right", x: Traction(1e-4)),
    ],
    bem: ({bem}),
)"#,
        points.join(", ")
    );
    Scene::parse(&text, Path::new("necked_bar.ron")).expect("parses")
}

/// The right edge's mean displacement along x (length-weighted).
fn end_displacement(scene: &Scene) -> f64 {
    let (_, level) = pdbem::run_bem::solve(scene).expect("solves");
    let mesh = &level.setup.mesh;
    let right = mesh.group("right").expect("right edge");
    let (mut sum, mut len) = (0.0, 0.0);
    for (e, u) in mesh.elements.iter().zip(&level.solution.u) {
        if e.group == right {
            sum += u[0] * e.h;
            len += e.h;
        }
    }
    sum / len
}

/// A neck of the outline narrower than its elements gets a note (`pdbem::setup::outline_necks`)
/// naming every piece near it, with the size that resolves it; with that size the note goes
/// and the bar's end displacement lands within 1 % of a mesh twice as fine. Measured at
/// g = 1e-3 m (0.45 of the 2.24e-3 m elements there): default +7.2 %, advised +0.4 %
/// against g / 16 (g / 8 here: within 0.3 % of g / 16).
#[test]
fn a_neck_of_the_outline_narrower_than_its_elements_is_noted_and_the_advised_sizes_resolve_it() {
    let g = 1e-3;
    let coarse = necked_bar(g, "");
    let necks = pdbem::setup::outline_necks::unresolved(&coarse);
    assert_eq!(necks.len(), 1, "{necks:?}");
    let n = &necks[0];
    assert_eq!(n.groups, ["s2".to_string(), "s5".to_string()]);
    assert!((n.gap - g).abs() < 1e-12 && n.resolution() < 0.5, "{n:?}");
    let mut near = n.nearby.clone();
    near.sort();
    assert_eq!(near, ["s1", "s2", "s3", "s4", "s5", "s6"], "{n:?}");
    let note = pdbem::setup::outline_necks::note(n);
    assert!(note.contains("bem.group_sizes.s3 <= 2.500e-4 m"), "{note}");
    assert_eq!(
        pdbem::runner::plausibility::outline_necks(&coarse),
        vec![note]
    );

    let sizes = |h: f64| {
        let groups: Vec<String> = (1..=6).map(|i| format!(r#""s{i}": {h:e}"#)).collect();
        format!("group_sizes: {{{}}}", groups.join(", "))
    };
    let advised = necked_bar(g, &sizes(g / 4.0));
    assert!(pdbem::setup::outline_necks::unresolved(&advised).is_empty());
    let (u0, u, u_ref) = (
        end_displacement(&coarse),
        end_displacement(&advised),
        end_displacement(&necked_bar(g, &sizes(g / 8.0))),
    );
    println!("end displacement: default {u0:.5e}, advised {u:.5e}, finer {u_ref:.5e}");
    assert!(
        (u / u_ref - 1.0).abs() < 0.01,
        "advised {u} against {u_ref}"
    );
    assert!(
        u0 / u_ref - 1.0 > 0.05,
        "the default mesh was measured 7.6 % too compliant"
    );
}

/// Necks that are not: a wide neck, the narrow slot itself (a gap outside the body) and
/// a rectangle with an edge crack get no note.
#[test]
fn wide_necks_narrow_slots_and_plain_plates_get_no_neck_note() {
    assert!(pdbem::setup::outline_necks::unresolved(&necked_bar(0.01, "")).is_empty());
    // Slots 1e-4 m wide, far narrower than their 1e-3 m elements, a 0.04 m neck between.
    let slot = Scene::parse(
        r#"(
    name: "slotted",
    material: (E: 1.0, nu: 0.3, plane: Stress),
    body: (outline: Polygon(points: [(0, 0), (0.09995, 0), (0.09995, 0.03), (0.10005, 0.03), (0.10005, 0), (0.2, 0), (0.2, 0.1), (0, 0.1)])),
    boundary: [
        (on: "edge7", x: Displacement(0.0), y: Displacement(0.0)),
        (on: "edge6", y: Traction(1e-4)),
    ],
    bem: (element_size: 1e-3),
)"#,
        Path::new("slotted.ron"),
    )
    .expect("parses");
    assert!(pdbem::setup::outline_necks::unresolved(&slot).is_empty());
    let cracked = plate(
        r#"(name: "c", start: (0, 0.5), angle_deg: 0, length: 0.5)"#,
        "",
    );
    assert!(pdbem::setup::outline_necks::unresolved(&cracked).is_empty());
}

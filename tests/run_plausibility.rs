//! Results that are not what they seem come with a note (issue 17): overlapping crack faces
//! (K_I < 0, CMOD < 0), the two SIF estimates disagreeing, and a windowed tip that no
//! contour fits around. The shipped BEM cases pass the review without a note.

mod common_scene;

use common_scene::{case, case_files};
use pdbem::runner::mode::{mode_of, Mode};
use pdbem::runner::plausibility::{review, CONDITION_LIMIT};
use pdbem::runner::RunSummary;
use pdbem::scene::Scene;

/// BEM solve and the runner's review, as `run_scene` does them.
fn reviewed(scene: &Scene) -> RunSummary {
    let (mut s, _) = pdbem::run_bem::solve(scene).expect("solves");
    review(scene, &mut s);
    s
}

fn has_note(s: &RunSummary, parts: &[&str]) -> bool {
    s.notes.iter().any(|n| parts.iter().all(|p| n.contains(p)))
}

#[test]
fn a_plate_in_compression_notes_overlapping_faces() {
    let pulled = case("sent_bem_a5", &[("bem.element_size", "0.2")]);
    let s = reviewed(&pulled);
    assert!(
        s.tips[0].k1 > 0.0 && !has_note(&s, &["overlap"]),
        "{:?}",
        s.notes
    );
    let pushed = case(
        "sent_bem_a5",
        &[
            ("bem.element_size", "0.2"),
            ("boundary.0.x.Traction", "0.5"),
            ("boundary.1.x.Traction", "-0.5"),
        ],
    );
    let s = reviewed(&pushed);
    assert!(s.tips[0].k1 < 0.0 && s.cracks[0].cmod.unwrap() < 0.0);
    assert!(
        has_note(
            &s,
            &[
                "tip crack.end: K_I = -",
                "crack faces overlap",
                "no contact"
            ]
        ),
        "{:?}",
        s.notes
    );
    assert!(
        has_note(&s, &["crack crack: CMOD = -", "crack faces overlap"]),
        "{:?}",
        s.notes
    );
}

#[test]
fn disagreeing_sif_estimates_are_noted() {
    // Crack elements twice the shipped 0.025 m: the interaction integral moves by 4 %
    // (measured 4.6 % of K_eq between the two estimates; 0.49 % at the shipped size).
    let coarse = case(
        "inclined_crack_45_finite",
        &[
            ("bem.element_size", "0.5"),
            ("bem.group_sizes.crack", "0.05"),
        ],
    );
    let s = reviewed(&coarse);
    assert!(
        has_note(
            &s,
            &[
                "tip crack.end: the crack-opening fit (K_I",
                "interaction integral (K_I",
                "more than 2 %"
            ]
        ),
        "{:?}",
        s.notes
    );
}

#[test]
fn shipped_bem_cases_pass_the_review_without_a_note() {
    let mut solved = 0;
    for f in case_files() {
        let mut scene = Scene::load(&f).unwrap();
        if mode_of(&scene) != Mode::Bem {
            continue;
        }
        scene.bem.condition_estimate = true;
        let s = reviewed(&scene);
        let cond = s.extra["condition_estimate"].as_f64().unwrap();
        println!("{}: condition {cond:.3e}", f.display());
        // Measured at most 4.9e6 (sent_bem_a8): three orders below the limit.
        assert!(cond < 1e-3 * CONDITION_LIMIT, "{}: {cond}", f.display());
        // The one note a shipped case may carry: an infinite plate's reference on a
        // finite body (first_scene, inclined_crack_45_finite).
        let finite_plate = "scene: reference: InclinedCrackInfinite is the infinite plate's";
        let others: Vec<_> = s
            .notes
            .iter()
            .filter(|n| !n.starts_with(finite_plate))
            .collect();
        assert!(others.is_empty(), "{}: {:?}", f.display(), s.notes);
        solved += 1;
    }
    assert!(solved >= 5, "only {solved} BEM cases");
}

#[test]
fn a_window_too_large_for_a_contour_is_noted_by_check_and_run() {
    // a/W = 0.8: the tip is 2 m from the bottom edge. A 2.4 m window puts its corners
    // 1.70 m from the tip; a contour must be at least 1.1 x that (1.87 m) but at most
    // 0.9 x 2 m = 1.8 m: none fits.
    let big = case(
        "coupled_sent_a8",
        &[
            ("coupling.side", "2.4"),
            ("coupling.n", "24"),
            ("bem.element_size", "0.1"),
        ],
    );
    let expect = ["tip crack.end: no K reported: window 0", "side 2.3142e0 m"];
    let f = pdbem::setup::footprint::of(&big).unwrap();
    assert!(
        f.describe()
            .iter()
            .any(|l| expect.iter().all(|p| l.contains(p))),
        "{:?}",
        f.describe()
    );
    let (s, _) = pdbem::run_coupled::solve(&big).expect("solves");
    assert!(s.tips.is_empty());
    assert!(has_note(&s, &expect), "{:?}", s.notes);
    // The shipped 2 m window leaves a contour: K reported, no note.
    let fits = case(
        "coupled_sent_a8",
        &[("coupling.n", "20"), ("bem.element_size", "0.1")],
    );
    assert!(pdbem::setup::footprint::of(&fits).unwrap().notes.is_empty());
    let (s, _) = pdbem::run_coupled::solve(&fits).expect("solves");
    assert_eq!(s.tips.len(), 1);
    assert!(s.notes.is_empty(), "{:?}", s.notes);
}

/// A static coupled solve whose window breaks or softens bonds notes it: the BEM keeps the
/// scene's crack, so K and the CMOD belong to a body the window cracked further. Measured
/// on the SENT plate (a/W = 0.5, tension 0.5): `CriticalStretch(0.001)` breaks 1148 pairs
/// and K_I comes out +129 % against Tada; the tanh law from s_m = 5e-4 breaks 626 and
/// softens 2040 (+132 %). Elastic bonds: no note.
#[test]
fn a_static_window_that_breaks_bonds_is_noted() {
    use pdbem::scene::Failure;
    let laws = [
        (Failure::CriticalStretch(0.001), false),
        (
            Failure::Degradation {
                s_m: 5e-4,
                s_c: 1.5e-3,
                beta: 3.0,
            },
            true,
        ),
    ];
    for (law, softens) in laws {
        let mut scene = case("coupled_sent_a5", &[]);
        scene.pd.as_mut().unwrap().failure = law;
        let (s, _) = pdbem::run_coupled::solve(&scene).expect("solves");
        let note = s
            .notes
            .iter()
            .find(|n| n.starts_with("PD window 0 broke ") && n.contains("further-cracked body"))
            .unwrap_or_else(|| panic!("{:?}", s.notes));
        let broken: usize = note["PD window 0 broke ".len()..]
            .split(' ')
            .next()
            .and_then(|n| n.parse().ok())
            .expect("a count");
        assert!(broken > 300, "{note}");
        assert_eq!(note.contains("softened"), softens, "{note}");
    }
    let (s, _) = pdbem::run_coupled::solve(&case("coupled_sent_a5", &[])).expect("solves");
    assert!(!has_note(&s, &["PD window 0"]), "{:?}", s.notes);
}

#[test]
fn a_window_that_leaves_a_thin_strip_of_bem_body_is_noted_by_check_and_run() {
    // a/W = 0.8: the tip is 2 m from the bottom edge; a 3.6 m window centred on it leaves
    // a 0.2 m strip of BEM body under it (0.056 of its side, under the quarter side the
    // coupling needs to converge reliably).
    let thin = case(
        "coupled_sent_a8",
        &[
            ("coupling.side", "3.6"),
            ("coupling.n", "36"),
            ("bem.element_size", "0.1"),
        ],
    );
    let expect = [
        "window 0",
        "strip of BEM body 0.2000 m wide",
        "0.06 of its 3.6000 m side",
    ];
    let f = pdbem::setup::footprint::of(&thin).unwrap();
    assert!(
        f.describe()
            .iter()
            .any(|l| expect.iter().all(|p| l.contains(p))),
        "{:?}",
        f.describe()
    );
    // The run stalls at a residual of 1 (5 s) and its error names the strip as the cause.
    let Err(e) = pdbem::run_coupled::solve(&thin) else {
        panic!("the coupling converged on a 0.2 m strip");
    };
    let msg = format!("{e:#}");
    assert!(
        msg.contains("likely cause") && expect.iter().all(|p| msg.contains(p)),
        "{msg}"
    );
    // Against the edge (side 4 m, the window's lower side on the bottom edge), no note.
    let flush = case(
        "coupled_sent_a8",
        &[
            ("coupling.side", "4.0"),
            ("coupling.n", "40"),
            ("bem.element_size", "0.1"),
        ],
    );
    let f = pdbem::setup::footprint::of(&flush).unwrap();
    assert!(
        f.notes.iter().all(|n| !n.contains("strip")),
        "{:?}",
        f.notes
    );
}

#[test]
fn the_scene_notes_reach_the_summary() {
    // A bond-based PD window under a BEM body of nu = 0.3: the scene notes the ratio the
    // PD part runs with, and the run's summary keeps that note first.
    // The edited scene (what a sweep runs) carries the note once.
    let scene = case("coupled_sent_a8", &[("material.nu", "0.3")]);
    assert_eq!(
        scene
            .notes
            .iter()
            .filter(|n| n.contains("material.nu = 0.3"))
            .count(),
        1,
        "{:?}",
        scene.notes
    );
    let mut s = RunSummary::default();
    review(&scene, &mut s);
    assert!(
        s.notes[0].starts_with("scene: material.nu = 0.3"),
        "{:?}",
        s.notes
    );
}

#[test]
fn a_refined_body_notes_the_solver_settings_it_does_not_read() {
    use pdbem::scene::{AdrParams, PdSolver};
    let notes = |scene: &mut Scene| {
        scene.notes.clear();
        scene.note_inert_fields();
        scene.notes.clone()
    };
    // The quasi-static refined body: the default solver is no note, ADR or a check
    // interval are (the body solves by conjugate gradients and checks at every equilibrium).
    let mut scene = case("seed004_edge_crack_adaptive", &[]);
    assert!(notes(&mut scene).is_empty(), "{:?}", scene.notes);
    let pd = scene.pd.as_mut().unwrap();
    pd.solver = PdSolver::Adr(AdrParams::default());
    pd.refinement.as_mut().unwrap().check_every = 5;
    let n = notes(&mut scene);
    assert!(
        n.iter()
            .any(|n| n.starts_with("pd.solver (Adr) is not read"))
            && n.iter()
                .any(|n| n.starts_with("pd.refinement.check_every = 5")),
        "{n:?}"
    );
    // Adaptive dynamics: the conjugate-gradient tolerance is the field it does not read.
    let mut scene = case("seed004_branching_case2_adaptive", &[]);
    assert!(notes(&mut scene).is_empty(), "{:?}", scene.notes);
    scene
        .pd
        .as_mut()
        .unwrap()
        .refinement
        .as_mut()
        .unwrap()
        .tolerance = 1e-6;
    let n = notes(&mut scene);
    assert!(
        n.len() == 1 && n[0].starts_with("pd.refinement.tolerance = 1e-6 is not read"),
        "{n:?}"
    );
}

#[test]
fn an_infinite_plate_reference_on_a_finite_body_is_noted() {
    // first_scene: a 0.1 m crack at the centre of a 1 x 0.5 m plate, K_I 4.7 % above the
    // infinite plate's closed form (docs/scene.md); the note gives the distance of the
    // nearest edge in half crack lengths.
    let scope = |scene: &Scene| {
        let r = scene.reference.as_ref().expect("a reference");
        r.scope_note(scene)
    };
    let first = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/cases/first_scene.ron"
    ))
    .unwrap();
    let note = scope(&first).expect("a finite plate is noted");
    assert!(
        note.contains("nearest edge is 5.0 half crack lengths"),
        "{note}"
    );
    assert!(first.notes.contains(&note), "{:?}", first.notes);
    // Ten times the plate: 50 half-lengths.
    let large = case(
        "first_scene",
        &[
            ("body.outline.Rectangle.x0", "-4.5"),
            ("body.outline.Rectangle.y0", "-2.25"),
            ("body.outline.Rectangle.width", "10"),
            ("body.outline.Rectangle.height", "5"),
        ],
    );
    let note = scope(&large).expect("still finite");
    assert!(
        note.contains("nearest edge is 50.0 half crack lengths"),
        "{note}"
    );
    assert_eq!(
        large.notes,
        vec![note],
        "the edited scene carries its own note"
    );
    // A hole by the crack of the infinite plate (k1_err +45 % on the finite plate, no word
    // before), and Kirsch's hole in a finite plate (hoop peak +12 %, no word before).
    let hole = r#"[{"Circle": {"center": [1.7072, 1.7072], "radius": 1}}]"#;
    let note = scope(&case("inclined_crack_45", &[("body.holes", hole)])).expect("noted");
    assert!(
        note.contains("it holds 1 other hole(s) and 0 other crack(s)"),
        "{note}"
    );
    let square = r#"{"Rectangle": {"x0": -5, "y0": -5, "width": 10, "height": 10}}"#;
    let pulled =
        r#"[{"on": "left", "x": {"Traction": -1}}, {"on": "right", "x": {"Traction": 1}}]"#;
    let kirsch = case(
        "kirsch_hole",
        &[
            ("body.outline", square),
            ("boundary", pulled),
            ("outputs.grids", "[]"),
            ("outputs.lines", "[]"),
        ],
    );
    let note = scope(&kirsch).expect("noted");
    assert!(
        note.contains("Kirsch is the infinite plate's closed form for one hole")
            && note.contains("nearest edge is 5.0 hole radii"),
        "{note}"
    );
    // The infinite plate is the reference's own body; SENT is not an idealisation of it.
    assert_eq!(scope(&case("kirsch_hole", &[])), None);
    assert_eq!(scope(&case("inclined_crack_45", &[])), None);
    assert_eq!(scope(&case("sent_bem_a5", &[])), None);
}

/// `pd_edge_crack` (seed 001's plate, 50 x 50 nodes) with G_c = 1e-6 J/m^2: its ramp's
/// first load, 5 MPa, breaks the bonds of 99.7 % of the plate's volume, and the run gave a
/// kink of 0 degrees and an initiation load beside a note that blamed the solver
/// tolerance. Now a note says the body broke throughout and the kinks are null; the
/// seed's G_c (110 J/m^2) on the same grid gets no such note and a kink.
#[test]
fn an_initiation_ramp_that_breaks_the_body_throughout_is_noted() {
    let run = |g_c: &str, tag: &str| {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/pd_edge_crack.ron"),
        )
        .unwrap()
        .replace("g_c: 110", &format!("g_c: {g_c}"))
        .replace("nx: 200", "nx: 50");
        let scene = Scene::from_ron_str(&text, std::path::Path::new("edge.ron")).unwrap();
        let dir =
            std::env::temp_dir().join(format!("pdbem-throughout-{tag}-{}", std::process::id()));
        let s = pdbem::runner::run_scene(&scene, &dir, false).expect("runs");
        let _ = std::fs::remove_dir_all(&dir);
        s
    };
    let shattered = run("1e-6", "tiny");
    // The check's note on the final load, logged before the run started, comes first.
    assert!(
        shattered.notes[0].starts_with("boundary.0.y: the final load's nominal strain"),
        "{:?}",
        shattered.notes
    );
    assert!(
        has_note(
            &shattered,
            &[
                "99.7 % of the body's volume is past damage 0.4",
                "kink angles are left out"
            ]
        ),
        "{:?}",
        shattered.notes
    );
    assert!(
        shattered.extra["kink_deg"].is_null(),
        "{}",
        shattered.extra["kink_deg"]
    );
    let seed = run("110", "seed");
    assert!(
        !has_note(&seed, &["of the body's volume is past damage"]),
        "{:?}",
        seed.notes
    );
    assert!(seed.extra["kink_deg"].is_f64());

    // The ramp on refined particles (seed 004's Table 2 plate at dx = 2 mm, G_c = 1e-4
    // J/m^2 for 1000): 99.4 % of its volume.
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases/seed004_edge_crack_initiation_adaptive.ron"),
    )
    .unwrap()
    .replace("g_c: 1000", "g_c: 1e-4")
    .replace("dx: 0.001", "dx: 0.002");
    let scene = Scene::from_ron_str(&text, std::path::Path::new("adaptive.ron")).unwrap();
    let dir = std::env::temp_dir().join(format!("pdbem-throughout-p-{}", std::process::id()));
    let s = pdbem::runner::run_scene(&scene, &dir, false).expect("runs");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        has_note(&s, &["99.4 % of the body's volume"]),
        "{:?}",
        s.notes
    );
    assert!(s.extra["kink_deg"].is_null());
}

/// `pdbem check` notes a quasi-static PD ramp whose final load's nominal strain is at
/// least 10 times the bonds' damage onset: `pd_three_point_bend` with s_m = 1e-5 (1617
/// times; its run had not ended after 5 minutes, the shipped one takes 81 s) and
/// `pd_edge_crack` with G_c = 1e-6 J/m^2 (5312 times at nx = 50); the shipped cases stay
/// below 1.8 and get no such note.
#[test]
fn check_notes_a_final_load_far_past_the_damage_onset() {
    let notes = |file: &str, from: &str, to: &str| {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("cases")
                .join(file),
        )
        .unwrap();
        assert!(text.contains(from), "{file}: {from}");
        let scene =
            Scene::from_ron_str(&text.replace(from, to), std::path::Path::new(file)).unwrap();
        pdbem::setup::footprint::of(&scene)
            .expect("footprint")
            .notes
    };
    let bend = notes(
        "pd_three_point_bend.ron",
        "s_m: 0.016, s_c: 0.02",
        "s_m: 0.00001, s_c: 0.00002",
    );
    assert!(
        bend.iter().any(|n| n
            .starts_with("boundary.2.y: the final load's nominal strain 1.617e-2")
            && n.contains("is 1617 times the bonds' damage onset 1.000e-5")),
        "{bend:?}"
    );
    let edge = notes("pd_edge_crack.ron", "nx: 200", "nx: 50");
    assert!(
        !edge.iter().any(|n| n.contains("nominal strain")),
        "{edge:?}"
    );
    let edge = notes("pd_edge_crack.ron", "g_c: 110", "g_c: 1e-6");
    assert!(
        edge.iter()
            .any(|n| n.contains("times the bonds' damage onset")),
        "{edge:?}"
    );
    for file in ["pd_three_point_bend.ron", "pd_notched_bar_adaptive.ron"] {
        let n = notes(file, "(", "(");
        assert!(
            !n.iter().any(|n| n.contains("nominal strain")),
            "{file}: {n:?}"
        );
    }
}

/// An edge crack at 2 degrees to its edge cuts a flap 3 m long and at most 0.1 m thick
/// off a 20 m x 10 m plate; pulled by 1 Pa (E = 1e4 Pa) the linear solution bends it by
/// more than the plate's size (CMOD 138 m, estimate 147 m): a note says the
/// small-displacement solution no longer describes it. At 60 degrees (no flap) none.
#[test]
fn a_cmod_beyond_a_tenth_of_the_crack_is_noted() {
    let plate = |angle: f64| {
        let text = format!(
            r#"(name: "flap", description: "an edge crack nearly along its edge",
            material: (E: 1e4, nu: 0.3, plane: Stress),
            body: (outline: Rectangle(x0: 0, y0: 0, width: 20, height: 10)),
            cracks: [(name: "crack", start: (5, 0), angle_deg: {angle}, length: 3)],
            boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))])"#
        );
        Scene::parse(&text, std::path::Path::new("flap.ron")).unwrap()
    };
    let s = reviewed(&plate(2.0));
    let cmod = s.cracks[0].cmod.unwrap();
    assert!(cmod > 20.0, "{cmod}");
    assert!(
        has_note(&s, &["crack crack: CMOD is", "small-displacement"]),
        "{:?}",
        s.notes
    );
    let s = reviewed(&plate(60.0));
    assert!(!has_note(&s, &["small-displacement"]), "{:?}", s.notes);
}

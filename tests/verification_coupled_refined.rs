//! Refined PD windows (`coupling.refine`, `pdbem_pd::mixed`): the SENT plate a/W = 0.5
//! with nu = 0.3 and a state-based window coarse at its interface (dx = 0.1 m) and fine at
//! the tip must give the CMOD of the BEM-only solve of the same plate within 1 %, as the
//! uniform window does (`verification_coupled_state_based.rs`), with the zone at one and
//! at two levels; a zone reaching within two horizons of a window side is refused.

mod scene_validation_common;

use pdbem::scene::{Scene, WindowRefine};
use scene_validation_common::{assert_invalid, base_with};

/// (coupled CMOD, PD nodes) with the zone `refine`.
fn coupled(refine: WindowRefine) -> (f64, usize) {
    let mut s = Scene::load("cases/coupled_sent_a5_refined.ron").unwrap();
    s.coupling.as_mut().unwrap().refine = Some(refine);
    let (sum, out) = pdbem::run_coupled::solve(&s).unwrap();
    let nodes = out
        .setup
        .problem
        .windows
        .iter()
        .map(|w| w.model.n_real())
        .sum();
    (sum.cracks[0].cmod.unwrap(), nodes)
}

#[test]
fn sent_a5_refined_window_cmod_within_one_percent_of_bem_alone() {
    let mut bem = Scene::load("cases/sent_bem_a5.ron").unwrap();
    bem.material.nu = 0.3;
    let (sb, _) = pdbem::run_bem::solve(&bem).unwrap();
    let b = sb.cracks[0].cmod.unwrap();
    for (levels, nodes) in [(1, 508), (2, 700)] {
        let (c, n) = coupled(WindowRefine {
            half_size: 0.3,
            levels,
        });
        let err = c / b - 1.0;
        println!("levels {levels}: coupled CMOD {c:.6e}, BEM alone {b:.6e}, difference {err:+.4}, {n} PD nodes");
        // Measured: +0.44 % (levels 1, 508 nodes) and +0.35 % (levels 2, 700 nodes);
        // uniform windows of the same side: n = 20 +0.48 % (400 nodes), n = 40 +0.26 %
        // (1600), n = 80 +0.13 % (6400) (docs/coupled_refined.md).
        assert_eq!(n, nodes);
        assert!(err.abs() < 0.01, "levels {levels}: {err}");
    }
}

#[test]
fn refine_zone_must_keep_two_horizons_from_the_window_sides() {
    let pd = "pd: (model: StateBased)";
    // side 2, n = 20: dx = 0.1, 2 delta = 0.603, so half_size <= 1 - 0.603 - 0.05 = 0.347.
    let co = |r: &str| format!("{pd}, coupling: (side: 2, n: 20, refine: {r})");
    assert_invalid(
        &base_with(&co("(half_size: 0.4, levels: 1)")),
        "coupling.refine.half_size",
        "two horizons",
    );
    assert_invalid(
        &base_with(&co("(half_size: 0.3, levels: 3)")),
        "coupling.refine.levels",
        "1 (4 children) or 2",
    );
    assert_invalid(
        &base_with(&co("(half_size: 0, levels: 1)")),
        "coupling.refine.half_size",
        "",
    );
    assert!(scene_validation_common::load(&base_with(&co("(half_size: 0.3, levels: 2)"))).is_ok());
    // The tanh law acts on each pair's normalised stretch on mixed spacing
    // (pd/tests/verification_mixed_spacing.rs).
    assert!(scene_validation_common::load(&base_with(
        "pd: (failure: Degradation(s_m: 0.01, s_c: 0.02, beta: 3)), coupling: (side: 2, n: 20, refine: (half_size: 0.3, levels: 1))",
    ))
    .is_ok());
}

/// The PD-BEM growth history of the valid scene `sc` (outputs discarded; `tag` names the
/// scratch folder).
fn grow(sc: &Scene, tag: &str) -> pdbem::growth::GrowthHistory {
    sc.validate().unwrap();
    let dir = std::env::temp_dir().join(format!("pdbem-refined-{tag}-{}", std::process::id()));
    let ctx = pdbem::runner::RunContext::new(&dir, true).unwrap();
    let h = pdbem::growth::pd_bem::run(sc, &ctx).unwrap();
    ctx.writer.abort();
    h
}

/// Growth with a refined window (`coupling/src/growth/fine_zone.rs`): the tension plate's
/// mode-I crack (along x = 10 m) with the seed's 2 m window of 20 x 20 cells and a level-1
/// zone of 0.3 m (fine dx 0.05 m), moved by 0.35 m, the longest move its zone holds
/// (`pdbem check` refuses the case's 0.5 m). Before the crack was kept in the fine cells,
/// its tip ran past the zone's end before every move and the path wandered 0.05-0.18 m
/// off the line by y = 6.8 m (docs/coupled_refined.md).
#[test]
fn refined_window_growth_keeps_the_path_on_the_line() {
    let mut sc = Scene::load("cases/growth_tension_edge.ron").unwrap();
    sc.pd.as_mut().unwrap().failure = pdbem::scene::Failure::FromGc;
    let co = sc.coupling.as_mut().unwrap();
    co.refine = Some(WindowRefine {
        half_size: 0.3,
        levels: 1,
    });
    let gr = sc.growth.as_mut().unwrap();
    gr.sif_spacing = Some(0.0);
    gr.move_distance = Some(0.5);
    let text = sc.validate().unwrap_err().to_string();
    assert!(
        text.contains("growth.move_distance") && text.contains("at most 0.3500 m"),
        "{text}"
    );
    let gr = sc.growth.as_mut().unwrap();
    gr.move_distance = Some(0.35);
    gr.elements_per_extension = 4;
    let h = grow(&sc, "growth");
    // Measured: failure at load 3.3, 23 moves, the tip on the bottom edge.
    assert!(h.failure, "no structural failure");
    assert!(h.relocations.len() >= 15, "{} moves", h.relocations.len());
    let path = &h.paths[0].points;
    assert!(path.last().unwrap().y < 0.05, "ends at {:?}", path.last());
    // Down to y = 2 m, before the last windows: measured 0.003 m off the line, a
    // sixteenth of a fine dx; before the fine-cell rule, 0.1 m by y = 6.8 m.
    let off = |lo: f64| {
        path.iter()
            .filter(|p| p.y > lo)
            .map(|p| (p.x - 10.0).abs())
            .fold(0.0, f64::max)
    };
    assert!(
        off(2.0) < 0.025,
        "path {:.4} m off the crack line",
        off(2.0)
    );
    // The window against the bottom edge holds the tip 0.3 m above the zone its top
    // interface side allows: the crack grows 0.1 m through coarse cells into the zone,
    // which then follows it to the edge in place. Measured 0.100 m off the line at most
    // (the uniform 40 x 40 window: 0.06 m); through coarse cells all the way, 0.17 m.
    assert!(
        off(-1.0) < 0.12,
        "path {:.4} m off the crack line",
        off(-1.0)
    );
}

/// A growth scene with refinement levels the mixed grid does not build is refused for the
/// levels alone (no move-distance rule computed from them, no overflowing shift).
#[test]
fn refined_growth_with_bad_levels_names_the_levels_only() {
    let mut sc = Scene::load("cases/growth_tension_edge_refined.ron").unwrap();
    sc.coupling.as_mut().unwrap().refine = Some(WindowRefine {
        half_size: 0.55,
        levels: 40,
    });
    let text = sc.validate().unwrap_err().to_string();
    assert!(text.contains("coupling.refine.levels"), "{text}");
    assert!(!text.contains("growth.move_distance"), "{text}");
}

/// `cases/growth_tension_edge_refined.ron` (3 m windows, level-1 zone of 0.55 m, 0.5 m
/// moves) to the bottom edge. The last window sits against that edge; its zone is
/// re-centred on the tip in place (relocation records from a window to itself) and
/// reaches the free edge, so the crack runs through fine cells all the way. Measured:
/// 0.001 m off the line everywhere (0.003 m from the uniform 60 x 60 window at the fine
/// spacing); with the last stretch through coarse cells, as before the re-zoning, 0.021 m.
#[test]
fn refined_windows_keep_the_crack_in_fine_cells_up_to_the_edge() {
    let mut sc = Scene::load("cases/growth_tension_edge_refined.ron").unwrap();
    sc.growth.as_mut().unwrap().sif_spacing = Some(0.0);
    let h = grow(&sc, "edge");
    assert!(h.failure, "no structural failure");
    let in_place = h.relocations.iter().filter(|r| r.from == r.to).count();
    assert!(
        in_place >= 1,
        "no re-zoning in {} relocations",
        h.relocations.len()
    );
    let path = &h.paths[0].points;
    assert!(path.last().unwrap().y < 1e-9, "ends at {:?}", path.last());
    let off = path.iter().map(|p| (p.x - 10.0).abs()).fold(0.0, f64::max);
    assert!(off < 0.01, "path {off:.4} m off the crack line");
}

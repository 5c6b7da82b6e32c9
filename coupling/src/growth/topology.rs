//! Whether a macro layout leaves the BEM body in one piece.
//!
//! Seen from BEM, a crack is a cut from one of its ends to the other; a window is a hole
//! whose inside PD carries. Take a graph whose nodes are the outline and the windows, with
//! an edge for each window reaching the outline and an edge for each crack between the
//! nodes its two ends are attached to (an end on the outline, or inside a window; a free
//! tip in the BEM body attaches to nothing). A cycle in this graph closes a chain of cuts
//! around part of the BEM body, which then hangs on PD alone. The growth driver notes the
//! moment (the crack has cut through everything BEM carries, only the window's ligament
//! is left) and goes on: the coupling holds such a piece by its equilibrium
//! ([`crate::floating`]) until the crack reaches the outline (seed 002 Algorithm 2
//! step 9: structural failure).

use pdbem_bem::V2;

use crate::setup::Layout;
use crate::window::{Body, SideKind, Window};
use pdbem_geometry::polygon_distance;

/// Union-find root with path halving.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Node of a crack end: 0 for the outline, `1 + i` for window `i`, None when free.
fn attachment(p: V2, windows: &[Window], body: &Body, tol: f64) -> Option<usize> {
    if polygon_distance(&p, &body.outline) <= tol {
        return Some(0);
    }
    windows
        .iter()
        .position(|w| w.contains(p, tol))
        .map(|i| i + 1)
}

/// The windows of `layout` that can be placed in `body`.
fn placed_windows(layout: &Layout, body: &Body) -> Vec<Window> {
    layout
        .windows
        .iter()
        .enumerate()
        .filter_map(|(i, s)| Window::place(i, s.clone(), body).ok())
        .collect()
}

/// The graph's edges from the outline (node 0) to every window (node i + 1) with a side
/// on it.
fn outline_edges(windows: &[Window]) -> Vec<(usize, usize)> {
    windows
        .iter()
        .enumerate()
        .filter(|(_, w)| w.sides.contains(&SideKind::Outer))
        .map(|(i, _)| (0, i + 1))
        .collect()
}

/// Whether the cracks of `layout` from index `first` on (cracks joining a tip to a hole,
/// [`crate::growth::driver::join_name`]) close a chain of cuts: the graph of the module
/// docs with every hole a node too, the outline-window edges and the cracks before
/// `first` joined first (a cycle among them is the state the run was already in), then
/// the joining cracks one by one. Returns the index (from `first`) of the first joining
/// crack that closes a cycle: a crack from the outline into a hole and another from the
/// hole to the outline, or from a hole back to it, cut a piece of the body off.
pub fn join_cuts(layout: &Layout, body: &Body, first: usize) -> Option<usize> {
    let windows = placed_windows(layout, body);
    let tol = windows.iter().map(Window::tol).fold(1e-12, f64::max);
    let nw = windows.len();
    let node = |p: V2| {
        attachment(p, &windows, body, tol).or_else(|| {
            body.holes
                .iter()
                .position(|h| polygon_distance(&p, h) <= tol)
                .map(|i| 1 + nw + i)
        })
    };
    let mut parent: Vec<usize> = (0..=nw + body.holes.len()).collect();
    let mut edges = outline_edges(&windows);
    let ends = |c: &crate::setup::MacroCrack| {
        let (a, b) = (c.points[0], *c.points.last().expect("a crack has points"));
        node(a).zip(node(b))
    };
    edges.extend(layout.cracks.iter().take(first).filter_map(ends));
    for (x, y) in edges {
        let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
        parent[rx] = ry;
    }
    for (k, c) in layout.cracks.iter().enumerate().skip(first) {
        let Some((x, y)) = ends(c) else { continue };
        let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
        if rx == ry {
            return Some(k - first);
        }
        parent[rx] = ry;
    }
    None
}

/// Whether the cracks and windows of `layout` cut the BEM body of `body` apart (see the
/// module docs). Windows that cannot be placed count as not reaching the outline.
pub fn cuts_body(layout: &Layout, body: &Body) -> bool {
    let windows = placed_windows(layout, body);
    if windows.len() != layout.windows.len() {
        return false;
    }
    let tol = windows.iter().map(Window::tol).fold(1e-12, f64::max);
    let mut parent: Vec<usize> = (0..=windows.len()).collect();
    let mut edges = outline_edges(&windows);
    for c in &layout.cracks {
        let (a, b) = (c.points[0], *c.points.last().expect("a crack has points"));
        if let (Some(x), Some(y)) = (
            attachment(a, &windows, body, tol),
            attachment(b, &windows, body, tol),
        ) {
            edges.push((x, y));
        }
    }
    for (x, y) in edges {
        let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
        if rx == ry {
            return true;
        }
        parent[rx] = ry;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pd_window::PdSettings;
    use crate::setup::MacroCrack;
    use crate::window::WindowSpec;
    use pdbem_bem::mesh::{FaceMode, LoopSpec};

    fn layout(cracks: Vec<Vec<V2>>, windows: Vec<V2>) -> (Layout, Body) {
        let outline = vec![
            V2::new(0.0, 0.0),
            V2::new(20.0, 0.0),
            V2::new(20.0, 10.0),
            V2::new(0.0, 10.0),
        ];
        let l = Layout {
            outline: LoopSpec {
                points: outline.clone(),
                edge_groups: vec!["e".into(); 4],
                edge_sizes: vec![0.1; 4],
                is_hole: false,
            },
            holes: vec![],
            cracks: cracks
                .into_iter()
                .enumerate()
                .map(|(i, points)| MacroCrack {
                    name: format!("c{i}"),
                    points,
                    faces: FaceMode::Coincident,
                    element_size: 0.1,
                    segment_elements: false,
                })
                .collect(),
            windows: windows
                .into_iter()
                .map(|center| WindowSpec {
                    center,
                    angle: 0.0,
                    dx: 0.1,
                    nx: 20,
                    ny: 20,
                    horizon_factor: 3.015,
                })
                .collect(),
            pd: PdSettings {
                youngs_modulus: 1.0,
                thickness: 1.0,
                plane: pdbem_pd::Plane::Stress,
                failure: pdbem_pd::Failure::None,
                surface_correction: false,
                bulk_correction: false,
                material: pdbem_pd::PdMaterial::Pmb,
                crack_face_correction: false,
                refine: None,
            },
        };
        let body = Body {
            outline,
            holes: vec![],
        };
        (l, body)
    }

    #[test]
    fn edge_crack_into_an_interior_window_keeps_the_body_whole() {
        let (l, b) = layout(
            vec![vec![V2::new(10.0, 10.0), V2::new(10.0, 5.0)]],
            vec![V2::new(10.0, 5.0)],
        );
        assert!(!cuts_body(&l, &b));
    }

    #[test]
    fn window_reaching_the_outline_under_an_edge_crack_cuts() {
        let (l, b) = layout(
            vec![vec![V2::new(10.0, 10.0), V2::new(10.0, 1.0)]],
            vec![V2::new(10.0, 1.0)],
        );
        assert!(cuts_body(&l, &b));
    }

    #[test]
    fn two_edge_cracks_in_one_window_cut() {
        let (l, b) = layout(
            vec![
                vec![V2::new(0.0, 5.0), V2::new(9.5, 5.0)],
                vec![V2::new(20.0, 5.0), V2::new(10.5, 5.0)],
            ],
            vec![V2::new(10.0, 5.0)],
        );
        assert!(cuts_body(&l, &b));
        // In two separate interior windows they do not.
        let (l, b) = layout(
            vec![
                vec![V2::new(0.0, 5.0), V2::new(7.0, 5.0)],
                vec![V2::new(20.0, 5.0), V2::new(13.0, 5.0)],
            ],
            vec![V2::new(7.0, 5.0), V2::new(13.0, 5.0)],
        );
        assert!(!cuts_body(&l, &b));
    }

    #[test]
    fn a_crack_joined_to_a_hole_cuts_only_when_it_closes_a_chain() {
        // A hole [9, 11] x [2, 3]; an edge crack down from the top edge into a window
        // [9, 11] x [5, 7], joined from its tip (10, 6) to the hole rim (10, 3).
        let hole = vec![
            V2::new(9.0, 2.0),
            V2::new(9.0, 3.0),
            V2::new(11.0, 3.0),
            V2::new(11.0, 2.0),
        ];
        let edge = vec![V2::new(10.0, 10.0), V2::new(10.0, 6.0)];
        let join = vec![V2::new(10.0, 6.0), V2::new(10.0, 3.0)];
        let (l, mut b) = layout(vec![edge.clone(), join.clone()], vec![V2::new(10.0, 6.0)]);
        b.holes = vec![hole.clone()];
        assert_eq!(join_cuts(&l, &b, 1), None);
        // Another crack from the left edge into the hole: outline - window - hole -
        // outline, the join closes the chain.
        let side = vec![V2::new(0.0, 2.5), V2::new(9.0, 2.5)];
        let (l, mut b) = layout(vec![edge, side, join], vec![V2::new(10.0, 6.0)]);
        b.holes = vec![hole];
        assert_eq!(join_cuts(&l, &b, 2), Some(0));
    }
}

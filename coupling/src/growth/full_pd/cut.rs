//! Whether the cracks of the damage field cut the body through (full-PD failure, step 4
//! of the module docs of [`super`]).

use pdbem_geometry::{point_segment_distance, P2};
use pdbem_pd::crack_path::{crack_clusters, PathParams};

use super::rounds::pd_fail;
use crate::error::CouplingError;
use crate::growth::front::{BoundaryGraph, Front};

/// A cut found by [`crack_cuts_body`]: the two contacts of the link that closed it and
/// the holes it runs through.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Cut {
    /// A contact of each end of the closing link (on the outline or a hole).
    pub contacts: (P2, P2),
    /// Names of the holes in the cut's chain of cracks: those it runs through, and any
    /// other hole cracks had joined to its boundaries before (empty for one crack from
    /// outline to outline).
    pub holes: Vec<String>,
}

impl Cut {
    /// The note of a run that this cut ended at load step `step` (load factor `load`).
    pub fn note(&self, step: usize, load: f64) -> String {
        let through = match &self.holes[..] {
            [] => String::new(),
            holes => format!(" through the hole(s) {}", holes.join(", ")),
        };
        let (a, b) = self.contacts;
        format!(
            "load {load} (step {step}): the damage cuts the body{through}, the last link \
             between ({:.4e}, {:.4e}) and ({:.4e}, {:.4e}) m",
            a.x, a.y, b.x, b.y
        )
    }
}

/// Whether the macro cracks ([`crack_clusters`] of the damage `phi` of the real nodes at
/// `x`) cut the body through, by the rule of [`Front::separated`] applied to the damage
/// itself, so that it also sees cracks no tracked tip followed (on the shear plate a crack
/// from the end of the bottom clamp up to the kink of the main crack, seed 002 section
/// 3.2.3; on the hole plate a crack from the hole's far side to the outline after the
/// tracked tip ran into the hole). The boundaries (the outline and each hole) are the
/// nodes of a graph; a cluster links the boundaries it touches (a node within one dx of
/// them), once per stretch of contact (contacts linked within two horizons,
/// [`single_linkage`]). A cycle cuts a piece off: one crack reaching the outline at two
/// places, a crack from the outline into a hole and another from the hole to the outline,
/// or a crack from a hole back to it.
pub(super) fn crack_cuts_body(
    x: &[[f64; 2]],
    phi: &[f64],
    front: &Front,
    params: &PathParams,
    (dx, delta): (f64, f64),
) -> Result<Option<Cut>, CouplingError> {
    let names = front.hole_names();
    let phi = with_tracked_cracks(x, phi, front, dx);
    // Node 0 is the outline, node 1 + h hole h.
    let mut graph = BoundaryGraph::new(1 + names.len());
    for cluster in crack_clusters(x, &phi, dx, params).map_err(pd_fail)? {
        let mut touched: Vec<Vec<P2>> = vec![Vec::new(); graph.len()];
        for &i in &cluster {
            let p = P2::new(x[i][0], x[i][1]);
            if front.outline_distance(&p) <= dx {
                touched[0].push(p);
            }
            for (h, d) in front.hole_distances(&p).into_iter().enumerate() {
                if d <= dx {
                    touched[1 + h].push(p);
                }
            }
        }
        let links: Vec<(usize, P2)> = touched
            .iter()
            .enumerate()
            .flat_map(|(b, contacts)| {
                single_linkage(contacts, 2.0 * delta)
                    .into_iter()
                    .map(move |g| (b, contacts[g]))
            })
            .collect();
        for w in links.windows(2) {
            if graph.link(w[0].0, w[1].0) {
                let holes = graph
                    .cycle_nodes(w[0].0)
                    .into_iter()
                    .filter(|&b| b > 0)
                    .map(|b| names[b - 1].to_string())
                    .collect();
                return Ok(Some(Cut {
                    contacts: (w[0].1, w[1].1),
                    holes,
                }));
            }
        }
    }
    Ok(None)
}

/// The damage `phi` with every node within one dx of a tracked crack (its pre-crack and
/// the path traced so far, [`Front::cracks`]) raised to 1. A straight pre-crack leaves
/// its neighbours at a damage of about 0.3, below the macro-crack threshold, so without
/// this a crack grown from an edge pre-crack would not link the outline to the hole (or
/// edge) it ran into.
fn with_tracked_cracks(x: &[[f64; 2]], phi: &[f64], front: &Front, dx: f64) -> Vec<f64> {
    let mut out = phi.to_vec();
    for crack in &front.cracks {
        for seg in crack.points.windows(2) {
            let (a, b) = (seg[0], seg[1]);
            let (lo, hi) = (a.inf(&b).add_scalar(-dx), a.sup(&b).add_scalar(dx));
            for (i, xi) in x.iter().enumerate() {
                let p = P2::new(xi[0], xi[1]);
                let inside = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
                if inside && point_segment_distance(&p, &a, &b) <= dx {
                    out[i] = 1.0;
                }
            }
        }
    }
    out
}

/// One point of every group of `points` linked within `link` (single linkage), in order
/// of first appearance. A damage band along the outline is one group however long it is.
fn single_linkage(points: &[P2], link: f64) -> Vec<usize> {
    let mut group = vec![usize::MAX; points.len()];
    let mut firsts = Vec::new();
    for start in 0..points.len() {
        if group[start] != usize::MAX {
            continue;
        }
        group[start] = start;
        firsts.push(start);
        let mut stack = vec![start];
        while let Some(k) = stack.pop() {
            for j in 0..points.len() {
                if group[j] == usize::MAX && (points[j] - points[k]).norm() <= link {
                    group[j] = start;
                    stack.push(j);
                }
            }
        }
    }
    firsts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::front::FrontCrack;
    use pdbem_geometry::HoleShape;
    use pdbem_pd::{Hole, PdModel, PdProblem, Region};

    /// A 10 m square plate (its outline, no cracks in the front), with a hole of radius
    /// 1.5 m at its centre when `hole`, and a PD model of it at dx = 0.5 m with the
    /// pre-cracks `cracks` (polylines).
    fn plate(cracks: Vec<Vec<[f64; 2]>>, hole: bool) -> (Front, PdModel, f64) {
        plate_tracking(cracks, hole, Vec::new())
    }

    /// [`plate`] whose front tracks the cracks `tracked` (a mouth on the outline).
    fn plate_tracking(
        cracks: Vec<Vec<[f64; 2]>>,
        hole: bool,
        tracked: Vec<FrontCrack>,
    ) -> (Front, PdModel, f64) {
        let outline = vec![
            P2::new(0.0, 0.0),
            P2::new(10.0, 0.0),
            P2::new(10.0, 10.0),
            P2::new(0.0, 10.0),
        ];
        let (centre, radius) = ([5.0, 5.0], 1.5);
        let holes = if hole {
            let shape = HoleShape::Circle {
                center: P2::new(centre[0], centre[1]),
                radius,
            };
            vec![("hole".to_string(), shape)]
        } else {
            Vec::new()
        };
        let front = Front::new(Some(outline), holes, tracked);
        let mut region = Region::rectangle([0.0, 0.0], [10.0, 10.0]);
        if hole {
            region.holes.push(Hole::Circle { centre, radius });
        }
        let p = PdProblem {
            region,
            dx: 0.5,
            youngs_modulus: 1.0,
            cracks,
            ..Default::default()
        };
        let delta = p.horizon();
        (front, PdModel::new(&p).expect("model"), delta)
    }

    fn cut_of(cracks: Vec<Vec<[f64; 2]>>, hole: bool) -> Option<Cut> {
        let (front, model, delta) = plate(cracks, hole);
        let (x, phi) = (model.positions(), model.damage());
        crack_cuts_body(x, &phi, &front, &PathParams::default(), (0.5, delta)).expect("clusters")
    }

    fn cuts(cracks: Vec<Vec<[f64; 2]>>) -> Option<(P2, P2)> {
        cut_of(cracks, false).map(|c| c.contacts)
    }

    #[test]
    fn cracks_chained_through_a_hole_cut_the_body() {
        // From the bottom edge into the hole, and from the hole to the top edge.
        let into = vec![[5.0, -1.0], [5.0, 4.0]];
        let out_top = vec![[5.0, 6.0], [5.0, 11.0]];
        let out_right = vec![[6.0, 5.0], [11.0, 5.0]];
        // Either crack alone leaves the body whole.
        assert_eq!(cut_of(vec![into.clone()], true), None);
        assert_eq!(cut_of(vec![out_top.clone()], true), None);
        // Together they cut it, through the hole; so does the bottom crack with one from
        // the hole to the right edge (a quarter cut off).
        for other in [out_top, out_right] {
            let cut = cut_of(vec![into.clone(), other], true).expect("cut through the hole");
            assert_eq!(cut.holes, vec!["hole".to_string()]);
            assert!(
                cut.note(3, 1.5).contains("through the hole(s) hole"),
                "{cut:?}"
            );
        }
        // A tracked crack from the bottom edge into the hole whose nodes are not damaged
        // (as a pre-crack's neighbours, below the threshold) links the edge to the hole
        // all the same: with a damaged crack from the hole to the top edge it cuts.
        let tracked = FrontCrack {
            name: "a".into(),
            points: vec![P2::new(5.0, 0.0), P2::new(5.0, 3.5)],
            mouth: true,
        };
        let (front, model, delta) =
            plate_tracking(vec![vec![[5.0, 6.0], [5.0, 11.0]]], true, vec![tracked]);
        let (x, phi) = (model.positions(), model.damage());
        let cut = crack_cuts_body(x, &phi, &front, &PathParams::default(), (0.5, delta));
        assert!(cut.expect("clusters").is_some());
        // The same two cracks without the hole are two edge cracks 2 m apart: no cut.
        let apart = vec![vec![[5.0, -1.0], [5.0, 4.0]], vec![[5.0, 6.0], [5.0, 11.0]]];
        assert_eq!(cut_of(apart, false), None);
    }

    #[test]
    fn a_crack_from_outline_to_outline_cuts_the_body_whichever_way_it_runs() {
        // Straight across: contacts on the left and right edges.
        let (a, b) = cuts(vec![vec![[-1.0, 5.0], [11.0, 5.0]]]).expect("cut");
        assert!(a.x < 0.5 && b.x > 9.5, "{a} {b}");
        // Down from the top, along, and back out through the bottom (a kinked crack
        // whose far end no tip tracked).
        let kinked = vec![[5.0, 11.0], [5.0, 5.0], [3.0, 5.0], [3.0, -1.0]];
        assert!(cuts(vec![kinked]).is_some());
    }

    #[test]
    fn edge_cracks_and_damage_along_an_edge_do_not_cut_it() {
        // An edge crack stopping 4 m short of the far edge.
        assert_eq!(cuts(vec![vec![[-1.0, 5.0], [6.0, 5.0]]]), None);
        // Two edge cracks from opposite edges, 2 m apart (two clusters).
        let two = vec![vec![[-1.0, 5.0], [4.0, 5.0]], vec![[6.0, 5.0], [11.0, 5.0]]];
        assert_eq!(cuts(two), None);
        // A damaged band along the whole left edge: one stretch of contacts.
        assert_eq!(cuts(vec![vec![[0.5, -1.0], [0.5, 11.0]]]), None);
    }
}

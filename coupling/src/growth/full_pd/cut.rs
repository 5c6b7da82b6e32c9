//! Whether a crack of the damage field cuts the body through (full-PD failure, step 4 of
//! the module docs of [`super`]).

use pdbem_geometry::P2;
use pdbem_pd::crack_path::{crack_clusters, PathParams};

use super::rounds::pd_fail;
use crate::error::CouplingError;
use crate::growth::front::Front;

/// Whether a macro crack ([`crack_clusters`] of the damage `phi` of the real nodes at
/// `x`) cuts the body: it reaches the outline (a node within one dx of it) at two places,
/// its outline contacts falling into two groups or more when linked within two horizons.
/// The rule of [`Front::separated`] for any crack, also one no tracked tip followed (on
/// the shear plate a crack from the end of the bottom clamp up to the kink of the main
/// crack, seed 002 section 3.2.3). Returns a contact of each of two groups.
pub(super) fn crack_cuts_body(
    x: &[[f64; 2]],
    phi: &[f64],
    front: &Front,
    params: &PathParams,
    (dx, delta): (f64, f64),
) -> Result<Option<(P2, P2)>, CouplingError> {
    for cluster in crack_clusters(x, phi, dx, params).map_err(pd_fail)? {
        let contacts: Vec<P2> = cluster
            .iter()
            .map(|&i| P2::new(x[i][0], x[i][1]))
            .filter(|p| front.outline_distance(p) <= dx)
            .collect();
        let groups = single_linkage(&contacts, 2.0 * delta);
        if let [a, b, ..] = groups[..] {
            return Ok(Some((contacts[a], contacts[b])));
        }
    }
    Ok(None)
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
    use pdbem_pd::{PdModel, PdProblem, Region};

    /// A 10 m square plate (its outline, no cracks in the front) and a PD model of it at
    /// dx = 0.5 m with the pre-cracks `cracks` (polylines).
    fn plate(cracks: Vec<Vec<[f64; 2]>>) -> (Front, PdModel, f64) {
        let outline = vec![
            P2::new(0.0, 0.0),
            P2::new(10.0, 0.0),
            P2::new(10.0, 10.0),
            P2::new(0.0, 10.0),
        ];
        let front = Front::new(Some(outline), Vec::new(), Vec::new());
        let p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [10.0, 10.0]),
            dx: 0.5,
            youngs_modulus: 1.0,
            cracks,
            ..Default::default()
        };
        let delta = p.horizon();
        (front, PdModel::new(&p).expect("model"), delta)
    }

    fn cuts(cracks: Vec<Vec<[f64; 2]>>) -> Option<(P2, P2)> {
        let (front, model, delta) = plate(cracks);
        let (x, phi) = (model.positions(), model.damage());
        crack_cuts_body(x, &phi, &front, &PathParams::default(), (0.5, delta)).expect("clusters")
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

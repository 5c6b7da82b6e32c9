//! Strain watch of the BEM body: where a full-PD model would start a crack that PD-BEM
//! cannot see.
//!
//! PD-BEM lets cracks grow only inside the PD windows; the BEM body around them is linear
//! elastic however far it is strained. In bond-based PD a bond of direction e under a
//! uniform strain has the stretch s = e . eps e (seed 002 Eq. 6 with a small
//! deformation), so the most stretched bond at a point has s = eps_1, the maximum
//! principal strain, and bonds start to break where eps_1 reaches the onset stretch of the
//! windows' bond law (`pdbem_pd::material::BondLaw::damage_onset`: s0 of the PMB law, seed
//! 002 Eqs. 6-7; s_m of the tanh law, seed 000 Eq. 12). After every converged step the BEM strain is therefore sampled one horizon
//! inside the body's boundary (outline, holes, crack faces), where stress concentrations
//! away from the tips sit (clamp ends, corners, holes), at points about half a horizon
//! apart: one horizon from a sharp corner, where the elastic strain is singular, is about
//! where PD, which averages the deformation over the horizon, keeps it finite. Points
//! inside a window (grown by a horizon) or within half a window side of a tip are left
//! out: their strain is the tip's, which the windows model.
//!
//! The field is evaluated where the boundary strain (no integrals) ranks highest: at up to
//! 32 samples four horizons apart, then at every sample around the four most strained of
//! them ([`search`]); on `growth_shear_edge` this finds the same point and load as all
//! samples at both resolutions. On `growth_hole_edge` (904 elements) the run took 16.0 s
//! without the watch, 21.9 s with every sample evaluated and 17.1 s with this search
//! (another run sharing the machine).
//!
//! The sample at depth delta is an estimate of the PD bond stretch, not a bound. Measured
//! on `growth_shear_edge`, whose clamp end (10, 0) starts a second crack in full PD that
//! cuts the plate: the watch fires one horizon above (10, 0) at load 0.20 with dx =
//! 0.05 m, the load at which full PD cuts the plate, and at 0.24 with dx = 0.1 m, one load
//! step after full PD's 0.22 (the strain there at 0.22 is 0.94 s0).

use pdbem_bem::mesh::stencil::{apply, tangential_stencil};
use pdbem_bem::post::field::FieldEvaluator;
use pdbem_bem::{Material, Mesh, Solution, V2};

use crate::window::Window;
use pdbem_geometry::point_segment_projection;

/// The most strained sample of the BEM body.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Hotspot {
    /// Sample position (m).
    pub position: V2,
    /// Maximum principal strain there (-).
    pub strain: f64,
    /// Onset stretch of the windows' failure law (-).
    pub onset: f64,
}

impl Hotspot {
    /// Whether a full-PD model would break bonds there.
    pub fn breaks(&self) -> bool {
        self.strain >= self.onset
    }
}

/// Whether `p` lies in the body meshed by the closed loops of `mesh` (crossing parity:
/// inside the outline, outside its holes and the window openings).
fn in_body(mesh: &Mesh, p: V2) -> bool {
    let mut inside = false;
    for r in &mesh.loops {
        for e in &mesh.elements[r.clone()] {
            let (a, b) = (e.a, e.b);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if x > p.x {
                    inside = !inside;
                }
            }
        }
    }
    inside
}

/// Distance from `p` to the nearest element of `mesh`.
fn distance_to_mesh(mesh: &Mesh, p: V2) -> f64 {
    mesh.elements
        .iter()
        .map(|e| point_segment_projection(&p, &e.a, &e.b).0)
        .fold(f64::INFINITY, f64::min)
}

/// Sample points one horizon `delta` inside the body, behind the elements of `mesh`
/// outside the groups `skip` (the window interfaces), about `delta / 2` apart, each with
/// the element it lies behind. Left out: points closer than `delta / 2` to any element
/// (near a corner or another face, where the evaluation is nearly singular and the point
/// is no longer one horizon deep), outside the body, inside a window grown by `delta`, or
/// within `clear` of a tip.
pub fn sample_points(
    mesh: &Mesh,
    skip: &[usize],
    windows: &[&Window],
    tips: &[V2],
    delta: f64,
    clear: f64,
) -> Vec<(V2, usize)> {
    let mut kept: Vec<(V2, usize)> = Vec::new();
    for (i, e) in mesh.elements.iter().enumerate() {
        if skip.contains(&e.group) {
            continue;
        }
        let p = e.mid - delta * e.normal;
        let free = windows.iter().all(|w| !w.contains(p, delta))
            && tips.iter().all(|t| (p - t).norm() > clear)
            && kept.iter().all(|(q, _)| (p - q).norm() >= 0.5 * delta);
        if free && distance_to_mesh(mesh, p) >= 0.5 * delta && in_body(mesh, p) {
            kept.push((p, i));
        }
    }
    kept
}

/// Maximum principal strain on the boundary at every element, from its traction
/// (sigma_nn, sigma_nt) and the tangential derivative of the boundary displacement
/// (eps_tt, by the stencil of the linear reconstruction, [`tangential_stencil`]); zero
/// tangential strain where the stencil has no neighbours. Cheap (no integrals), it ranks
/// the samples: corners and clamp ends, where the elastic strain is singular, come first.
pub fn boundary_strains(mesh: &Mesh, material: &Material, sol: &Solution) -> Vec<f64> {
    let du = apply(&tangential_stencil(mesh), &sol.u);
    let (two_mu, nu) = (2.0 * material.mu(), material.nu_eff());
    mesh.elements
        .iter()
        .zip(&sol.t)
        .zip(&du)
        .map(|((e, t), g)| {
            let (t, g) = (V2::new(t[0], t[1]), V2::new(g[0], g[1]));
            let (s_nn, s_nt) = (t.dot(&e.normal), t.dot(&e.tangent));
            let e_tt = g.dot(&e.tangent);
            let s_tt = (two_mu * e_tt + nu * s_nn) / (1.0 - nu);
            let e_nn = (s_nn - nu * (s_tt + s_nn)) / two_mu;
            principal_strain([e_tt, e_nn, s_nt / two_mu])
        })
        .collect()
}

/// Up to `count` samples behind the most strained elements (`strains` per element), at
/// least `spread` apart: a sample is passed over when a more strained one was taken within
/// `spread` of it, so that one singular spot (a corner, the kinks of a grown crack face)
/// does not take every place.
pub fn most_strained(
    samples: &[(V2, usize)],
    strains: &[f64],
    count: usize,
    spread: f64,
) -> Vec<V2> {
    let mut ranked: Vec<&(V2, usize)> = samples.iter().collect();
    ranked.sort_by(|a, b| strains[b.1].total_cmp(&strains[a.1]));
    let mut taken: Vec<V2> = Vec::with_capacity(count);
    for (p, _) in ranked {
        if taken.len() == count {
            break;
        }
        if taken.iter().all(|q| (p - q).norm() >= spread) {
            taken.push(*p);
        }
    }
    taken
}

/// Maximum principal strain of the plane strain tensor [exx, eyy, exy].
fn principal_strain(e: [f64; 3]) -> f64 {
    0.5 * (e[0] + e[1]) + (0.25 * (e[0] - e[1]).powi(2) + e[2] * e[2]).sqrt()
}

/// Maximum principal strain at `points` in the field of `eval`.
fn strains_at(eval: &FieldEvaluator, points: &[V2]) -> Vec<f64> {
    let material = *eval.material();
    eval.stresses(points)
        .into_iter()
        .map(|s| principal_strain(material.strain_from_stress(s)))
        .collect()
}

/// The most strained of `points` in the field of `eval` (its BEM solution and remote
/// stress at the current load).
pub fn hottest(eval: &FieldEvaluator, points: &[V2], onset: f64) -> Option<Hotspot> {
    strains_at(eval, points)
        .into_iter()
        .zip(points)
        .map(|(strain, p)| Hotspot {
            position: *p,
            strain,
            onset,
        })
        .max_by(|a, b| a.strain.total_cmp(&b.strain))
}

/// How many samples [`search`] evaluates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchSize {
    /// Spread-out candidates ([`most_strained`]).
    pub candidates: usize,
    /// Least distance between candidates (m).
    pub spread: f64,
    /// Candidates around which every sample within `spread` is evaluated too.
    pub refined: usize,
}

/// The most strained sample, found in two passes: the spread-out candidates of
/// [`most_strained`] (ranked by the boundary strains `ranks`), then every sample around
/// the most strained of them, since the boundary ranking picks a region, not the deepest
/// point of its interior field.
pub fn search(
    eval: &FieldEvaluator,
    samples: &[(V2, usize)],
    ranks: &[f64],
    onset: f64,
    size: SearchSize,
) -> Option<Hotspot> {
    let coarse = most_strained(samples, ranks, size.candidates, size.spread);
    let strains = strains_at(eval, &coarse);
    let mut order: Vec<usize> = (0..coarse.len()).collect();
    order.sort_by(|&a, &b| strains[b].total_cmp(&strains[a]));
    let centres: Vec<V2> = order
        .iter()
        .take(size.refined)
        .map(|&i| coarse[i])
        .collect();
    let near: Vec<V2> = samples
        .iter()
        .map(|s| s.0)
        .filter(|p| centres.iter().any(|c| (p - c).norm() < size.spread))
        .collect();
    // The centres are samples themselves, so the most strained candidate is among `near`.
    hottest(eval, &near, onset)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::window::{SideKind, WindowSpec};
    use pdbem_bem::mesh::LoopSpec;
    use pdbem_bem::{MeshBuilder, Plane as BemPlane};

    /// A 4 m x 2 m plate in 0.05 m elements.
    fn plate() -> Mesh {
        let mut b = MeshBuilder::new();
        b.add_loop(LoopSpec::rectangle(0.0, 0.0, 4.0, 2.0, 0.05));
        b.build().unwrap()
    }

    /// The exact boundary data of a uniform stress `s` [sxx, syy, sxy].
    fn uniform(mesh: &Mesh, material: &Material, s: [f64; 3]) -> Solution {
        let e = material.strain_from_stress(s);
        let strain = |d: V2| [e[0] * d.x + e[2] * d.y, e[2] * d.x + e[1] * d.y];
        Solution {
            u: mesh.elements.iter().map(|el| strain(el.mid)).collect(),
            t: mesh
                .elements
                .iter()
                .map(|el| {
                    let n = el.normal;
                    [s[0] * n.x + s[2] * n.y, s[2] * n.x + s[1] * n.y]
                })
                .collect(),
            lambda: Vec::new(),
            du: mesh.elements.iter().map(|el| strain(el.tangent)).collect(),
        }
    }

    #[test]
    fn a_uniform_strain_is_read_back_one_horizon_inside() {
        let mesh = plate();
        let material = Material::new(1e4, 1.0 / 3.0, BemPlane::Stress).unwrap();
        // eps_1 of [sxx, syy, sxy] = [30, -10, 20] Pa, plane stress, nu = 1/3.
        let s = [30.0, -10.0, 20.0];
        let sol = uniform(&mesh, &material, s);
        let e = material.strain_from_stress(s);
        let exact = principal_strain(e);
        assert!((exact - 4.43790e-3).abs() < 1e-8, "{exact}");
        let delta = 0.15;
        let window = Window {
            spec: WindowSpec {
                center: V2::new(1.0, 1.0),
                angle: 0.0,
                dx: 0.05,
                nx: 12,
                ny: 12,
                horizon_factor: 3.0,
            },
            sides: [SideKind::Interface; 4],
        };
        let tip = V2::new(3.0, 1.0);
        let samples = sample_points(&mesh, &[], &[&window], &[tip], delta, 0.5);
        let pts: Vec<V2> = samples.iter().map(|s| s.0).collect();
        assert!(pts.len() > 60, "{} points", pts.len());
        for (i, p) in pts.iter().enumerate() {
            assert!(in_body(&mesh, *p), "{p}");
            assert!(distance_to_mesh(&mesh, *p) >= 0.5 * delta - 1e-12, "{p}");
            assert!(!window.contains(*p, delta) && (p - tip).norm() > 0.5, "{p}");
            assert!(
                pts[..i].iter().all(|q| (p - q).norm() >= 0.5 * delta),
                "{p}"
            );
        }
        // The boundary estimate is exact for a linear displacement field.
        let ranks = boundary_strains(&mesh, &material, &sol);
        for (e, b) in ranks.iter().enumerate() {
            assert!(
                (b / exact - 1.0).abs() < 1e-9,
                "element {e}: {b} vs {exact}"
            );
        }
        let eval = FieldEvaluator::new(&mesh, &material, &sol, Default::default());
        let h = hottest(&eval, &pts, 0.004).unwrap();
        assert!(
            (h.strain / exact - 1.0).abs() < 1e-3,
            "{} vs {exact}",
            h.strain
        );
        assert!(h.breaks());
        assert!(!hottest(&eval, &pts, 0.005).unwrap().breaks());
        // The two-pass search finds the same strain from a few candidates.
        let size = SearchSize {
            candidates: 8,
            spread: 4.0 * delta,
            refined: 2,
        };
        let found = search(&eval, &samples, &ranks, 0.004, size).unwrap();
        assert!((found.strain / exact - 1.0).abs() < 1e-3, "{found:?}");
    }

    #[test]
    fn the_samples_behind_the_most_strained_elements_come_first() {
        let s = |x: f64| (V2::new(x, 0.0), x as usize);
        let samples = [s(0.0), s(1.0), s(2.0), s(3.0)];
        let strains = [0.1, 0.4, 0.2, 0.3];
        let top = most_strained(&samples, &strains, 2, 0.5);
        assert_eq!(top, [V2::new(1.0, 0.0), V2::new(3.0, 0.0)]);
        assert_eq!(most_strained(&samples, &strains, 9, 0.5).len(), 4);
        // Samples within 1.5 of a more strained one are passed over.
        let spread = most_strained(&samples, &strains, 9, 1.5);
        assert_eq!(spread, [V2::new(1.0, 0.0), V2::new(3.0, 0.0)]);
    }
}

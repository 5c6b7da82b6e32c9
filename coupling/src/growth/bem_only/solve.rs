//! One geometry of BEM-only growth, meshed and solved at unit load (the problem is
//! linear: K(f) = f K(1)), with the SIFs of every tip by the crack-opening fit
//! ([`pdbem_bem::post::sif::cod_sif`]).
//!
//! Meshing: with a [`TipSizing`] rule (every scene without user-fixed crack sizes) the
//! local-feature sources of [`super::sizing`]; otherwise each crack at its fixed element
//! size with a uniform tip zone of da/8 within da once cracks have grown.
//!
//! A solved geometry is accepted as a growth state only if no growing tip has K_I < 0
//! and no crack mouth closes (CMOD < 0) at unit load: the linear BEM has no contact, so
//! overlapping faces are not a state of the body, and near a short ligament they are the
//! mark of a mesh too coarse for it. [`Engine::solve_checked`] then refines the tip
//! sources by 2 (sizes and gradings halved, kept for the rest of the run) up to
//! [`MAX_REFINE`] and reports what is still wrong ([`Checked::Overlap`]). A geometry that
//! needed such a refinement is accepted only once K has settled: the growing tips' K_eq
//! within [`SETTLED_K`] and kinks within [`SETTLED_KINK_DEG`] between two successive
//! refinements; else it is refused ([`Checked::Unsettled`]). Before, an edge crack at 1
//! degree to its edge (a 0.17 mm sliver beside 10 mm of crack) overlapped at the first
//! mesh, was accepted at the second with K_I = +4.2e6 Pa m^0.5 where the static BEM gives
//! -5.9e6 +- 2.6e7, and the run declared the body failed at its first load.

use std::time::Instant;

use pdbem_bem::mesh::{CrackSpec, TipRefinement};
use pdbem_bem::post::sif::{cmod, cod_sif, interaction_integral, tip_length_scale};
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::{BemSystem, Mesh, MeshBuilder, PairCache, Solution};

use super::body::{fail, BemOnlyBody};
use super::sizing::{simplify_crack, tip_scales, tip_sources, TipScale, SIMPLIFY_FRACTION};
use crate::error::CouplingError;
use crate::growth::criterion::{mcs, TipSif};
use crate::growth::front::Front;
use crate::growth::records::Scenario;

/// Largest refinement of the tip sources a geometry gets before an overlap ends the run.
pub const MAX_REFINE: f64 = 4.0;

/// Relative change of a growing tip's K_eq between two refinements within which a
/// geometry that overlapped at a coarser mesh counts as settled (module docs).
pub const SETTLED_K: f64 = 0.02;

/// Change of a growing tip's kink angle (degrees) between two refinements within which
/// such a geometry counts as settled.
pub const SETTLED_KINK_DEG: f64 = 1.0;

/// Crack-opening stations wanted within one increment once cracks have grown (meshes
/// without a [`super::sizing::TipSizing`] rule): the fit over them has its four terms.
const STATIONS_PER_INCREMENT: f64 = 8.0;

/// One solved geometry at unit load.
pub(crate) struct Solved {
    pub mesh: Mesh,
    pub solution: Solution,
    pub sifs: Vec<TipSif>,
    /// CMOD of the first crack with a mouth at load factor 1 (m).
    pub cmod: Option<f64>,
    pub solve_s: f64,
    /// Refinement of the tip sources it was meshed with.
    pub refine: f64,
}

/// A solved geometry, or why it is not a growth state.
pub(crate) enum Checked {
    /// Accepted.
    Ok(Box<Solved>),
    /// K_I < 0 at a growing tip or CMOD < 0 at the finest refinement (the message).
    Overlap(String),
    /// Overlapping at a coarser mesh, K not settled by the finest refinement (the message).
    Unsettled(String),
}

/// Fixed meshing data of a run: crack element sizes and increments.
pub(crate) struct Sizes {
    /// Element size of each crack (m): the size cap of its faces.
    pub element: Vec<f64>,
    /// Increment of each crack (m).
    pub da: Vec<f64>,
}

impl Sizes {
    /// Tip refinement of grown geometries without a sizing rule: elements of da / 8 (at
    /// most the crack size) within one increment of every tip.
    fn tip_zone(&self) -> TipRefinement {
        let da = self.smallest_da();
        let h = self.element.iter().copied().fold(f64::INFINITY, f64::min);
        TipRefinement {
            size: h.min(da / STATIONS_PER_INCREMENT),
            radius: da,
        }
    }

    /// The smallest increment (m).
    pub fn smallest_da(&self) -> f64 {
        self.da.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// The context of one run: body, conditions, the pair cache of the last mesh and the
/// refinement of the tip sources.
pub(crate) struct Engine<'a> {
    pub body: &'a BemOnlyBody,
    pub scenario: &'a dyn Scenario,
    pub pairs: PairCache,
    pub refine: f64,
}

impl<'a> Engine<'a> {
    /// A fresh engine (no cached pairs, no refinement).
    pub fn new(body: &'a BemOnlyBody, scenario: &'a dyn Scenario) -> Self {
        Engine {
            body,
            scenario,
            pairs: PairCache::default(),
            refine: 1.0,
        }
    }

    /// Meshes the front's cracks (module docs) and returns the mesh with the fit radius
    /// of every tip (`None`: the static fit of the initial mesh).
    fn mesh(
        &self,
        front: &Front,
        sizes: Option<&Sizes>,
        grown: bool,
    ) -> Result<(Mesh, Option<Vec<TipScale>>), CouplingError> {
        let mut b = MeshBuilder::new();
        for l in &self.body.loops {
            b.add_loop(l.clone());
        }
        let tol = sizes.map_or(0.0, |s| SIMPLIFY_FRACTION * s.smallest_da());
        for (i, spec) in self.body.cracks.iter().enumerate() {
            let mut spec = CrackSpec {
                points: simplify_crack(front, i, tol),
                ..spec.clone()
            };
            if let Some(s) = sizes {
                spec.element_size = s.element[i];
                if grown && self.body.sizing.is_none() {
                    spec.tip = Some(s.tip_zone());
                }
            }
            b.add_crack(spec);
        }
        let scales = match &self.body.sizing {
            Some(rule) => {
                let scales = tip_scales(front, &self.body.loops, self.body.fit_fraction, grown);
                let tips = tip_sources(front, &scales, rule, self.refine);
                b.set_size_field(self.body.field.with(tips));
                Some(scales)
            }
            None => None,
        };
        Ok((b.build()?, scales))
    }

    /// Element size of every crack (the size cap of its faces: the largest element of
    /// its upper face in the initial mesh without a sizing rule) and the increments
    /// (`da`, else each crack's element size).
    pub fn sizes(&self, front: &Front, da: Option<f64>) -> Result<Sizes, CouplingError> {
        let element: Vec<f64> = if self.body.sizing.is_some() {
            self.body.cracks.iter().map(|c| c.element_size).collect()
        } else {
            let (mesh, _) = self.mesh(front, None, false)?;
            mesh.cracks
                .iter()
                .map(|c| {
                    c.upper
                        .iter()
                        .map(|&e| mesh.elements[e].h)
                        .fold(0.0, f64::max)
                })
                .collect()
        };
        let da = match da {
            Some(da) => vec![da; element.len()],
            None => element.clone(),
        };
        Ok(Sizes { element, da })
    }

    /// Meshes and solves the current geometry at unit load, reusing the element-pair
    /// blocks of the last geometry (the outline and the crack away from the tips stay).
    /// `grown`: the cracks have grown (the fit stays on the straight run behind a tip).
    pub fn solve(
        &mut self,
        front: &Front,
        sizes: &Sizes,
        grown: bool,
    ) -> Result<Solved, CouplingError> {
        let t0 = Instant::now();
        let (mesh, scales) = self.mesh(front, Some(sizes), grown)?;
        let bcs = self
            .scenario
            .bem_conditions(&mesh)
            .map_err(|m| fail(format!("boundary conditions: {m}")))?;
        let sys = BemSystem::new_with_cache(
            &mesh,
            &self.body.material,
            &bcs,
            &self.body.params,
            Some(&mut self.pairs),
        )?;
        let solution = sys.solve()?;
        let fit = |t: usize, ci: usize, pos| match &scales {
            Some(s) => s.iter().find(|s| s.tip == t).map_or(0.0, |s| s.fit),
            None => {
                let cap = if grown {
                    sizes.tip_zone().radius
                } else {
                    f64::INFINITY
                };
                (self.body.fit_fraction * tip_length_scale(&mesh, ci, pos)).min(cap)
            }
        };
        let sifs = self.tip_sifs(front, &mesh, &solution, fit)?;
        let cmod = (0..mesh.cracks.len()).find_map(|i| cmod(&mesh, &solution, i));
        Ok(Solved {
            mesh,
            solution,
            sifs,
            cmod,
            solve_s: t0.elapsed().as_secs_f64(),
            refine: self.refine,
        })
    }

    /// [`Engine::solve`], refined while a growing tip has K_I < 0 or a mouth closes, and
    /// after such a refinement until K settles (module docs).
    pub fn solve_checked(
        &mut self,
        front: &Front,
        sizes: &Sizes,
        grown: bool,
    ) -> Result<Checked, CouplingError> {
        // The last solve without an overlap since a coarser mesh overlapped.
        let mut refined = false;
        let mut last: Option<Solved> = None;
        loop {
            let s = self.solve(front, sizes, grown)?;
            let why = overlap(front, &s);
            if why.is_none() && (!refined || self.body.sizing.is_none()) {
                return Ok(Checked::Ok(Box::new(s)));
            }
            let unsettled = match (&why, &last) {
                (None, Some(c)) => match unsettled(front, (&c.sifs, c.refine), (&s.sifs, s.refine)) {
                    None => return Ok(Checked::Ok(Box::new(s))),
                    Some(what) => Some(what),
                },
                (None, None) => Some(format!(
                    "a growing tip's K_I or the mouth's opening was negative at {}x and is not at {}x",
                    self.refine / 2.0,
                    self.refine
                )),
                (Some(_), _) => None,
            };
            if self.body.sizing.is_none() || self.refine >= MAX_REFINE {
                return Ok(match (why, unsettled) {
                    (Some(why), _) => Checked::Overlap(format!(
                        "{why} with the tip elements refined {}x",
                        self.refine
                    )),
                    (None, what) => Checked::Unsettled(format!(
                        "K does not settle as the tip elements are refined up to {}x ({}): the \
                         mesh does not resolve the geometry near the tip (a crack running \
                         close to the outline, a hole or another crack, or a ligament shorter \
                         than the elements), so its K and kink are not known",
                        self.refine,
                        what.unwrap_or_default()
                    )),
                });
            }
            refined = true;
            last = why.is_none().then_some(s);
            self.refine *= 2.0;
        }
    }

    /// SIFs of every tip by the crack-opening fit over r < `fit(tip, crack, position)`,
    /// or by the interaction integral on a contour no larger for the cracks of
    /// [`BemOnlyBody::integral_cracks`].
    fn tip_sifs(
        &self,
        front: &Front,
        mesh: &Mesh,
        solution: &Solution,
        fit: impl Fn(usize, usize, pdbem_geometry::P2) -> f64,
    ) -> Result<Vec<TipSif>, CouplingError> {
        let mut sifs = Vec::new();
        let ev = (!self.body.integral_cracks.is_empty()).then(|| {
            FieldEvaluator::new(mesh, &self.body.material, solution, self.body.background)
        });
        for (ci, at_end, pos, dir) in mesh.tips() {
            let end = if at_end { "end" } else { "start" };
            let name = format!("{}.{end}", mesh.cracks[ci].name);
            let Some(t) = front.tips.iter().position(|f| f.name == name) else {
                continue;
            };
            let r = fit(t, ci, pos);
            let integral = ev
                .as_ref()
                .filter(|_| self.body.integral_cracks.contains(&mesh.cracks[ci].name));
            let (k1, k2) = match integral {
                Some(ev) => {
                    let (fraction, points) = self.body.contour;
                    let radius = (fraction * tip_length_scale(mesh, ci, pos)).min(r);
                    let c = &mesh.cracks[ci];
                    let h_tip = mesh.elements[if at_end {
                        c.upper[c.upper.len() - 1]
                    } else {
                        c.upper[0]
                    }]
                    .h;
                    let (k1, k2, _) =
                        interaction_integral(ev, pos, dir, radius, points, h_tip, Some(ci));
                    (k1, k2)
                }
                None => {
                    let (k1, k2, _) = cod_sif(mesh, &self.body.material, solution, ci, at_end, r);
                    (k1, k2)
                }
            };
            if !(k1.is_finite() && k2.is_finite()) {
                return Err(fail(format!(
                    "tip {name}: no SIF (no crack element within {r:.3e} m of the tip)"
                )));
            }
            let (theta, k_eq) = mcs(k1, k2);
            sifs.push(TipSif {
                tip: t,
                k1,
                k2,
                theta,
                k_eq,
            });
        }
        Ok(sifs)
    }
}

/// How the growing tips' K of a `fine` solve differ from those of a `coarse` one (one
/// refinement coarser), each its SIFs and refinement, beyond [`SETTLED_K`] or
/// [`SETTLED_KINK_DEG`]; `None` when settled.
fn unsettled(
    front: &Front,
    (coarse, coarse_refine): (&[TipSif], f64),
    (fine, fine_refine): (&[TipSif], f64),
) -> Option<String> {
    for f in fine {
        if front.tips[f.tip].ended.is_some() {
            continue;
        }
        let Some(c) = coarse.iter().find(|c| c.tip == f.tip) else {
            continue;
        };
        let dk = (f.k_eq - c.k_eq).abs() / f.k_eq.abs().max(f64::MIN_POSITIVE);
        let dtheta = (f.theta - c.theta).to_degrees().abs();
        if dk > SETTLED_K || dtheta > SETTLED_KINK_DEG {
            return Some(format!(
                "tip {}: K_eq {:.4e} at {}x and {:.4e} Pa m^0.5 at {}x, kink {:.2} and {:.2} degrees",
                front.tips[f.tip].name,
                c.k_eq,
                coarse_refine,
                f.k_eq,
                fine_refine,
                c.theta.to_degrees(),
                f.theta.to_degrees()
            ));
        }
    }
    None
}

/// Why a solved geometry is not a growth state: K_I < 0 at a growing tip, or the first
/// mouth closing (CMOD < 0), at unit load.
fn overlap(front: &Front, s: &Solved) -> Option<String> {
    for t in &s.sifs {
        if front.tips[t.tip].ended.is_none() && t.k1 < 0.0 {
            return Some(format!(
                "K_I = {:.4e} Pa m^0.5 < 0 at tip {} ({:.4}, {:.4}) at unit load",
                t.k1,
                front.tips[t.tip].name,
                front.tip_position(t.tip).x,
                front.tip_position(t.tip).y
            ));
        }
    }
    match s.cmod {
        Some(c) if c < 0.0 => Some(format!("CMOD = {c:.4e} m < 0 at unit load")),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::front::FrontCrack;
    use pdbem_geometry::P2;

    fn sif(k_eq: f64, theta_deg: f64) -> TipSif {
        TipSif {
            tip: 0,
            k1: k_eq,
            k2: 0.0,
            theta: theta_deg.to_radians(),
            k_eq,
        }
    }

    /// K_eq within 2 % and kinks within 1 degree settle; 3 % or 1.5 degrees do not, and
    /// the message names the tip, both values and both refinements.
    #[test]
    fn k_settles_within_two_percent_and_one_degree() {
        let front = Front::new(
            Some(vec![
                P2::new(0.0, 0.0),
                P2::new(1.0, 0.0),
                P2::new(1.0, 1.0),
                P2::new(0.0, 1.0),
            ]),
            Vec::new(),
            vec![FrontCrack {
                name: "c".into(),
                points: vec![P2::new(0.0, 0.5), P2::new(0.2, 0.5)],
                mouth: true,
            }],
        );
        let fine = [sif(1.0e6, 0.0)];
        let close = [sif(1.019e6, 0.9)];
        assert_eq!(unsettled(&front, (&close, 2.0), (&fine, 4.0)), None);
        for off in [[sif(1.03e6, 0.0)], [sif(1.0e6, 1.5)]] {
            let why = unsettled(&front, (&off, 2.0), (&fine, 4.0)).expect("unsettled");
            assert!(why.starts_with("tip c.end: K_eq "), "{why}");
            assert!(why.contains(" at 2x and 1.0000e6 Pa m^0.5 at 4x"), "{why}");
        }
    }
}

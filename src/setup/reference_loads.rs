//! The loads a scene's analytic reference assumes (REFERENCES.md): `SentTada` is Tada's
//! strip under uniform tension sigma across its crack, `InclinedCrackInfinite` uniaxial
//! tension sigma at beta to the crack line, `Kirsch` uniaxial tension sigma. Every
//! reference leaves its holes and crack faces free. A scene whose loads are another
//! problem got k1_err, k2_err, cmod_err and hoop_peak_err against the wrong numbers, with
//! exit code 0 (`sent_bem_a5` with `sigma: 0.7` against its tractions of 0.5 Pa: k1_err
//! = -28.7 %; a shear load under the same reference: cmod_err = -100 %). [`check`] refuses
//! such a scene in `pdbem check` and before every run.
//!
//! The test: the tractions at load factor 1 on every outline element that no
//! displacement condition holds are those of one uniform stress S, n -> S n (the weighted
//! least-squares fit of S over those elements reproduces each to 1e-6 of the largest
//! traction), and S is the reference's, sigma e (x) e, to 1e-6 of |sigma| (Kirsch, and
//! `InclinedCrackInfinite` without `beta_deg`: the principal stresses sigma and 0, e along
//! the first; that reference then takes its K from S, [`load_stress`]). A displacement
//! condition may hold the body only with zero values and only where the outline's normal
//! is along e (a held end of the strip, as `growth_tension_edge` holds its left edge);
//! holes and crack faces carry no condition. An infinite plate's S is its remote stress.

use anyhow::{bail, Result};
use pdbem_bem::{Bc, Mesh};

use super::bem::{conditions, mesh_builder, MissingGroup};
use crate::geometry::P2;
use crate::scene::shapes::SceneGeometry;
use crate::scene::{Reference, Scene};

/// Relative tolerance of every comparison (tractions, stresses, directions).
const TOL: f64 = 1e-6;

/// An error when the loads of `scene` are not those its `reference` assumes; `Ok` without
/// a reference, and for a body the BEM mesher refuses (its own error comes first).
pub fn check(scene: &Scene) -> Result<()> {
    let Some(reference) = &scene.reference else {
        return Ok(());
    };
    let geo = SceneGeometry::of(scene);
    let Some(expected) = expected(reference, &geo) else {
        return Ok(());
    };
    let drop_beta = match reference {
        Reference::InclinedCrackInfinite {
            beta_deg: Some(_), ..
        } => " (or drop beta_deg: the reference then takes the direction of the loads)",
        _ => "",
    };
    let fail = |why: String| -> Result<()> {
        bail!(
            "{}: reference: {}, but this scene {why}: its errors would be against another load; load the body as the reference assumes or remove `reference`{drop_beta}",
            scene.file_label().display(),
            assumes(reference, &expected)
        )
    };
    match scene_stress(scene, &geo, &expected) {
        None => Ok(()),
        Some(Err(why)) => fail(why),
        Some(Ok(s)) if !expected.matches(&s) => fail(format!(
            "loads its body with the uniform stress sxx = {:.6e}, syy = {:.6e}, sxy = {:.6e} Pa at load factor 1",
            s[0], s[1], s[2]
        )),
        Some(Ok(_)) => Ok(()),
    }
}

/// The uniform stress (sxx, syy, sxy) of the loads of `scene` at load factor 1: an
/// infinite plate's remote stress, or the stress whose tractions the outline carries;
/// `None` when the loads are no uniform stress or hold the body other than at the ends of
/// its tension (as [`check`] tests them), or the body cannot be meshed.
pub fn load_stress(scene: &Scene) -> Option<[f64; 3]> {
    let free = Expected {
        sigma: 0.0,
        dir: None,
    };
    scene_stress(scene, &SceneGeometry::of(scene), &free)?.ok()
}

/// The angle (degrees, in [0, 90]) between the line of cracks.0 and the tension of
/// [`load_stress`] (its principal direction of larger magnitude).
pub fn load_beta_deg(scene: &Scene) -> Option<f64> {
    let s = load_stress(scene)?;
    let geo = SceneGeometry::of(scene);
    let c = geo.cracks.first()?;
    let d = c.points.last()? - c.points.first()?;
    let e = Expected {
        sigma: 0.0,
        dir: None,
    }
    .direction(&s);
    let cos = (d.dot(&e) / d.norm()).abs().min(1.0);
    cos.is_finite().then(|| cos.acos().to_degrees())
}

/// [`outline_stress`] on the body's mesh at load factor 1, or the remote stress of an
/// infinite plate whose holes and cracks carry no condition; `None` when the mesher or
/// the conditions refuse the body (their own errors come first).
fn scene_stress(
    scene: &Scene,
    geo: &SceneGeometry,
    expected: &Expected,
) -> Option<std::result::Result<[f64; 3], String>> {
    if geo.outline.is_none() {
        return Some(free_holes_and_faces(scene).map(|_| geo.remote.unwrap_or([0.0; 3])));
    }
    let mesh = mesh_builder(scene, geo, 1.0).ok()?.build().ok()?;
    let bcs = conditions(scene, &mesh, 1.0, None, MissingGroup::Error).ok()?;
    Some(outline_stress(&mesh, &bcs, expected))
}

/// The stress a reference assumes: `sigma e (x) e`, with `e` fixed (`Some`) or free
/// (Kirsch: any direction).
struct Expected {
    sigma: f64,
    dir: Option<P2>,
}

impl Expected {
    /// True when `s` (sxx, syy, sxy) is this stress.
    fn matches(&self, s: &[f64; 3]) -> bool {
        let scale = self.sigma.abs().max(norm(s));
        match self.dir {
            Some(e) => {
                let want = uniaxial(self.sigma, e);
                let off = (0..3).map(|i| (s[i] - want[i]).abs()).fold(0.0, f64::max);
                off <= TOL * scale
            }
            None => {
                let (big, small) = principal(s);
                (big - self.sigma).abs() <= TOL * scale && small.abs() <= TOL * scale
            }
        }
    }

    /// The tension direction: the reference's, or the first principal direction of `s`.
    fn direction(&self, s: &[f64; 3]) -> P2 {
        self.dir.unwrap_or_else(|| {
            let (big, _) = principal(s);
            let (a, b) = (s[0] - big, s[2]);
            let (c, d) = (s[2], s[1] - big);
            // A null vector of S - big I from its larger row.
            let v = if a.hypot(b) >= c.hypot(d) {
                P2::new(-b, a)
            } else {
                P2::new(-d, c)
            };
            let n = v.norm();
            if n > 0.0 {
                v / n
            } else {
                P2::new(1.0, 0.0)
            }
        })
    }
}

/// The stress `reference` assumes, from the scene's first crack; `None` when the crack
/// it needs is missing (validation refuses that scene).
fn expected(reference: &Reference, geo: &SceneGeometry) -> Option<Expected> {
    let chord = || {
        let c = geo.cracks.first()?;
        let d = c.points.last()? - c.points.first()?;
        let n = d.norm();
        (n > 0.0).then(|| d / n)
    };
    match *reference {
        Reference::SentTada { sigma, .. } => {
            // Across the strip (validation holds the crack within a degree of this axis).
            let d = geo
                .cracks
                .first()
                .and_then(|c| geo.mouth_axis(c))
                .or_else(chord)?;
            Some(Expected {
                sigma,
                dir: Some(P2::new(-d.y, d.x)),
            })
        }
        Reference::InclinedCrackInfinite { sigma, beta_deg } => {
            let d = chord()?;
            // Without beta_deg the tension may take any direction (the reference follows it).
            let dir = beta_deg.map(|b| {
                let (s, c) = b.to_radians().sin_cos();
                P2::new(c * d.x - s * d.y, s * d.x + c * d.y)
            });
            Some(Expected { sigma, dir })
        }
        Reference::Kirsch { sigma } => Some(Expected { sigma, dir: None }),
    }
}

/// What `r` assumes, with the stress `e` it stands for.
fn assumes(r: &Reference, e: &Expected) -> String {
    let tension = match e.dir {
        Some(d) => format!(
            "uniaxial tension {:.6e} Pa along ({:.4}, {:.4})",
            e.sigma,
            d.x + 0.0, // no "-0.0000"
            d.y + 0.0
        ),
        None => format!("uniaxial tension {:.6e} Pa", e.sigma),
    };
    let (name, whose) = match r {
        Reference::SentTada { .. } => ("SentTada", "across cracks.0, with free crack faces"),
        Reference::InclinedCrackInfinite { beta_deg, .. } => (
            "InclinedCrackInfinite",
            match beta_deg {
                Some(_) => {
                    "at beta_deg counter-clockwise from the line of cracks.0, with free crack faces"
                }
                None => "in some direction, with free crack faces",
            },
        ),
        Reference::Kirsch { .. } => ("Kirsch", "with a free hole"),
    };
    format!("{name} assumes {tension} {whose}")
}

/// `Err(why)` when a boundary condition of an infinite plate names a hole or a crack.
fn free_holes_and_faces(scene: &Scene) -> std::result::Result<(), String> {
    match scene
        .boundary
        .iter()
        .position(|b| b.is_loading() || holds(b))
    {
        Some(k) => Err(format!(
            "has a condition on '{}' (boundary.{k})",
            scene.boundary[k].on
        )),
        None => Ok(()),
    }
}

fn holds(b: &crate::scene::BoundaryCondition) -> bool {
    use crate::scene::Component::Displacement;
    matches!(b.x, Displacement(_)) || matches!(b.y, Displacement(_))
}

/// The uniform stress the outline's tractions are, or why they are none (or why the
/// holes, crack faces or held elements depart from `expected`). `mesh.loops[0]` is the
/// outline; every other element is a hole's or a crack face's.
fn outline_stress(
    mesh: &Mesh,
    bcs: &[[Bc; 2]],
    expected: &Expected,
) -> std::result::Result<[f64; 3], String> {
    let outline = mesh.loops.first().cloned().unwrap_or(0..0);
    let group = |i: usize| mesh.groups[mesh.elements[i].group].clone();
    let mut free = Vec::new();
    let mut held = Vec::new();
    for (i, bc) in bcs.iter().enumerate() {
        let moved = bc
            .iter()
            .any(|b| matches!(b, Bc::Displacement(v) if *v != 0.0));
        let is_held = bc.iter().any(|b| matches!(b, Bc::Displacement(_)));
        let loaded = bc.iter().any(|b| matches!(b, Bc::Traction(v) if *v != 0.0));
        if !outline.contains(&i) {
            if is_held || loaded {
                return Err(format!("has a condition on '{}'", group(i)));
            }
        } else if moved {
            return Err(format!(
                "moves '{}' by a displacement (only tractions give a stress to compare)",
                group(i)
            ));
        } else if is_held {
            held.push(i);
        } else {
            free.push(i);
        }
    }
    let s = fit(mesh, bcs, &free).ok_or("has no traction on its outline".to_string())?;
    let scale = free
        .iter()
        .map(|&i| traction(&bcs[i]).norm())
        .fold(norm(&s), f64::max);
    for &i in &free {
        let n = mesh.elements[i].normal;
        let t = traction(&bcs[i]);
        let r = P2::new(s[0] * n.x + s[2] * n.y, s[2] * n.x + s[1] * n.y) - t;
        if r.norm() > TOL * scale {
            let m = mesh.elements[i].mid;
            return Err(format!(
                "loads its outline with no uniform stress: '{}' at ({:.6e}, {:.6e}) carries ({:.6e}, {:.6e}) Pa",
                group(i), m.x, m.y, t.x, t.y
            ));
        }
    }
    let e = expected.direction(&s);
    if let Some(&i) = held.iter().find(|&&i| {
        let n = mesh.elements[i].normal;
        (n.x * e.y - n.y * e.x).abs() > TOL
    }) {
        return Err(format!(
            "holds '{}', which is not an end of the tension (its outward normal is not along ({:.4}, {:.4}))",
            group(i),
            e.x,
            e.y
        ));
    }
    Ok(s)
}

fn traction(bc: &[Bc; 2]) -> P2 {
    P2::new(bc[0].value(), bc[1].value())
}

/// Weighted least squares of (sxx, syy, sxy) over the elements `free`: S n = t per
/// element, weight its length. `None` when the normals do not fix all three.
fn fit(mesh: &Mesh, bcs: &[[Bc; 2]], free: &[usize]) -> Option<[f64; 3]> {
    let mut a = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    for &i in free {
        let e = &mesh.elements[i];
        let (n, t, w) = (e.normal, traction(&bcs[i]), e.h);
        // Rows of the two equations in (sxx, syy, sxy).
        for (row, rhs) in [
            (nalgebra::Vector3::new(n.x, 0.0, n.y), t.x),
            (nalgebra::Vector3::new(0.0, n.y, n.x), t.y),
        ] {
            a += w * row * row.transpose();
            b += w * rhs * row;
        }
    }
    let diag = a.diagonal().max();
    if diag.is_nan() || diag <= 0.0 || a.determinant().abs() <= 1e-12 * diag.powi(3) {
        return None;
    }
    let x = a.lu().solve(&b)?;
    Some([x[0], x[1], x[2]])
}

fn uniaxial(sigma: f64, e: P2) -> [f64; 3] {
    [sigma * e.x * e.x, sigma * e.y * e.y, sigma * e.x * e.y]
}

fn norm(s: &[f64; 3]) -> f64 {
    s[0].abs().max(s[1].abs()).max(s[2].abs())
}

/// Principal stresses of `s`, the larger in magnitude first.
fn principal(s: &[f64; 3]) -> (f64, f64) {
    let m = 0.5 * (s[0] + s[1]);
    let r = (0.5 * (s[0] - s[1])).hypot(s[2]);
    let (p, q) = (m + r, m - r);
    if p.abs() >= q.abs() {
        (p, q)
    } else {
        (q, p)
    }
}

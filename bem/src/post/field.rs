//! Interior displacement and stress:
//! $u_i(x) = \sum_e \int U_{ij} t_j - \int T_{ij} u_j$,
//! $\sigma_{ij}(x) = \sum_e \int D_{kij} t_k - \int S_{kij} u_k$ (REFERENCES.md), the stress
//! obtained row by row as the traction on the planes with normals $e_1$ and $e_2$.

use crate::integrate::far::{far_displacement, Densities};
use crate::integrate::{
    integrate_element, integrate_element_linear, integrate_element_linear_displacement,
    KernelConsts, PairIntegrals,
};
use crate::mesh::{Mesh, V2};
use crate::{Material, Solution};
use rayon::prelude::*;

/// A uniform remote stress [sxx, syy, sxy] superposed on the computed (perturbation) field.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Background {
    /// Remote stress [sxx, syy, sxy] (Pa).
    pub stress: [f64; 3],
}

/// Evaluates fields of one solution.
pub struct FieldEvaluator<'a> {
    mesh: &'a Mesh,
    material: Material,
    sol: &'a Solution,
    background: Background,
    kc: KernelConsts,
}

impl<'a> FieldEvaluator<'a> {
    /// Evaluator of `sol` on `mesh`, plus a uniform `background` field.
    pub fn new(
        mesh: &'a Mesh,
        material: &Material,
        sol: &'a Solution,
        background: Background,
    ) -> Self {
        Self {
            mesh,
            material: *material,
            sol,
            background,
            kc: KernelConsts::from(material),
        }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        self.mesh
    }

    /// The uniform remote field added to the solution's.
    pub fn background(&self) -> &Background {
        &self.background
    }

    /// Traction on element `e` of the whole field: the solution's plus the background
    /// stress on the element's outward normal (zero on the free faces of a crack in an
    /// infinite plate, which the solution loads by minus the remote traction).
    pub fn boundary_traction(&self, e: usize) -> [f64; 2] {
        let n = self.mesh.elements[e].normal;
        let [sxx, syy, sxy] = self.background.stress;
        let t = self.sol.t[e];
        [t[0] + sxx * n.x + sxy * n.y, t[1] + sxy * n.x + syy * n.y]
    }

    /// Displacement at element `e`'s collocation point, background included.
    pub fn boundary_displacement(&self, e: usize) -> [f64; 2] {
        let b = self.background_u(self.mesh.elements[e].mid);
        let u = self.sol.u[e];
        [u[0] + b[0], u[1] + b[1]]
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// Background displacement (uniform strain, no rotation, zero at the origin).
    fn background_u(&self, x: V2) -> [f64; 2] {
        let e = self.material.strain_from_stress(self.background.stress);
        [e[0] * x.x + e[2] * x.y, e[2] * x.x + e[1] * x.y]
    }

    /// Element integrals for field point x (normal m) and the element's displacement as
    /// seen by the integrals: (integrals, first-moment integrals, derivative).
    /// `displacement_only`: the H blocks are not needed (and stay zero).
    fn pair(
        &self,
        x: V2,
        m: V2,
        e: usize,
        displacement_only: bool,
    ) -> (PairIntegrals, Option<(PairIntegrals, [f64; 2])>) {
        let el = &self.mesh.elements[e];
        if self.sol.du.is_empty() {
            (integrate_element(x, m, el, &self.kc), None)
        } else {
            let (p, p1) = if displacement_only {
                integrate_element_linear_displacement(x, m, el, &self.kc)
            } else {
                integrate_element_linear(x, m, el, &self.kc)
            };
            (p, Some((p1, self.sol.du[e])))
        }
    }

    /// Displacement at an interior point. Elements at least 3 lengths away are summed
    /// straight from the kernels at their Gauss points ([`far_displacement`]).
    pub fn displacement(&self, x: V2) -> [f64; 2] {
        let mut u = self.background_u(x);
        for (e, (ue, te)) in self.sol.u.iter().zip(&self.sol.t).enumerate() {
            let d = Densities {
                t: *te,
                u: *ue,
                g: self.sol.du.get(e).copied().unwrap_or_default(),
            };
            if let Some(du) = far_displacement(x, &self.mesh.elements[e], &self.kc, &d) {
                u[0] += du[0];
                u[1] += du[1];
                continue;
            }
            let (p, lin) = self.pair(x, V2::new(1.0, 0.0), e, true);
            for i in 0..2 {
                for j in 0..2 {
                    u[i] += p.u[i][j] * te[j] - p.t[i][j] * ue[j];
                    if let Some((p1, g)) = &lin {
                        u[i] -= p1.t[i][j] * g[j];
                    }
                }
            }
        }
        u
    }

    /// Stress [sxx, syy, sxy] at an interior point.
    pub fn stress(&self, x: V2) -> [f64; 3] {
        let mut s = [[0.0; 2]; 2];
        for (e, (ue, te)) in self.sol.u.iter().zip(&self.sol.t).enumerate() {
            for (row, m) in [V2::new(1.0, 0.0), V2::new(0.0, 1.0)].iter().enumerate() {
                let (p, lin) = self.pair(x, *m, e, false);
                for j in 0..2 {
                    for k in 0..2 {
                        s[row][j] += p.k[j][k] * te[k] - p.h[j][k] * ue[k];
                        if let Some((p1, g)) = &lin {
                            s[row][j] -= p1.h[j][k] * g[k];
                        }
                    }
                }
            }
        }
        let b = self.background.stress;
        [
            s[0][0] + b[0],
            s[1][1] + b[1],
            0.5 * (s[0][1] + s[1][0]) + b[2],
        ]
    }

    /// Displacements at many points (parallel).
    pub fn displacements(&self, pts: &[V2]) -> Vec<[f64; 2]> {
        pts.par_iter().map(|p| self.displacement(*p)).collect()
    }

    /// Stresses at many points (parallel).
    pub fn stresses(&self, pts: &[V2]) -> Vec<[f64; 3]> {
        pts.par_iter().map(|p| self.stress(*p)).collect()
    }

    /// Tangential (hoop) stress at each element of loop `l`, from the tangential derivative
    /// of the boundary displacement (central differences between neighbouring collocation
    /// points) and the known traction: $\sigma_{tt} = \frac{2\mu}{1-\nu}\varepsilon_{tt}
    /// + \frac{\nu}{1-\nu}\sigma_{nn}$ (plane-strain form, effective nu), plus the background.
    pub fn boundary_hoop_stress(&self, l: usize) -> Vec<(V2, f64)> {
        let range = self.mesh.loops[l].clone();
        let ids: Vec<usize> = range.collect();
        let n = ids.len();
        let (mu, nu) = (self.kc.mu, self.kc.nu);
        let mut out = Vec::with_capacity(n);
        for k in 0..n {
            let (ip, i, inx) = (ids[(k + n - 1) % n], ids[k], ids[(k + 1) % n]);
            let el = &self.mesh.elements[i];
            let (ep, en) = (&self.mesh.elements[ip], &self.mesh.elements[inx]);
            let ds = 0.5 * ep.h + el.h + 0.5 * en.h;
            let du = V2::new(
                self.sol.u[inx][0] - self.sol.u[ip][0],
                self.sol.u[inx][1] - self.sol.u[ip][1],
            );
            let ett = du.dot(&el.tangent) / ds;
            let tn = V2::new(self.sol.t[i][0], self.sol.t[i][1]).dot(&el.normal);
            let stt = 2.0 * mu / (1.0 - nu) * ett + nu / (1.0 - nu) * tn;
            let b = self.background.stress;
            let (tx, ty) = (el.tangent.x, el.tangent.y);
            let bg = b[0] * tx * tx + b[1] * ty * ty + 2.0 * b[2] * tx * ty;
            out.push((el.mid, stt + bg));
        }
        out
    }
}

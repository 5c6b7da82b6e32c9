//! What [`PdModel`] and the solvers call to stay model-agnostic: the tangent pattern and
//! its assembly, ADR's density bound and the predictor's coupling to prescribed DOFs,
//! each the PMB bond form or the state-based row form.

use super::tangent::RowInput;
use super::{Corrections, StateBased};
use crate::bonds::Bonds;
use crate::error::PdError;
use crate::forces::TangentKind;
use crate::geometry::P2;
use crate::grid::Grid;
use crate::model::PdModel;
use crate::problem::{PdMaterial, PdProblem};
use crate::tangent::Tangent;

/// The state-based constants of `p` (None for PMB); sets `bonds.k` to the pair stiffness.
pub(crate) fn for_problem(
    p: &PdProblem,
    grid: &Grid,
    bonds: &mut Bonds,
    intact: &[u8],
) -> Option<StateBased> {
    let PdMaterial::StateBased { poisson_ratio } = p.material else {
        return None;
    };
    let corr = Corrections {
        surface: p.surface_correction,
        crack_faces: p.crack_face_correction,
    };
    let moduli = super::moduli(p.plane, p.youngs_modulus, poisson_ratio);
    let sb = StateBased::new(grid, bonds, intact, moduli, corr);
    bonds.k = sb.pair_stiffness(bonds, grid.volume);
    Some(sb)
}

impl PdModel {
    /// The state-based constants, `None` for PMB.
    pub fn state_based(&self) -> Option<&StateBased> {
        self.osb.as_ref()
    }

    /// Force density (N/m^3) on node `i` from the pair of its bond `b` (`i -> j`), history
    /// frozen: the PMB bond force, or the state-based $(t_{ij} - t_{ji}) V'_j$
    /// ([`super::pair_force`]).
    pub fn pair_force(&self, i: usize, b: usize) -> P2 {
        if self.intact[b] == 0 {
            return [0.0; 2];
        }
        if let Some(sb) = &self.osb {
            return super::pair_force(
                sb,
                &self.bonds,
                self.law,
                &self.intact,
                &self.s_hist,
                &self.u,
                i,
                b,
                self.grid.volume,
            );
        }
        let j = self.bonds.nbr[b] as usize;
        let y = [
            self.bonds.xi[b][0] + (self.u[j][0] - self.u[i][0]),
            self.bonds.xi[b][1] + (self.u[j][1] - self.u[i][1]),
        ];
        self.bond_force(b, y)
    }

    /// The inputs of a state-based tangent row at the current state.
    pub(crate) fn osb_rows(&self, kind: TangentKind) -> Option<RowInput<'_>> {
        self.osb.as_ref().map(|sb| RowInput {
            sb,
            bonds: &self.bonds,
            law: self.law,
            intact: &self.intact,
            s_hist: &self.s_hist,
            u: &self.u,
            volume: self.grid.volume,
            kind,
        })
    }

    /// The free-DOF tangent pattern of this model (bond pattern for PMB, two-hop stencil
    /// for the state-based model).
    pub fn new_tangent(&self) -> Result<Tangent, PdError> {
        if self.osb.is_some() {
            Tangent::from_stencil(super::stencil(&self.bonds), &self.bc.fixed)
        } else {
            Tangent::new(&self.bonds, &self.bc.fixed)
        }
    }

    /// Fill `t` (from [`Self::new_tangent`]) with the tangent of `kind` at the current
    /// state.
    pub fn assemble_tangent(&self, t: &mut Tangent, kind: TangentKind) {
        match self.osb_rows(kind) {
            Some(r) => super::assemble(t, &r),
            None => t.assemble_in(
                &self.bonds,
                self.law,
                &self.intact,
                &self.s_hist,
                &self.u,
                kind,
            ),
        }
    }

    /// State-based model: the absolute row sums of the tangent per DOF in the reference
    /// configuration (ADR's fictitious density, seed 002 Eq. 15). `None` for PMB, whose
    /// bound ADR takes bond by bond.
    pub fn stiffness_row_sums(&self) -> Option<Vec<[f64; 2]>> {
        let zero = vec![[0.0; 2]; self.u.len()];
        let mut r = self.osb_rows(TangentKind::Secant)?;
        r.u = &zero;
        Some(super::row_sums(&r))
    }

    /// State-based model: `rhs[d(i,p)] += sum_m K[(i,p),(m,q)] du_m[q]` over the
    /// prescribed components `m, q` (the predictor's load vector, `du` the increment of the
    /// prescribed displacements), with the tangent of the current state. Returns false
    /// (and does nothing) for PMB.
    pub fn add_prescribed_coupling(&self, dof: &[usize], du: &[[f64; 2]], rhs: &mut [f64]) -> bool {
        let Some(r) = self.osb_rows(TangentKind::Consistent) else {
            return false;
        };
        let (offsets, nodes) = super::stencil(&self.bonds);
        let fam = super::Families::new(&r);
        let mut sc = super::tangent::RowScratch::default();
        let mut blocks = Vec::new();
        for i in 0..self.u.len() {
            if dof[2 * i] == usize::MAX && dof[2 * i + 1] == usize::MAX {
                continue;
            }
            let st = &nodes[offsets[i]..offsets[i + 1]];
            if !st.iter().any(|&m| {
                let f = self.bc.fixed[m as usize];
                f[0] || f[1]
            }) {
                continue;
            }
            blocks.clear();
            blocks.resize(st.len(), [[0.0; 2]; 2]);
            super::row_blocks(&r, &fam, (i, super::Part::Full), st, &mut sc, &mut blocks);
            for (m, blk) in st.iter().zip(&blocks) {
                let m = *m as usize;
                for p in 0..2 {
                    let d = dof[2 * i + p];
                    if d == usize::MAX {
                        continue;
                    }
                    for q in 0..2 {
                        if self.bc.fixed[m][q] {
                            rhs[d] += blk[p][q] * du[m][q];
                        }
                    }
                }
            }
        }
        true
    }
}

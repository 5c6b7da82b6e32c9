//! [`PdModel`]: grid, bonds, material, boundary data and the mutable state
//! (displacements, bond history, load factor), with the operations the
//! solvers and the coupling need.
//!
//! Nodes `0..n_real` are real, `n_real..n` fictitious (virtual). Forces are
//! force densities (N/m^3) inside the solvers; public force getters return
//! Newtons (density times the node volume). On a mixed grid ([`crate::mixed`]) every
//! per-node force is per reference (coarse) volume `grid.volume`, so the same
//! conversion gives newtons.

use std::ops::Range;

use crate::bonds::{build_bonds, cut_cracks, Bonds};
use crate::boundary::{resolve, Boundary};
use crate::damage::damage;
use crate::error::PdError;
use crate::forces::{
    bond_tangent_scaled, elastic_energy, internal_forces, stretch_scale, BondState, ForceStats,
    History, TangentKind,
};
use crate::geometry::P2;
use crate::grid::Grid;
use crate::material::{micromodulus, BondLaw};
use crate::mixed::build_grid;
use crate::problem::{Failure, PdMaterial, PdProblem};
use crate::state_based::{self, StateBased};
use crate::surface::{apply_crack_face_correction, apply_surface_correction};

/// A snapshot of the mutable state, for roll-back (switching solver) and
/// restarts (coupling) and growth checkpoints (serialisable).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModelState {
    /// Displacements.
    pub u: Vec<P2>,
    /// Bond intact flags.
    pub intact: Vec<u8>,
    /// Bond stretch history.
    pub s_hist: Vec<f64>,
    /// Load factor.
    pub load: f64,
}

/// A discretised bond-based PD body ready for the solvers.
#[derive(Clone, Debug)]
pub struct PdModel {
    pub(crate) grid: Grid,
    pub(crate) bonds: Bonds,
    pub(crate) law: BondLaw,
    pub(crate) c: f64,
    pub(crate) intact: Vec<u8>,
    pub(crate) s_hist: Vec<f64>,
    pub(crate) u: Vec<P2>,
    pub(crate) bc: Boundary,
    pub(crate) load: f64,
    pub(crate) force: Vec<P2>,
    pub(crate) cut: usize,
    /// The state-based constants ([`crate::state_based`]); `None` for PMB.
    pub(crate) osb: Option<StateBased>,
}

/// The bond law before any model is built (for `pdbem check` and a run's first lines).
impl PdProblem {
    /// The bond law the problem's model resolves ([`PdModel::law`]) without building it:
    /// the state-based fracture energy through seed 004 Eq. 11, every other law through
    /// [`BondLaw::from_failure`], at the (coarse) horizon.
    pub fn bond_law(&self) -> BondLaw {
        match (self.material, self.failure) {
            (PdMaterial::StateBased { poisson_ratio }, Failure::FractureEnergy { g_c }) => {
                let (kappa, mu) =
                    state_based::moduli(self.plane, self.youngs_modulus, poisson_ratio);
                BondLaw::Brittle {
                    s0: state_based::critical_stretch(kappa, mu, g_c, self.horizon()),
                }
            }
            _ => BondLaw::from_failure(
                self.failure,
                self.plane,
                self.youngs_modulus,
                self.horizon(),
            ),
        }
    }
}

impl PdModel {
    /// Validate the problem and build the model (load factor 0, zero displacement).
    pub fn new(p: &PdProblem) -> Result<Self, PdError> {
        p.validate()?;
        let grid = build_grid(p)?;
        let mixed = grid.is_mixed();
        let mut bonds = if mixed {
            crate::mixed::build_bonds(&grid, &p.region)
        } else {
            build_bonds(&grid, &p.region)
        };
        let c = micromodulus(p.plane, p.youngs_modulus, p.thickness, grid.delta);
        let pmb = p.material == PdMaterial::Pmb;
        if p.surface_correction && pmb {
            if mixed {
                crate::mixed::surface_correction(&mut bonds, &grid, c, p.youngs_modulus, p.plane);
            } else {
                apply_surface_correction(
                    &mut bonds,
                    c,
                    grid.volume,
                    (p.youngs_modulus, p.plane),
                    grid.angle,
                );
            }
        }
        set_coefficients(&mut bonds, &grid, c);
        let mut intact = vec![1u8; bonds.len()];
        let cut = cut_cracks(&grid, &bonds, &p.cracks, &mut intact);
        if p.crack_face_correction && cut > 0 && pmb {
            apply_crack_face_correction(&mut bonds, &intact, grid.angle);
            set_coefficients(&mut bonds, &grid, c);
        }
        let osb = state_based::for_problem(p, &grid, &mut bonds, &intact);
        if !p.cracks.is_empty() && cut == 0 {
            return Err(PdError::invalid(
                "cracks",
                "no bond crosses the pre-cracks: they lie outside the material or are shorter than dx",
            ));
        }
        let bc = resolve(p, &grid)?;
        let law = match (&osb, p.failure) {
            (Some(sb), Failure::FractureEnergy { g_c }) => BondLaw::Brittle {
                s0: state_based::critical_stretch(sb.kappa, sb.mu, g_c, grid.delta),
            },
            _ => BondLaw::from_failure(p.failure, p.plane, p.youngs_modulus, grid.delta),
        };
        let n = grid.len();
        let nb = bonds.len();
        Ok(PdModel {
            grid,
            bonds,
            law,
            c,
            intact,
            s_hist: vec![0.0; nb],
            u: vec![[0.0; 2]; n],
            bc,
            load: 0.0,
            force: vec![[0.0; 2]; n],
            cut,
            osb,
        })
    }

    /// The grid (positions, spacing, horizon, node volume).
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The static bond data.
    pub fn bonds(&self) -> &Bonds {
        &self.bonds
    }

    /// The resolved bond law.
    pub fn law(&self) -> BondLaw {
        self.law
    }

    /// Micromodulus `c` (N/m^6).
    pub fn micromodulus(&self) -> f64 {
        self.c
    }

    /// Boundary data (fixed components, base values, body forces).
    pub fn boundary(&self) -> &Boundary {
        &self.bc
    }

    /// Number of nodes (real + fictitious).
    pub fn n_nodes(&self) -> usize {
        self.grid.len()
    }

    /// Number of real nodes.
    pub fn n_real(&self) -> usize {
        self.grid.n_real
    }

    /// Number of directed bonds (twice the number of pairs).
    pub fn n_bonds(&self) -> usize {
        self.bonds.len()
    }

    /// Reference positions.
    pub fn positions(&self) -> &[P2] {
        &self.grid.pos
    }

    /// Current displacements.
    pub fn displacements(&self) -> &[P2] {
        &self.u
    }

    /// Bond pairs whose state (intact / broken) differs from `other`'s, a model on the same
    /// grid (each pair is stored in both directions, hence the halving).
    pub fn differing_pairs(&self, other: &PdModel) -> usize {
        let (a, b) = (self.bond_intact(), other.bond_intact());
        a.iter()
            .zip(b)
            .filter(|(x, y)| (**x == 0) != (**y == 0))
            .count()
            / 2
    }

    /// Largest nodal distance between the displacements of `self` and `other`, a model on
    /// the same grid, relative to the largest displacement of `self` (0 for two states at
    /// rest). For comparing the equilibria of two solvers.
    pub fn relative_displacement_gap(&self, other: &PdModel) -> f64 {
        let scale = self.u.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
        let gap = self
            .u
            .iter()
            .zip(&other.u)
            .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]))
            .fold(0.0, f64::max);
        if scale > 0.0 {
            gap / scale
        } else {
            gap
        }
    }

    /// No-fail zone: every intact bond with an end node at which `protect` holds can no
    /// longer break (flag [`crate::forces::NO_FAIL`]; degrading bonds stay elastic).
    /// Returns the number of directed bonds marked.
    pub fn protect_bonds(&mut self, protect: impl Fn(P2) -> bool) -> usize {
        let flags: Vec<bool> = self.grid.pos.iter().map(|&x| protect(x)).collect();
        self.protect_nodes(|i| flags[i])
    }

    /// [`Self::protect_bonds`] by node index: every intact bond with an end node `i` for
    /// which `protect(i)` holds can no longer break. Returns the directed bonds marked.
    pub fn protect_nodes(&mut self, protect: impl Fn(usize) -> bool) -> usize {
        let flags: Vec<bool> = (0..self.grid.pos.len()).map(&protect).collect();
        self.protect_pairs(|i, j| flags[i] || flags[j])
    }

    /// Every intact bond between nodes `i` and `j` for which `protect(i, j)` holds can no
    /// longer break. Returns the directed bonds marked.
    pub fn protect_pairs(&mut self, protect: impl Fn(usize, usize) -> bool) -> usize {
        let mut marked = 0;
        for i in 0..self.grid.pos.len() {
            for b in self.bonds.row(i) {
                let j = self.bonds.nbr[b] as usize;
                if self.intact[b] == 1 && protect(i, j) {
                    self.intact[b] = crate::forces::NO_FAIL;
                    marked += 1;
                }
            }
        }
        marked
    }

    /// Bond intact flags (0 broken or cut, 1 intact, [`crate::forces::NO_FAIL`] intact
    /// and unbreakable), CSR order.
    pub fn bond_intact(&self) -> &[u8] {
        &self.intact
    }

    /// Warm start: set every node's displacement (prescribed components are
    /// overwritten by their prescribed values).
    pub fn set_displacements(&mut self, u: &[P2]) -> Result<(), PdError> {
        if u.len() != self.u.len() {
            return Err(PdError::LengthMismatch {
                what: "displacements",
                expected: self.u.len(),
                got: u.len(),
            });
        }
        self.u.copy_from_slice(u);
        self.apply_prescribed();
        Ok(())
    }

    /// Current load factor.
    pub fn load_factor(&self) -> f64 {
        self.load
    }

    /// Set the load factor and impose the scaled prescribed displacements.
    pub fn set_load_factor(&mut self, load: f64) {
        self.load = load;
        self.apply_prescribed();
    }

    /// Impose `load * base` on every prescribed component.
    pub fn apply_prescribed(&mut self) {
        for (i, f) in self.bc.fixed.iter().enumerate() {
            for c in 0..2 {
                if f[c] {
                    self.u[i][c] = self.load * self.bc.base[i][c];
                }
            }
        }
    }

    /// Indices of the fictitious (virtual) nodes.
    pub fn virtual_nodes(&self) -> Range<usize> {
        self.grid.n_real..self.grid.len()
    }

    /// The base displacement (at load factor 1) of every virtual node, in
    /// [`Self::virtual_nodes`] order: what [`Self::set_prescribed_displacements`] set last
    /// (a growth checkpoint keeps it).
    pub fn prescribed_virtual(&self) -> Vec<P2> {
        self.bc.base[self.virtual_nodes()].to_vec()
    }

    /// Coupling: set the base displacement of every virtual node (in
    /// [`Self::virtual_nodes`] order), both components, and impose it at the
    /// current load factor (use load factor 1 to take the values as given).
    pub fn set_prescribed_displacements(&mut self, u: &[P2]) -> Result<(), PdError> {
        let r = self.virtual_nodes();
        if u.len() != r.len() {
            return Err(PdError::LengthMismatch {
                what: "virtual-node displacements",
                expected: r.len(),
                got: u.len(),
            });
        }
        for (k, i) in r.enumerate() {
            self.bc.base[i] = u[k];
        }
        self.apply_prescribed();
        Ok(())
    }

    /// Coupling: replace the body force density (N/m^3 at load factor 1) of
    /// every node, e.g. interface tractions spread by transfer functions.
    pub fn set_body_forces(&mut self, b: &[P2]) -> Result<(), PdError> {
        if b.len() != self.bc.body.len() {
            return Err(PdError::LengthMismatch {
                what: "body forces",
                expected: self.bc.body.len(),
                got: b.len(),
            });
        }
        self.bc.body.copy_from_slice(b);
        Ok(())
    }

    /// Coupling: the force (N) each virtual node exerts on the real nodes,
    /// summed over its bonds to real nodes (virtual-virtual bonds excluded;
    /// seed 002 Eq. 24 and Fig. 6), in [`Self::virtual_nodes`] order.
    pub fn virtual_node_forces(&self) -> Vec<P2> {
        let n_real = self.grid.n_real as u32;
        let v = self.grid.volume;
        self.virtual_nodes()
            .map(|i| {
                let mut f = [0.0; 2];
                for b in self.bonds.row(i) {
                    let j = self.bonds.nbr[b];
                    if j >= n_real || self.intact[b] == 0 {
                        continue;
                    }
                    let t = self.pair_force(i, b);
                    // Force on j from i is minus the force on i from j.
                    f[0] -= v * t[0];
                    f[1] -= v * t[1];
                }
                f
            })
            .collect()
    }

    pub(crate) fn bond_force(&self, b: usize, y: P2) -> P2 {
        let l = y[0].hypot(y[1]);
        let s = l * self.bonds.inv_len[b] - 1.0;
        let t = match self.law {
            BondLaw::Degrading { s_m, s_c, beta } => {
                let sn = s / stretch_scale(&self.bonds, b);
                crate::material::degradation(sn.max(self.s_hist[b]), s_m, s_c, beta).0
            }
            _ => 1.0,
        };
        let f = self.bonds.k[b] * t * s / l;
        [f * y[0], f * y[1]]
    }

    /// Internal force (N) on every node at the current state (history frozen).
    pub fn internal_forces(&mut self) -> Vec<P2> {
        self.compute_forces(History::Frozen);
        let v = self.grid.volume;
        self.force.iter().map(|f| [f[0] * v, f[1] * v]).collect()
    }

    /// Compute the force densities into the scratch buffer.
    pub(crate) fn compute_forces(&mut self, history: History) -> ForceStats {
        if let Some(sb) = self.osb.as_mut() {
            return state_based::internal_forces(
                sb,
                &self.bonds,
                self.law,
                BondState {
                    intact: &mut self.intact,
                    s_hist: &mut self.s_hist,
                },
                &self.u,
                &mut self.force,
                history,
                self.grid.volume,
            );
        }
        internal_forces(
            &self.bonds,
            self.law,
            BondState {
                intact: &mut self.intact,
                s_hist: &mut self.s_hist,
            },
            &self.u,
            &mut self.force,
            history,
        )
    }

    /// Commit the bond history at the current displacements (break bonds
    /// past `s0`/`s_c`, raise `s_hist`); returns the pass statistics.
    pub fn commit_history(&mut self) -> ForceStats {
        self.compute_forces(History::Update)
    }

    /// Statistics of the current state without changing it.
    pub fn stretch_stats(&mut self) -> ForceStats {
        self.compute_forces(History::Frozen)
    }

    /// Damage of every node (seed 002 Eq. 8).
    pub fn damage(&self) -> Vec<f64> {
        damage(&self.bonds, &self.intact)
    }

    /// Number of broken bond pairs, not counting pre-crack cuts.
    pub fn broken_bonds(&self) -> usize {
        let dead = self.intact.iter().filter(|&&x| x == 0).count();
        (dead - self.cut) / 2
    }

    /// Elastic energy (J) at the current state: of the intact bonds (PMB), or
    /// $\sum_k V W_k$ with the history frozen (state-based).
    pub fn energy(&self) -> f64 {
        if let Some(sb) = &self.osb {
            return state_based::elastic_energy(
                sb,
                &self.bonds,
                self.law,
                &self.intact,
                &self.s_hist,
                &self.u,
                self.grid.volume,
            );
        }
        elastic_energy(&self.bonds, &self.intact, &self.u, self.grid.volume)
    }

    /// Snapshot of the mutable state.
    pub fn state(&self) -> ModelState {
        ModelState {
            u: self.u.clone(),
            intact: self.intact.clone(),
            s_hist: self.s_hist.clone(),
            load: self.load,
        }
    }

    /// Copy a snapshot into `dst` without reallocating.
    pub fn save_into(&self, dst: &mut ModelState) {
        dst.u.clone_from(&self.u);
        dst.intact.clone_from(&self.intact);
        dst.s_hist.clone_from(&self.s_hist);
        dst.load = self.load;
    }

    /// Restore a snapshot taken from a model of the same grid and bonds (a growth
    /// checkpoint), checking its sizes first.
    pub fn try_restore(&mut self, s: &ModelState) -> Result<(), PdError> {
        for (what, expected, got) in [
            ("displacements", self.u.len(), s.u.len()),
            ("bond flags", self.intact.len(), s.intact.len()),
            ("bond history", self.s_hist.len(), s.s_hist.len()),
        ] {
            if expected != got {
                return Err(PdError::LengthMismatch {
                    what,
                    expected,
                    got,
                });
            }
        }
        self.restore(s);
        Ok(())
    }

    /// Restore a snapshot taken from this model.
    pub fn restore(&mut self, s: &ModelState) {
        self.u.clone_from(&s.u);
        self.intact.clone_from(&s.intact);
        self.s_hist.clone_from(&s.s_hist);
        self.load = s.load;
    }

    /// Dense tangent `K = -dF/du` over all `2n` DOFs (DOF `2i + c`), force
    /// densities, history frozen. A testing aid for small models only.
    pub fn tangent_dense(&self) -> Vec<Vec<f64>> {
        if let Some(r) = self.osb_rows(crate::forces::TangentKind::Consistent) {
            return state_based::dense_tangent(&r);
        }
        let n = self.n_nodes();
        let mut k = vec![vec![0.0; 2 * n]; 2 * n];
        for i in 0..n {
            for b in self.bonds.row(i) {
                if self.intact[b] == 0 {
                    continue;
                }
                let j = self.bonds.nbr[b] as usize;
                let y = [
                    self.bonds.xi[b][0] + (self.u[j][0] - self.u[i][0]),
                    self.bonds.xi[b][1] + (self.u[j][1] - self.u[i][1]),
                ];
                let m = bond_tangent_scaled(
                    self.law,
                    self.bonds.k[b],
                    self.bonds.inv_len[b],
                    y,
                    self.s_hist[b],
                    TangentKind::Consistent,
                    stretch_scale(&self.bonds, b),
                );
                for p in 0..2 {
                    for q in 0..2 {
                        k[2 * i + p][2 * i + q] += m[p][q];
                        k[2 * i + p][2 * j + q] -= m[p][q];
                    }
                }
            }
        }
        k
    }

    /// Internal force densities (N/m^3) for a given displacement field,
    /// history frozen, leaving the model state unchanged. A testing aid.
    pub fn force_density_at(&mut self, u: &[P2]) -> Vec<P2> {
        let saved = std::mem::replace(&mut self.u, u.to_vec());
        self.compute_forces(History::Frozen);
        self.u = saved;
        self.force.clone()
    }
}

/// The bond coefficients `k` of a uniform grid (`c v V G`) or a mixed one
/// ([`crate::mixed::set_coefficients`]).
fn set_coefficients(bonds: &mut Bonds, grid: &Grid, c: f64) {
    if grid.is_mixed() {
        crate::mixed::set_coefficients(bonds, grid, c);
    } else {
        bonds.set_coefficients(c, grid.volume);
    }
}

#[cfg(test)]
mod no_fail_tests {
    use super::*;
    use crate::problem::{Failure, Region};

    #[test]
    fn protected_bonds_do_not_break() {
        // 10 x 4 cells stretched by 5 % along x against s0 = 1 %: every bond with an x
        // component breaks, except those with an end in the protected left half.
        let p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [10.0, 4.0]),
            dx: 1.0,
            youngs_modulus: 1.0,
            failure: Failure::CriticalStretch { s0: 0.01 },
            ..Default::default()
        };
        let mut m = PdModel::new(&p).unwrap();
        let marked = m.protect_bonds(|x| x[0] < 5.0);
        assert!(marked > 0);
        let u: Vec<P2> = m.positions().iter().map(|x| [0.05 * x[0], 0.0]).collect();
        m.set_displacements(&u).unwrap();
        let st = m.commit_history();
        assert!(st.newly_broken > 0);
        let (pos, b) = (m.positions().to_vec(), m.bonds().clone());
        for i in 0..m.n_nodes() {
            for k in b.row(i) {
                let j = b.nbr[k] as usize;
                let protected = pos[i][0] < 5.0 || pos[j][0] < 5.0;
                assert_eq!(m.bond_intact()[k] != 0, protected || b.xi[k][0] == 0.0);
            }
        }
        assert_eq!(m.differing_pairs(&m.clone()), 0);
    }
}

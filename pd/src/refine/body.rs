//! The refinable body: dual-horizon particles with their sizes, levels, displacements,
//! loads and pre-cracks, built from a [`PdProblem`]'s grid and boundary conditions.

use rayon::prelude::*;

use crate::bonds::{cut_cracks, Bonds};
use crate::boundary::resolve;
use crate::error::PdError;
use crate::geometry::P2;
use crate::grid::Grid;
use crate::measure::{kink_angle_weighted, Tip};
use crate::mixed::build_grid;
use crate::problem::{Failure, PdMaterial, PdProblem};
use crate::state_based::dual_horizon::{families, DualHorizon};
use crate::state_based::{critical_stretch, moduli};

/// Dual-horizon particles of several sizes with their state and loads.
#[derive(Clone, Debug)]
pub struct Body {
    /// Families, constants and reference positions.
    pub dh: DualHorizon,
    /// Particle side `Delta_k` (m).
    pub size: Vec<f64>,
    /// Refinement level (0: a base grid particle).
    pub level: Vec<u8>,
    /// Displacements (m).
    pub u: Vec<P2>,
    /// Prescribed components.
    pub fixed: Vec<[bool; 2]>,
    /// Particles of a fictitious layer (outside the body; their constants are the full
    /// lattice family's, [`DualHorizon::from_families`]).
    pub layer: Vec<bool>,
    /// Prescribed displacement (m) of the fixed components.
    pub base: Vec<P2>,
    /// Body-force density (N/m^3).
    pub body: Vec<P2>,
    /// Pre-crack polylines.
    pub cracks: Vec<Vec<P2>>,
    /// Horizon factor `m = delta / Delta`.
    pub m: f64,
    /// Thickness (m).
    pub thickness: f64,
    /// 2-D bulk and shear moduli (Pa).
    pub moduli: (f64, f64),
    /// The failure law (for the critical stretch of Eq. 16).
    pub failure: Failure,
    /// Children keep their parent's horizon (seed 004 Table 3, delta_2 = delta_1) instead
    /// of halving it.
    pub keep_horizon: bool,
    /// Bytes a split may make the body hold, with the body it splits; `None`: the
    /// process's memory budget ([`crate::tangent::factor_budget`]).
    pub budget: Option<u64>,
}

impl Body {
    /// The particles of `p`'s grid, its loads at load factor 1 and its pre-cracks. Needs
    /// the state-based material. A fictitious layer (a displacement condition with
    /// `Layer::Fictitious`) joins as particles `n_real..` of the grid's spacing, prescribed
    /// as the uniform grid prescribes them: a particle of the layer keeps $\lambda\bar u$
    /// in its prescribed components (zero velocity, [`crate::refine::dynamics`]), and its
    /// children inherit the prescription ([`Body::split`]).
    pub fn from_problem(p: &PdProblem) -> Result<Self, PdError> {
        p.validate()?;
        let PdMaterial::StateBased { poisson_ratio } = p.material else {
            return Err(PdError::invalid(
                "material",
                "refinement needs the state-based model (dual horizons of seed 004)",
            ));
        };
        let grid = build_grid(p)?;
        let bc = resolve(p, &grid)?;
        let n = grid.len();
        let size = vec![grid.dx; n];
        let volume = vec![grid.volume; n];
        let delta = vec![grid.delta; n];
        let bonds = families(&grid.pos, &size, &volume, &delta);
        let intact = pre_cut(&grid, &bonds, &p.cracks);
        let mods = moduli(p.plane, p.youngs_modulus, poisson_ratio);
        let layer: Vec<bool> = (0..n).map(|i| i >= grid.n_real).collect();
        let bulk: Vec<Option<f64>> = layer.iter().map(|&l| l.then_some(grid.dx)).collect();
        let dh =
            DualHorizon::from_families(&grid.pos, volume, delta, bonds, intact, mods, &bulk, None)
                .ok_or_else(|| {
                    PdError::invalid("dx", "a particle family does not determine its constants")
                })?;
        let base = (0..n)
            .map(|i| {
                let mut b = [0.0; 2];
                for c in 0..2 {
                    if bc.fixed[i][c] {
                        b[c] = bc.base[i][c];
                    }
                }
                b
            })
            .collect::<Vec<P2>>();
        Ok(Body {
            dh,
            size,
            level: vec![0; n],
            u: base.clone(),
            fixed: bc.fixed[..n].to_vec(),
            layer,
            base,
            body: bc.body[..n].to_vec(),
            cracks: p.cracks.clone(),
            m: p.horizon_factor,
            thickness: p.thickness,
            moduli: mods,
            failure: p.failure,
            keep_horizon: false,
            budget: None,
        })
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.size.len()
    }

    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.size.is_empty()
    }

    /// Reference positions (m).
    pub fn positions(&self) -> &[P2] {
        &self.dh.pos
    }

    /// Total volume (m^3).
    pub fn total_volume(&self) -> f64 {
        self.dh.volume.iter().sum()
    }

    /// Total applied force (N): body-force density times volume.
    pub fn total_load(&self) -> P2 {
        let mut f = [0.0; 2];
        for (b, v) in self.body.iter().zip(&self.dh.volume) {
            f[0] += b[0] * v;
            f[1] += b[1] * v;
        }
        f
    }

    /// Critical stretch of particle `k`'s bonds from the failure law (`None` without one):
    /// seed 004 Eq. 11 with `k`'s horizon for `FractureEnergy`; for `CriticalStretch`,
    /// `s0` (given for the base grid's horizon) times `sqrt(delta_base / delta_k)`, the
    /// scaling of Eq. 11 at a fixed fracture energy (`s0 ~ delta^-1/2`; the mixed grid of
    /// the windows scales it the same way, [`crate::mixed`]), so that children with halved
    /// horizons are as tough as their parents rather than half as tough.
    pub fn critical_stretch(&self, k: usize) -> Option<f64> {
        match self.failure {
            Failure::None => None,
            Failure::CriticalStretch { s0 } => {
                let base = self.m * self.size[k] * f64::from(1u32 << self.level[k]);
                Some(s0 * (base / self.dh.delta[k]).sqrt())
            }
            Failure::FractureEnergy { g_c } => Some(critical_stretch(
                self.moduli.0,
                self.moduli.1,
                g_c,
                self.dh.delta[k],
            )),
            Failure::Degradation { s_c, .. } => Some(s_c),
        }
    }

    /// Kink angle (degrees) of the damage around `tip` in `r_min..r_max`, each particle
    /// weighing its volume ([`crate::measure::kink_angle_weighted`]).
    pub fn kink_angle(&self, tip: Tip, r_min: f64, r_max: f64) -> Option<f64> {
        kink_angle_weighted(
            self.positions(),
            &self.damage(),
            &self.dh.volume,
            tip,
            r_min,
            r_max,
        )
    }

    /// Damage of every particle over its horizon and dual horizon (seed 004 Eq. 14).
    pub fn damage(&self) -> Vec<f64> {
        (0..self.len())
            .into_par_iter()
            .map(|k| self.damage_of(k))
            .collect()
    }

    /// Damage of particle `k` ([`Self::damage`]): the broken share of the volume of its
    /// horizon and dual horizon.
    pub fn damage_of(&self, k: usize) -> f64 {
        let dh = &self.dh;
        let vol = &dh.volume;
        let (mut kept, mut all) = (0.0, 0.0);
        for b in dh.bonds.row(k) {
            let v = vol[dh.bonds.nbr[b] as usize];
            all += v;
            kept += f64::from(dh.intact[b]) * v;
        }
        let duals = dh.dual_offsets[k]..dh.dual_offsets[k + 1];
        for (&b, &o) in dh.dual[duals.clone()].iter().zip(&dh.dual_owner[duals]) {
            let v = vol[o as usize];
            all += v;
            kept += f64::from(dh.intact[b as usize]) * v;
        }
        if all > 0.0 {
            1.0 - kept / all
        } else {
            0.0
        }
    }

    /// Accumulated strains `(eps_xx, eps_yy)` of every particle (seed 004 Eq. 17 in the
    /// bond-projected reading of the module docs).
    pub fn accumulated_strain(&self) -> Vec<P2> {
        (0..self.len())
            .into_par_iter()
            .map(|k| self.accumulated_strain_of(k))
            .collect()
    }

    /// Accumulated strains of particle `k` ([`Self::accumulated_strain`]).
    pub fn accumulated_strain_of(&self, k: usize) -> P2 {
        let dh = &self.dh;
        let u = &self.u;
        let (mut num, mut den) = ([0.0; 2], [0.0; 2]);
        for b in dh.bonds.row(k).filter(|&b| dh.intact[b] != 0) {
            let j = dh.bonds.nbr[b] as usize;
            let xi = dh.bonds.xi[b];
            let w = dh.volume[j] * dh.bonds.inv_len[b] * dh.bonds.inv_len[b];
            for c in 0..2 {
                num[c] += w * (u[j][c] - u[k][c]) * xi[c];
                den[c] += w * xi[c] * xi[c];
            }
        }
        super::pass::strain_of(num, den)
    }
}

/// Bond flags of `bonds` over the grid with the pre-cracks cut (0 = cut).
fn pre_cut(grid: &Grid, bonds: &Bonds, cracks: &[Vec<P2>]) -> Vec<u8> {
    let mut intact = vec![1u8; bonds.len()];
    cut_cracks(grid, bonds, cracks, &mut intact);
    intact
}

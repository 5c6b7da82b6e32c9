//! Element-pair coefficient blocks kept from one assembly for the next.
//!
//! The blocks $H^c_{ij}$, $G^c_{ij}$ (and with the linear reconstruction the first-moment
//! block) of collocation element i on element j depend only on the two elements'
//! geometry, the material and $\alpha$, $\beta$ ([`super`] module docs, seed 002 Eqs.
//! 21-22), not on the boundary conditions. A crack-growth run rebuilds its mesh at every
//! window relocation, but only the crack faces near the tip and the window interface
//! change: most pairs are those of the outline and the old crack faces, identical to the
//! last assembly's. [`PairCache`] keeps every pair's blocks keyed by the two elements' end
//! points (bit for bit), so the next assembly integrates only the pairs with a new element
//! and copies the others. The result is bit-identical to a fresh assembly: the copied
//! blocks are the same function of the same inputs.
//!
//! The cache also keeps the allocations of the assembly before last (the block storage
//! and the first-moment matrix, about 60 MB and 20 MB at 800 elements) and hands them to
//! the next assembly, which overwrites every entry: fresh allocations of that size come
//! from the operating system as untouched pages, and the page faults and zeroing cost
//! about a third of an assembly that copies most of its pairs (measured on
//! `cases/growth_tension_edge.ron`, 700-800 elements).

use std::collections::HashMap;

use crate::integrate::{integrate_element, integrate_element_linear, KernelConsts};
use crate::mesh::{Element, Mesh};
use crate::Material;

use super::SolveParams;

/// Coefficient blocks of one element pair, row-major 2x2 each: $H^c$, $G^c$ and the
/// first-moment block of the reconstruction (zero without it).
pub(super) type PairBlocks = [f64; 12];

/// Largest cache kept (bytes of blocks): 700 elements take 47 MB; above about 2300
/// elements nothing is kept and every assembly integrates all pairs.
const MAX_CACHE_BYTES: usize = 512 << 20;

/// The blocks of the last assembled mesh, reused by the next assembly for the pairs of
/// elements both meshes have (see the module docs). Start with `PairCache::default()` and
/// pass the same cache to every [`super::BemSystem::new_with_cache`] of a sequence of
/// related meshes.
#[derive(Default)]
pub struct PairCache {
    /// What the blocks depend on besides geometry: alpha, beta factor, E, mu, nu_eff and
    /// whether the reconstruction was on.
    signature: Option<[u64; 6]>,
    /// End points of every element of the cached mesh, as bits.
    keys: Vec<[u64; 4]>,
    /// Blocks, column element major: pair (i, j) at `j * keys.len() + i`.
    blocks: Vec<PairBlocks>,
    /// Storage of the blocks before the cached ones, stale, for the next assembly.
    spare_blocks: Vec<PairBlocks>,
    /// Storage of the last first-moment matrix, stale, for the next assembly.
    spare_moments: Vec<f64>,
}

impl PairCache {
    /// Elements of the cached mesh.
    pub fn elements(&self) -> usize {
        self.keys.len()
    }

    /// For each element of `mesh`, its index in the cached mesh (None when new or when
    /// the cache was made with other constants).
    pub(super) fn matches(
        &self,
        mesh: &Mesh,
        material: &Material,
        params: &SolveParams,
    ) -> Vec<Option<usize>> {
        if self.signature != Some(signature(material, params)) {
            return vec![None; mesh.len()];
        }
        let index: HashMap<[u64; 4], usize> = self
            .keys
            .iter()
            .enumerate()
            .map(|(k, key)| (*key, k))
            .collect();
        mesh.elements
            .iter()
            .map(|e| index.get(&key(e)).copied())
            .collect()
    }

    /// The cached blocks of pair (collocation `i`, element `j`), old indices.
    #[inline]
    pub(super) fn get(&self, i: usize, j: usize) -> &PairBlocks {
        &self.blocks[j * self.keys.len() + i]
    }

    /// Whether a mesh of `nel` elements is kept.
    pub(super) fn keeps(nel: usize) -> bool {
        nel * nel * std::mem::size_of::<PairBlocks>() <= MAX_CACHE_BYTES
    }

    /// Storage for `len` pair blocks: the spare allocation, truncated or extended, with
    /// stale entries (the assembly writes every entry).
    pub(super) fn take_blocks(&mut self, len: usize) -> Vec<PairBlocks> {
        let mut v = std::mem::take(&mut self.spare_blocks);
        v.truncate(len);
        v.resize(len, [0.0; 12]);
        v
    }

    /// Storage for the `len` entries of a first-moment matrix, as [`Self::take_blocks`].
    pub(super) fn take_moments(&mut self, len: usize) -> Vec<f64> {
        let mut v = std::mem::take(&mut self.spare_moments);
        v.truncate(len);
        v.resize(len, 0.0);
        v
    }

    /// Keeps the storage of a first-moment matrix for the next assembly.
    pub(super) fn give_moments(&mut self, v: Vec<f64>) {
        self.spare_moments = v;
    }

    /// Replaces the cache with the blocks of `mesh` (empty `blocks`: too large to keep).
    pub(super) fn store(
        &mut self,
        mesh: &Mesh,
        material: &Material,
        params: &SolveParams,
        blocks: Vec<PairBlocks>,
    ) {
        if blocks.is_empty() {
            *self = PairCache::default();
            return;
        }
        self.signature = Some(signature(material, params));
        self.keys = mesh.elements.iter().map(key).collect();
        self.spare_blocks = std::mem::replace(&mut self.blocks, blocks);
    }
}

/// An element's end points as bits.
fn key(e: &Element) -> [u64; 4] {
    [e.a.x, e.a.y, e.b.x, e.b.y].map(f64::to_bits)
}

/// The constants the blocks depend on, as bits.
fn signature(material: &Material, params: &SolveParams) -> [u64; 6] {
    [
        params.alpha,
        params.beta_factor,
        material.e,
        material.mu(),
        material.nu_eff(),
        if params.reconstruct { 1.0 } else { 0.0 },
    ]
    .map(f64::to_bits)
}

/// Blocks of collocation element `ei` on element `ej` ([`super`] module docs): with the
/// reconstruction (`linear`) also the first-moment block $\alpha \hat T_1 + \beta \hat H_1$.
pub(super) fn pair_blocks(
    ei: &Element,
    ej: &Element,
    same: bool,
    kc: &KernelConsts,
    alpha: f64,
    beta: f64,
    linear: bool,
) -> PairBlocks {
    let mut out = [0.0; 12];
    let p = if linear {
        let (p, p1) = integrate_element_linear(ei.mid, ei.normal, ej, kc);
        for r in 0..2 {
            for c in 0..2 {
                out[8 + 2 * r + c] = alpha * p1.t[r][c] + beta * p1.h[r][c];
            }
        }
        p
    } else {
        integrate_element(ei.mid, ei.normal, ej, kc)
    };
    for r in 0..2 {
        for c in 0..2 {
            let d = if same && r == c { 1.0 } else { 0.0 };
            out[2 * r + c] = alpha * (d + p.t[r][c]) + beta * p.h[r][c];
            out[4 + 2 * r + c] = alpha * p.u[r][c] + beta * (p.k[r][c] - d);
        }
    }
    out
}

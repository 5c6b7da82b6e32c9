//! The factored BEM system of one coupled geometry ([`PreparedBem`]) and its assembly.

use pdbem_bem::{Bc, BemSystem, PairCache, Solution};

use super::params::Ordering;
use super::rigid::RigidBalance;
use super::CoupledProblem;
use crate::error::CouplingError;
use crate::floating::FloatingPieces;

/// The BEM system of one coupled geometry, assembled and factored once with the scene
/// conditions of [`CoupledProblem::bcs`] (the reference load) and the interface groups
/// variable; reused for every iteration and every load step on that geometry.
pub struct PreparedBem {
    pub(super) system: BemSystem,
    /// Pieces of a body cut apart that only the windows hold ([`crate::floating`]).
    pub(super) floating: FloatingPieces,
    /// The interface ordering the system was factored for.
    pub(super) ordering: Ordering,
    /// [`Ordering::TractionToPd`]: the windows' rigid-motion balance.
    pub(super) rigid: Option<RigidBalance>,
}

impl PreparedBem {
    /// Marks the interface groups variable (traction) in `problem`, then assembles and
    /// factors. Changing the mesh or the scene conditions needs a new `PreparedBem`.
    pub fn new(problem: &mut CoupledProblem) -> Result<Self, CouplingError> {
        Self::with_cache(problem, None)
    }

    /// The same, reusing the element-pair blocks `pairs` holds from an earlier geometry
    /// and leaving this one's there ([`PairCache`]).
    pub fn with_cache(
        problem: &mut CoupledProblem,
        pairs: Option<&mut PairCache>,
    ) -> Result<Self, CouplingError> {
        Self::with_ordering(problem, Ordering::DisplacementToPd, pairs)
    }

    /// The same for interface ordering `ordering`: with [`Ordering::TractionToPd`] the
    /// interface elements take displacements, and the BEM traction response to the
    /// windows' rigid motions is computed once (`traction::RigidBalance`).
    pub fn with_ordering(
        problem: &mut CoupledProblem,
        ordering: Ordering,
        pairs: Option<&mut PairCache>,
    ) -> Result<Self, CouplingError> {
        let system = factor_bem(problem, ordering, pairs)?;
        let (floating, rigid) = match ordering {
            Ordering::DisplacementToPd => (FloatingPieces::new(&problem.mesh, &system)?, None),
            Ordering::TractionToPd => (
                FloatingPieces::none(),
                Some(RigidBalance::new(problem, &system)?),
            ),
        };
        Ok(PreparedBem {
            system,
            floating,
            ordering,
            rigid,
        })
    }

    /// The interface ordering the system was factored for.
    pub fn ordering(&self) -> Ordering {
        self.ordering
    }

    /// Assembly wall time (s).
    pub fn assembly_s(&self) -> f64 {
        self.system.info().assembly_s
    }

    /// Element pairs of the assembly copied from a [`PairCache`] (0 without one).
    pub fn reused_pairs(&self) -> usize {
        self.system.info().reused_pairs
    }

    /// Factorization and response precomputation wall time (s).
    pub fn factor_s(&self) -> f64 {
        self.system.info().factor_s + self.system.info().response_s
    }

    /// Number of BEM unknowns.
    pub fn unknowns(&self) -> usize {
        self.system.info().unknowns
    }

    /// Solves at load scale `scale` with interface conditions `bcs` (physical tractions or
    /// displacements at that scale): `scale` times the reference solve with the
    /// interface values over `scale`.
    pub(super) fn solve_scaled(
        &self,
        bcs: &[[Bc; 2]],
        interface: &[usize],
        scale: f64,
    ) -> Result<Solution, CouplingError> {
        if scale == 1.0 {
            return Ok(self.system.solve_with(bcs)?);
        }
        let mut reference = bcs.to_vec();
        for &e in interface {
            for c in 0..2 {
                reference[e][c] = match bcs[e][c] {
                    Bc::Traction(v) => Bc::Traction(v / scale),
                    Bc::Displacement(v) => Bc::Displacement(v / scale),
                };
            }
        }
        let mut sol = self.system.solve_with(&reference)?;
        for v in sol
            .u
            .iter_mut()
            .chain(sol.t.iter_mut())
            .chain(sol.du.iter_mut())
        {
            v[0] *= scale;
            v[1] *= scale;
        }
        for l in &mut sol.lambda {
            *l *= scale;
        }
        Ok(sol)
    }
}

/// Assembles and factors the BEM system with the interface groups variable (tractions,
/// or displacements for [`Ordering::TractionToPd`]).
fn factor_bem(
    problem: &mut CoupledProblem,
    ordering: Ordering,
    pairs: Option<&mut PairCache>,
) -> Result<BemSystem, CouplingError> {
    let zero = match ordering {
        Ordering::DisplacementToPd => Bc::Traction(0.0),
        Ordering::TractionToPd => Bc::Displacement(0.0),
    };
    for w in &problem.windows {
        if let Some(g) = problem.mesh.group(&w.group) {
            if !problem.bem_params.variable_groups.contains(&g) {
                problem.bem_params.variable_groups.push(g);
            }
            for e in &w.interface.elements {
                problem.bcs[*e] = [zero, zero];
            }
        }
    }
    // Every iteration changes only the interface tractions: precompute the response of the
    // unknowns to them once (one blocked substitution with a few hundred columns), so each
    // iteration costs a product with it instead of a substitution through the whole factor.
    problem.bem_params.precompute_response = true;
    Ok(BemSystem::new_with_cache(
        &problem.mesh,
        &problem.material,
        &problem.bcs,
        &problem.bem_params,
        pairs,
    )?)
}

//! # pdbem-bem: Burton-Miller dual boundary integral solver with straight constant elements
//!
//! The macro body of pdbem (seed 002 section 2.2). At every collocation point (element
//! midpoint) the solver writes $\alpha\,$CBIE $+ \beta\,$HBIE (seed 002 Eqs. 21-22):
//! $$\alpha\Big[u(x) + \sum_e \hat T u_e - \sum_e \hat U t_e\Big] + \beta\Big[t(x) + \sum_e \hat H u_e - \sum_e \hat K t_e\Big] = 0,$$
//! with $\alpha = 1$ and $\beta = -h(x)/E$, the sign that makes $\beta \hat H_{ii}$
//! reinforce the diagonal (REFERENCES.md: the other sign makes the operator nearly singular).
//!
//! Map of the crate:
//! - [`analytic`]: closed-form LEFM references of REFERENCES.md the BEM is verified against
//!   (Tada SENT, the SENT FEM table, CMOD, Kirsch, inclined crack, Griffith K_c, PD constants).
//! - [`material`]: elastic constants, plane stress via the effective Poisson ratio.
//! - [`mesh`]: loops, holes, cracks with coincident or gapped faces, tip refinement.
//! - [`integrate`]: element integrals of U, T, K, H (closed form near, Gauss far, finite
//!   parts on the element itself).
//! - [`system`]: boundary conditions, assembly, rigid-body modes, LU factorization kept for
//!   further right-hand sides, condition estimate.
//! - [`post`]: interior displacement and stress, boundary stress, SIFs (crack-opening fit and
//!   interaction integral), kink angle, CMOD.
//! - `bench` (cargo feature `bench`): assembly / factorisation timings for `pdbem bench bem`.

pub mod analytic;
#[cfg(feature = "bench")]
pub mod bench;
pub mod error;
pub mod integrate;
pub mod material;
pub mod mesh;
pub mod post;
pub mod system;

pub use error::BemError;
pub use material::{Material, Plane};
pub use mesh::{Crack, Element, Mesh, MeshBuilder, V2};
pub use system::{Bc, BemFootprint, BemSystem, PairCache, Solution, SolveInfo, SolveParams};

//! The one scene-to-model layer: the only place where a validated [`Scene`] becomes a BEM
//! mesh specification, a PD problem, PD windows and coupling parameters. Validation,
//! `pdbem check` and every mode of `pdbem run` call it, so what `check` reports is what
//! `run` builds.
//!
//! Map:
//! - [`sizing`]: the one element-size rule (outline, holes, cracks and mouths, windows);
//! - [`close_tips`]: notes on tips nearer another boundary than the two-level estimate holds;
//! - [`thin_ligament`]: notes on cracks whose flank runs close along another boundary (a thin ligament the BEM crack faces do not resolve);
//! - [`bem`](mod@bem): the BEM model of a scene ([`bem::build`]: mesh, conditions, material);
//! - [`balance`]: refusal of finite bodies whose tractions nothing balances
//!   ([`balance::check`], run by [`bem::build`]; [`bem::check_balance`] for the modes
//!   with PD windows);
//! - [`pd`](mod@pd): the stand-alone PD problem ([`pd::problem_from_scene`]);
//! - [`reference_loads`]: refusal of a `reference` whose closed form assumes other loads
//!   than the scene's ([`reference_loads::check`], in `pdbem check` and before every run);
//! - [`fit_stations`]: refusal of crack meshes that leave a tip's crack-opening fit with
//!   too few stations for a K ([`fit_stations::check`], in `pdbem check` and before every
//!   run);
//! - [`ligament`]: refusal of pre-cracks whose ligament the PD grid cannot resolve, notes
//!   on ligaments under the horizon;
//! - [`coupled`]: the coupled model (windows, macro body, PD settings, Algorithm 1
//!   parameters; [`coupled::prepare`]);
//! - [`growth`]: the PD-BEM growth driver's input ([`growth::input`]);
//! - [`estimate`]: the size budget: a cheap estimate of the sizes from the scene alone,
//!   checked against the memory budget before anything is built ([`estimate::check`]);
//! - [`footprint`]: what a run will allocate (elements, unknowns, matrix bytes, PD nodes
//!   and bonds), computed from the same models before any solve ([`footprint::of`]).
//!
//! Shared conversions of scene enums to library ones live here: [`pd_failure`],
//! [`pd_material`], [`pd_plane`].

pub mod balance;
pub mod bem;
pub mod close_holes;
pub mod close_tips;
pub mod coupled;
pub mod estimate;
pub mod fit_stations;
pub mod footprint;
pub mod growth;
pub mod horizon_scale;
pub mod ligament;
pub mod outline_necks;
pub mod pd;
pub mod reference_loads;
pub mod refined_size;
pub mod sizing;
pub mod thin_ligament;

use anyhow::{Context, Result};

use crate::scene::{Failure, PdModelKind, PdSettings, Plane, Scene};

/// The PD failure law of a scene's `pd.failure` (`FromGc` takes `material.fracture.g_c`).
pub fn pd_failure(scene: &Scene, pd: &PdSettings) -> Result<pdbem_pd::Failure> {
    Ok(match &pd.failure {
        Failure::Elastic => pdbem_pd::Failure::None,
        Failure::CriticalStretch(s0) => pdbem_pd::Failure::CriticalStretch { s0: *s0 },
        Failure::FromGc => {
            let g_c = scene
                .material
                .fracture
                .as_ref()
                .and_then(|f| f.g_c)
                .with_context(|| {
                    format!(
                        "{}: pd.failure = FromGc needs material.fracture.g_c",
                        scene.file_label().display()
                    )
                })?;
            pdbem_pd::Failure::FractureEnergy { g_c }
        }
        Failure::Degradation { s_m, s_c, beta } => pdbem_pd::Failure::Degradation {
            s_m: *s_m,
            s_c: *s_c,
            beta: *beta,
        },
    })
}

/// The PD constitutive model of a scene: PMB, or state-based PD with `material.nu`.
pub fn pd_material(scene: &Scene, pd: &PdSettings) -> pdbem_pd::PdMaterial {
    match pd.model {
        PdModelKind::Pmb => pdbem_pd::PdMaterial::Pmb,
        PdModelKind::StateBased => pdbem_pd::PdMaterial::StateBased {
            poisson_ratio: scene.material.nu,
        },
    }
}

/// The PD plane condition of a scene's material.
pub fn pd_plane(scene: &Scene) -> pdbem_pd::Plane {
    match scene.material.plane {
        Plane::Stress => pdbem_pd::Plane::Stress,
        Plane::Strain => pdbem_pd::Plane::Strain,
    }
}

/// The last load factor of the scene (the static modes solve once, at the final load).
pub fn final_factor(scene: &Scene) -> f64 {
    scene.load.factors().last().copied().unwrap_or(1.0)
}

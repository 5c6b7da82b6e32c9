//! Scenes: the RON description of one study (DESIGN.md "Scenes and outputs").
//!
//! Entry points: [`Scene::load`] (read, parse, validate, normalise),
//! [`Scene::from_ron_str`] (the same for inline text), [`Scene::validate`],
//! [`path::with_overrides`] (set dotted paths for sweeps),
//! [`schema::scene_schema`] (every struct field and enum variant the parser accepts),
//! [`shapes::SceneGeometry::of`] (points for meshing and plotting).
//!
//! Sections: `material` ([`material`]), `body` ([`body`]), `cracks`
//! ([`crack`]), `boundary` and `load` ([`boundary`]), `bem` ([`bem`]),
//! `reference` ([`reference`](mod@reference)), `pd` ([`pd`]), `coupling` and `growth`
//! ([`coupling`]), `outputs` ([`outputs`]). What is absent is not built: no
//! `pd` = BEM alone; `pd` without `coupling` = stand-alone PD; `coupling` =
//! PD windows in a BEM body; `growth` = crack growth.
//!
//! RON extensions `implicit_some` and `unwrap_variant_newtypes` are on, so
//! optional fields are written without `Some(...)` and newtype variants take
//! their struct fields directly (`solver: Adr(tolerance: 1e-8)`).
//!
//! ```ron
//! (
//!     name: "sent_a5",
//!     material: (E: 1e4, nu: 0.3333333333, plane: Stress),
//!     body: (outline: Rectangle(x0: 0, y0: 0, width: 20, height: 10)),
//!     cracks: [(name: "c", start: (10, 10), angle_deg: -90, length: 5)],
//!     boundary: [
//!         (on: "left", x: Traction(-0.5)),
//!         (on: "right", x: Traction(0.5)),
//!     ],
//!     bem: (element_size: 0.1),
//!     reference: SentTada(width: 10, sigma: 0.5),
//! )
//! ```

pub mod bem;
pub mod body;
pub mod boundary;
pub mod coupling;
pub mod crack;
pub mod error;
pub mod material;
pub mod outputs;
pub mod path;
pub mod pd;
pub mod reference;
pub mod schema;
pub mod shapes;
pub mod validate;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use bem::{BemSettings, JContour, TipRefinement};
pub use body::{Body, Hole, NamedEdge, Outline, Patch, Pt};
pub use boundary::{BoundaryCondition, Component, Load};
pub use coupling::{
    Coupling, CouplingOrdering, DisplacementMap, Growth, GrowthMode, OverstrainAction, Placement,
    Relaxation, WindowRefine,
};
pub use crack::{Crack, CrackForm, Faces};
pub use error::{Issue, SceneError};
pub use material::{Fracture, Material, Plane};
pub use outputs::{Grid, Line, Outputs, PlotFormat};
pub use pd::{
    AdrParams, ExplicitParams, Failure, ImplicitParams, PdModelKind, PdRefinement, PdSettings,
    PdSolver, PdTraction, PdZone, RefineCircle, RefineOn, RegionVelocity, SwitchingParams,
};
pub use reference::Reference;

/// One study: geometry, material, loading and the optional solver sections.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short identifier; the default run folder is `runs/<name>`. Required,
    /// letters, digits, `_`, `-`, `.` only.
    pub name: String,
    /// Free text. Default empty.
    #[serde(default)]
    pub description: String,
    /// Elastic constants and fracture data. Required.
    pub material: Material,
    /// Outline and holes. Required.
    pub body: Body,
    /// Cracks. Default: none.
    #[serde(default)]
    pub cracks: Vec<Crack>,
    /// Boundary conditions on named groups; unnamed parts are traction-free. Default: none.
    #[serde(default)]
    pub boundary: Vec<BoundaryCondition>,
    /// Load stepping. Default: one step at factor 1.
    #[serde(default)]
    pub load: Load,
    /// BEM settings. Default: all defaults.
    #[serde(default)]
    pub bem: BemSettings,
    /// Analytic reference. Default: none.
    #[serde(default)]
    pub reference: Option<Reference>,
    /// Peridynamics. Default: none (BEM alone).
    #[serde(default)]
    pub pd: Option<PdSettings>,
    /// PD-BEM coupling. Default: none.
    #[serde(default)]
    pub coupling: Option<Coupling>,
    /// Crack growth. Default: none (static solve).
    #[serde(default)]
    pub growth: Option<Growth>,
    /// Output selection. Default: plots and CSVs.
    #[serde(default)]
    pub outputs: Outputs,
    /// File the scene was loaded from (not part of the RON).
    #[serde(skip)]
    pub source: Option<PathBuf>,
    /// Messages from loading (e.g. orientation normalised), for the user.
    #[serde(skip)]
    pub notes: Vec<String>,
}

/// The RON options scenes are read with (`implicit_some`, `unwrap_variant_newtypes`).
pub fn ron_options() -> ron::Options {
    ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .with_default_extension(ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES)
}

impl Scene {
    /// Reads, parses, validates and normalises a scene file. Syntax errors name
    /// the file, line and column; rule violations the file, field path and reason.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|error| SceneError::Io {
            file: path.to_path_buf(),
            error,
        })?;
        Scene::from_ron_str(&text, path)
    }

    /// Parses, validates and normalises RON text; `file` labels messages.
    pub fn from_ron_str(text: &str, file: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let mut scene = Scene::parse(text, file.as_ref())?;
        scene.validate()?;
        scene.normalise();
        scene.add_notes();
        Ok(scene)
    }

    /// Parses RON text without validating.
    pub fn parse(text: &str, file: &Path) -> Result<Scene, SceneError> {
        let mut scene: Scene =
            ron_options()
                .from_str(text)
                .map_err(|e: ron::error::SpannedError| SceneError::Syntax {
                    file: file.to_path_buf(),
                    line: e.span.start.line,
                    column: e.span.start.col,
                    message: e.code.to_string(),
                })?;
        scene.source = Some(file.to_path_buf());
        Ok(scene)
    }

    /// Checks every rule (see [`validate`]); all violations are reported together.
    pub fn validate(&self) -> Result<(), SceneError> {
        let issues = validate::check(self);
        if issues.is_empty() {
            Ok(())
        } else {
            Err(SceneError::Invalid {
                file: self.file_label(),
                issues,
            })
        }
    }

    /// The file name used in messages (`<inline>` when not from a file).
    pub fn file_label(&self) -> PathBuf {
        self.source
            .clone()
            .unwrap_or_else(|| PathBuf::from("<inline>"))
    }

    /// Makes the outline counter-clockwise and polygon holes clockwise
    /// (DESIGN.md), keeping each edge's name on the same edge; adds a note when
    /// something was reversed.
    pub fn normalise(&mut self) {
        if let Outline::Polygon { points, edge_names } = &mut self.body.outline {
            let pts: Vec<_> = points.iter().map(|p| crate::geometry::p2(*p)).collect();
            if !crate::geometry::is_ccw(&pts) {
                reverse_loop(points, edge_names.as_mut());
                self.notes
                    .push("body.outline: points reversed to run counter-clockwise".into());
            }
        }
        for (i, hole) in self.body.holes.iter_mut().enumerate() {
            if let Hole::Polygon { points, .. } = hole {
                let pts: Vec<_> = points.iter().map(|p| crate::geometry::p2(*p)).collect();
                if crate::geometry::is_ccw(&pts) {
                    points.reverse();
                    self.notes
                        .push(format!("body.holes.{i}: points reversed to run clockwise"));
                }
            }
        }
    }

    /// Every note a loaded or edited scene carries: [`Self::note_inert_fields`], a
    /// reference the body departs from ([`Reference::scope_note`]) and a size jump of 4 at
    /// a refinement zone's edge ([`PdSettings::zone_notes`]).
    pub fn add_notes(&mut self) {
        self.note_inert_fields();
        if let Some(pd) = &self.pd {
            self.notes.extend(pd.zone_notes());
        }
        if let Some(note) = self.reference.as_ref().and_then(|r| r.scope_note(self)) {
            self.notes.push(note);
        }
    }

    /// Notes on fields the scene sets but no solver reads (no silent garbage):
    /// `material.fracture.s0` (the PD failure law is `pd.failure`), `material.nu`
    /// where the bond-based PD model (`pd.model: Pmb`) fixes its own, and the solver
    /// settings a refined body does not read ([`PdRefinement::inert_notes`]).
    pub fn note_inert_fields(&mut self) {
        if self
            .pd
            .as_ref()
            .is_some_and(|p| p.model == PdModelKind::Pmb)
        {
            let (pmb_nu, label) = match self.material.plane {
                Plane::Stress => (1.0 / 3.0, "1/3 in plane stress"),
                Plane::Strain => (0.25, "1/4 in plane strain"),
            };
            let nu = self.material.nu;
            if (nu - pmb_nu).abs() > 1e-6 {
                self.notes.push(format!(
                    "material.nu = {nu} is not the PD model's: bond-based PD (pd.model: Pmb) has nu = {label}, so the PD part runs with that ratio; pd.model: StateBased uses material.nu"
                ));
            }
        }
        if let Some(pd) = &self.pd {
            if let Some(r) = &pd.refinement {
                self.notes.extend(r.inert_notes(&pd.solver, &pd.failure));
            }
        }
        if let Some(note) = self.initiation_solver_note() {
            self.notes.push(note);
        }
        let s0 = self.material.fracture.as_ref().and_then(|f| f.s0);
        let failure = self.pd.as_ref().map(|p| &p.failure);
        if let Some(s0) = s0 {
            if failure != Some(&Failure::CriticalStretch(s0)) {
                self.notes.push(format!(
                    "material.fracture.s0 = {s0} is not read by any solver: the PD failure law is pd.failure (use CriticalStretch({s0}))"
                ));
            }
        }
    }

    /// Whether stand-alone PD runs its crack-initiation ramp on the grid (uniform, zones
    /// or refined cells; `crate::run_pd`): a breaking law, pre-cracks and a load ramp,
    /// neither explicit dynamics nor seed 004's particles. That ramp solves every load
    /// and break round by Newton, whatever `pd.solver` says.
    pub fn runs_pd_initiation_ramp(&self) -> bool {
        let Some(pd) = &self.pd else {
            return false;
        };
        let particles = pd
            .refinement
            .as_ref()
            .is_some_and(|r| !r.on_cells(&pd.failure, &pd.solver));
        let cracks = match &pd.pre_cracks {
            Some(names) => self.cracks.iter().any(|c| names.contains(&c.name)),
            None => !self.cracks.is_empty(),
        };
        self.coupling.is_none()
            && self.growth.is_none()
            && !particles
            && matches!(pd.failure, Failure::CriticalStretch(_) | Failure::FromGc)
            && !matches!(pd.solver, PdSolver::Explicit(_))
            && cracks
            && self.load.factors().len() > 1
    }

    /// The note for a `pd.solver` the crack-initiation ramp does not read
    /// ([`Self::runs_pd_initiation_ramp`]): ADR, the switch or Newton's own settings
    /// (the default solver and `Implicit()` say nothing the ramp does not do).
    fn initiation_solver_note(&self) -> Option<String> {
        let pd = self.pd.as_ref()?;
        let newton = PdSolver::Implicit(ImplicitParams::default());
        if !self.runs_pd_initiation_ramp()
            || pd.solver == PdSolver::default()
            || pd.solver == newton
        {
            return None;
        }
        Some(
            "pd.solver is not read: the crack-initiation ramp (a breaking pd.failure, pre-cracks and a load ramp) solves every load and every round of bond breaking by Newton to a relative displacement update of 1e-6 (pdbem_pd::measure::ramp_to_initiation); drop the field or write `solver: Implicit()`".into(),
        )
    }

    /// Every edge-group name a boundary condition may use.
    pub fn edge_groups(&self) -> Vec<String> {
        let mut g = self.body.outline.edge_names();
        if !matches!(self.body.outline, Outline::Infinite { .. }) {
            g.push("outline".into());
        }
        g.extend(self.body.patches.iter().map(|p| p.name.clone()));
        g.extend(self.body.holes.iter().enumerate().map(|(i, h)| h.name(i)));
        for c in &self.cracks {
            g.push(c.name.clone());
            g.extend(c.face_names());
        }
        g
    }

    /// True when a condition on group `on` applies to the boundary piece named `group` (an
    /// outline edge, patch, hole or crack face, as the BEM mesh and the PD set-up name
    /// them): the same name, `outline` for every outline edge and patch, a crack's name for
    /// both its faces.
    pub fn covers(&self, on: &str, group: &str) -> bool {
        if on == group {
            return true;
        }
        if on == "outline" && !matches!(self.body.outline, Outline::Infinite { .. }) {
            return self.body.outline.edge_names().iter().any(|n| n == group)
                || self.body.patches.iter().any(|p| p.name == group);
        }
        self.cracks
            .iter()
            .any(|c| c.name == on && c.face_names().iter().any(|f| f == group))
    }

    /// Scene with defaults applied to the JSON form (what sweeps edit).
    pub fn to_json(&self) -> serde_json::Value {
        // Serialising plain data with finite numbers cannot fail.
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }
}

/// Elements on a piece of boundary of length `len` (m) with target size `h`
/// (m): round(len / h). Zero means `h` is too coarse; validation rejects it.
pub fn elements_on(len: f64, h: f64) -> usize {
    let n = (len / h).round();
    if n.is_finite() && n > 0.0 {
        n as usize
    } else {
        0
    }
}

/// Reverses a polygon's point order and moves edge names so each stays on its
/// edge: edge k of the reversed loop is edge (n - 2 - k) mod n of the original.
fn reverse_loop(points: &mut [Pt], names: Option<&mut Vec<String>>) {
    let n = points.len();
    points.reverse();
    if let Some(names) = names {
        if names.len() == n {
            let old = names.clone();
            for (k, name) in names.iter_mut().enumerate() {
                *name = old[(2 * n - 2 - k) % n].clone();
            }
        }
    }
}

//! The data-in description of a PD problem: [`PdProblem`] and its parts.
//!
//! A problem is plain data (serde, no scene-file format assumed): the region
//! (outline polygon with holes), the grid spacing `dx` and horizon factor
//! `m` (horizon `delta = m dx`, DESIGN.md), thickness, Young's modulus, plane
//! stress or strain, the failure law, pre-cracks and boundary conditions.
//! All prescribed values (displacements, forces, tractions) are multiplied
//! by the model's load factor. [`PdProblem::validate`] checks every rule once
//! and names the field that breaks it.

use serde::{Deserialize, Serialize};

use crate::error::PdError;
use crate::geometry::{dist_point_polygon_boundary, point_in_polygon, rotate, signed_area, P2};

/// Horizon factor `m = delta / dx` used by all seed papers (seed 000 sections
/// 3.2-5.3, seed 001 section 6, seed 002 section 3).
pub const DEFAULT_HORIZON_FACTOR: f64 = 3.015;

/// Plane stress or plane strain (selects the PMB micromodulus, seed 002 Eq. 5, or the
/// state-based bulk modulus, [`crate::state_based::moduli`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Plane {
    /// Plane stress: PMB `c = 9E/(pi t delta^3)`, Poisson's ratio fixed at 1/3.
    #[default]
    Stress,
    /// Plane strain: PMB `c = 48E/(5 pi t delta^3)`, Poisson's ratio fixed at 1/4.
    Strain,
}

/// Smallest Poisson ratio of the state-based model. Its energy density
/// $a\theta^2 + \frac12\sum\beta e^2/|\xi|\,V'$ has $a = (\kappa - 2\mu)/2 < 0$ below
/// nu = 1/3 (plane stress), and from some negative nu on the dilatation term outweighs
/// the bond term for local modes: the tangent of a free, surface-corrected 12 x 12 plate
/// (dx = 1) has negative eigenvalues from nu = -0.30 (plane stress) and -0.40 (plane
/// strain) at m = 3.015, from nu = -0.10 at m = 4 and 6 and -0.20 at m = 2 (without
/// the correction from -0.85, plane stress). Solutions there are not equilibria of a
/// stable body: ADR diverges, and the Table 2 plate under Newton opens 17 % less than at
/// nu = 1/3 at nu = -0.9 (plane stress, where Irwin's opening does not depend on nu).
/// From nu = 0 on every plate tried is positive definite beyond its three rigid motions
/// (horizon factors 2 to 6, a pre-crack with and without the crack-face correction, a
/// refined zone; `pd/tests/properties_state_based.rs`).
pub const MIN_STATE_BASED_NU: f64 = 0.0;

/// The constitutive model of the PD body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Default)]
pub enum PdMaterial {
    /// Bond-based prototype microelastic brittle model (seed 002 Eqs. 3-5): Poisson's
    /// ratio fixed at 1/3 (plane stress) or 1/4 (plane strain).
    #[default]
    Pmb,
    /// Ordinary state-based PD (seed 004 Eqs. 3-8, [`crate::state_based`]) with the
    /// given Poisson's ratio, in [0, 1/2) ([`MIN_STATE_BASED_NU`]).
    StateBased {
        /// Poisson's ratio nu (-).
        poisson_ratio: f64,
    },
}

/// A hole in the region (a free surface; no nodes inside).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Hole {
    /// Circular hole.
    Circle {
        /// Centre (m).
        centre: P2,
        /// Radius (m).
        radius: f64,
    },
    /// Polygonal hole (any orientation).
    Polygon {
        /// Vertices (m).
        points: Vec<P2>,
    },
}

impl Hole {
    /// Whether `p` lies strictly inside the hole.
    pub fn contains(&self, p: P2) -> bool {
        match self {
            Hole::Circle { centre, radius } => (p[0] - centre[0]).hypot(p[1] - centre[1]) < *radius,
            Hole::Polygon { points } => point_in_polygon(p, points),
        }
    }

    /// Distance from `p` to the hole boundary.
    pub fn boundary_distance(&self, p: P2) -> f64 {
        match self {
            Hole::Circle { centre, radius } => {
                ((p[0] - centre[0]).hypot(p[1] - centre[1]) - radius).abs()
            }
            Hole::Polygon { points } => dist_point_polygon_boundary(p, points),
        }
    }
}

/// The body: an outline polygon (counter-clockwise) minus holes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Region {
    /// Outer boundary, counter-clockwise (m).
    pub outline: Vec<P2>,
    /// Holes (free surfaces).
    pub holes: Vec<Hole>,
}

impl Region {
    /// Axis-aligned rectangle `[min, max]`.
    pub fn rectangle(min: P2, max: P2) -> Self {
        Region {
            outline: vec![min, [max[0], min[1]], max, [min[0], max[1]]],
            holes: Vec::new(),
        }
    }

    /// Rectangle of `width x height` centred at `centre`, rotated by `angle`
    /// (radians, counter-clockwise). Pair it with `grid_angle = angle` so the
    /// grid follows the rectangle's sides.
    pub fn rotated_rectangle(centre: P2, width: f64, height: f64, angle: f64) -> Self {
        let (w, h) = (0.5 * width, 0.5 * height);
        let outline = [[-w, -h], [w, -h], [w, h], [-w, h]]
            .iter()
            .map(|&p| {
                let r = rotate(p, angle);
                [centre[0] + r[0], centre[1] + r[1]]
            })
            .collect();
        Region {
            outline,
            holes: Vec::new(),
        }
    }

    /// Whether `p` is material: inside the outline and in no hole.
    pub fn contains(&self, p: P2) -> bool {
        point_in_polygon(p, &self.outline) && !self.holes.iter().any(|h| h.contains(p))
    }
}

/// The failure law of the bonds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum Failure {
    /// Bonds never break (linear/nonlinear elasticity only).
    #[default]
    None,
    /// PMB brittle bonds breaking irreversibly at stretch `s0` (seed 002 Eq. 6).
    CriticalStretch {
        /// Critical stretch (dimensionless).
        s0: f64,
    },
    /// PMB brittle bonds with `s0` from the fracture energy (seed 002 Eq. 7).
    FractureEnergy {
        /// Critical energy release rate `G_c` (J/m^2).
        g_c: f64,
    },
    /// Continuous tanh degradation (seed 000 Eq. 12), irreversible through
    /// the largest stretch reached; a bond is broken once it reaches `s_c`.
    Degradation {
        /// Stretch where degradation starts.
        s_m: f64,
        /// Stretch where the bond carries no force.
        s_c: f64,
        /// Steepness (seed 000 uses 3).
        beta: f64,
    },
}

/// Which nodes a boundary condition acts on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Selection {
    /// Every candidate node (e.g. all fictitious nodes around a coupling window).
    All,
    /// Nodes with `min <= x <= max` componentwise.
    Box {
        /// Lower corner (m).
        min: P2,
        /// Upper corner (m).
        max: P2,
    },
    /// Nodes within `distance` of an open polyline (`None` = the horizon delta).
    NearPolyline {
        /// Polyline vertices (m).
        points: Vec<P2>,
        /// Distance (m); `None` means the horizon `delta`.
        distance: Option<f64>,
    },
    /// Nodes within `radius` of `centre`.
    Circle {
        /// Centre (m).
        centre: P2,
        /// Radius (m).
        radius: f64,
    },
    /// Nodes in a rectangle turned by any angle: $0 \le (p - o)\cdot a_i \le l_i$ for
    /// its corner `origin` $o$, unit `axes` $a_1 \perp a_2$ and `extent` $l$ (e.g. the
    /// fictitious strip along a side of a turned coupling window).
    OrientedBox {
        /// The corner the extents are measured from (m).
        origin: P2,
        /// Unit, orthogonal axes.
        axes: [P2; 2],
        /// Extents along the axes (m), >= 0.
        extent: [f64; 2],
    },
}

impl Selection {
    /// Whether point `p` is selected, given the horizon `delta`.
    pub fn contains(&self, p: P2, delta: f64) -> bool {
        let eps = 1e-9 * delta;
        match self {
            Selection::All => true,
            Selection::Box { min, max } => {
                p[0] >= min[0] - eps
                    && p[0] <= max[0] + eps
                    && p[1] >= min[1] - eps
                    && p[1] <= max[1] + eps
            }
            Selection::NearPolyline { points, distance } => {
                crate::geometry::dist_point_polyline(p, points) <= distance.unwrap_or(delta) + eps
            }
            Selection::Circle { centre, radius } => {
                (p[0] - centre[0]).hypot(p[1] - centre[1]) <= radius + eps
            }
            Selection::OrientedBox {
                origin,
                axes,
                extent,
            } => {
                let d = [p[0] - origin[0], p[1] - origin[1]];
                axes.iter().zip(extent).all(|(a, l)| {
                    let s = d[0] * a[0] + d[1] * a[1];
                    s >= -eps && s <= l + eps
                })
            }
        }
    }
}

/// Where a prescribed displacement acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Layer {
    /// On fictitious nodes created outside the region, within the horizon
    /// `delta` of its boundary (seed 000 section 2.3, seed 002 Fig. 1).
    #[default]
    Fictitious,
    /// On real nodes of the region (e.g. a pinned point).
    Real,
}

/// A boundary condition. Every value is multiplied by the load factor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum BoundaryCondition {
    /// Prescribed displacement per component (`None` leaves it free).
    Displacement {
        /// Selected nodes.
        on: Selection,
        /// Prescribed x displacement (m).
        ux: Option<f64>,
        /// Prescribed y displacement (m).
        uy: Option<f64>,
        /// Fictitious layer outside the region, or real nodes.
        layer: Layer,
    },
    /// A total force (N) spread as a uniform body force over the selected
    /// real nodes (seed 000 section 2.3: `b = P / (s dx)`).
    Force {
        /// Selected real nodes (the loading boundary layer).
        on: Selection,
        /// Total force (N).
        force: P2,
    },
    /// A traction (Pa) on an edge polyline, converted to a body force in the
    /// boundary layer of real nodes within `depth` (default `dx`) of the
    /// edge: total force `t * length * thickness` (seed 000 section 2.3,
    /// seed 001 section 6).
    Traction {
        /// Loaded edge (polyline on the boundary).
        edge: Vec<P2>,
        /// Traction vector (Pa).
        traction: P2,
        /// Depth of the boundary layer (m); `None` = `dx`.
        depth: Option<f64>,
    },
}

/// Everything needed to build a [`crate::PdModel`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PdProblem {
    /// The body.
    pub region: Region,
    /// Grid spacing (m).
    pub dx: f64,
    /// Horizon factor `m` (`delta = m dx`); default 3.015.
    pub horizon_factor: f64,
    /// Thickness (m); default 1.
    pub thickness: f64,
    /// Young's modulus (Pa).
    pub youngs_modulus: f64,
    /// Plane stress (default) or plane strain.
    pub plane: Plane,
    /// Bond failure law; default none.
    pub failure: Failure,
    /// Pre-cracks: bonds crossing these polylines are cut at start.
    pub cracks: Vec<Vec<P2>>,
    /// Boundary conditions, applied in order (a later one overrides an
    /// earlier one on the same component).
    pub boundary: Vec<BoundaryCondition>,
    /// How `Traction` conditions load the body: body-force layer (default) or
    /// seed 001's transfer functions ([`crate::traction`]).
    pub traction: TractionLoad,
    /// Apply the surface correction; default false. PMB: the Madenci-Oterkus energy
    /// method ([`crate::surface`]); state-based: the fourth-moment fit of
    /// [`crate::state_based`] (the node's energy density is the bulk one for every
    /// homogeneous strain).
    pub surface_correction: bool,
    /// Stiffen the bonds around pre-crack faces by the energy-method factor of the bonds
    /// the pre-cracks removed ([`crate::surface::apply_crack_face_correction`]; the
    /// state-based model fits the node's constants to its uncut family instead); default
    /// false.
    pub crack_face_correction: bool,
    /// Grid rotation (radians, counter-clockwise); default 0.
    pub grid_angle: f64,
    /// Grid origin (a cell corner); default: the lower-left corner of the
    /// outline's bounding box in the grid frame.
    pub grid_origin: Option<P2>,
    /// Constitutive model; default [`PdMaterial::Pmb`].
    pub material: PdMaterial,
    /// Zones whose cells are split into finer ones, with dual-horizon forces between
    /// the sizes ([`crate::mixed`]); default none (a uniform grid).
    pub refine_zones: Vec<crate::refine_zone::RefineZone>,
}

impl Default for PdProblem {
    fn default() -> Self {
        PdProblem {
            region: Region::default(),
            dx: 0.0,
            horizon_factor: DEFAULT_HORIZON_FACTOR,
            thickness: 1.0,
            youngs_modulus: 0.0,
            plane: Plane::Stress,
            failure: Failure::None,
            cracks: Vec::new(),
            boundary: Vec::new(),
            traction: TractionLoad::BodyForceLayer,
            surface_correction: false,
            crack_face_correction: false,
            grid_angle: 0.0,
            grid_origin: None,
            material: PdMaterial::Pmb,
            refine_zones: Vec::new(),
        }
    }
}

fn positive(field: &str, v: f64) -> Result<(), PdError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(PdError::invalid(
            field,
            format!("must be positive and finite, got {v}"),
        ))
    }
}

fn finite_point(field: &str, p: P2) -> Result<(), PdError> {
    if p[0].is_finite() && p[1].is_finite() {
        Ok(())
    } else {
        Err(PdError::invalid(field, format!("non-finite point {p:?}")))
    }
}

impl PdProblem {
    /// Horizon `delta = m dx` (m).
    pub fn horizon(&self) -> f64 {
        self.horizon_factor * self.dx
    }

    /// Check every rule; the error names the field and the violated constraint.
    pub fn validate(&self) -> Result<(), PdError> {
        positive("dx", self.dx)?;
        if !(self.horizon_factor.is_finite() && self.horizon_factor >= 1.0) {
            return Err(PdError::invalid(
                "horizon_factor",
                format!(
                    "horizon delta = m dx = {:.4e} m is smaller than dx = {:.4e} m (m = {}); use m >= 1 (3.015 is usual)",
                    self.horizon(),
                    self.dx,
                    self.horizon_factor
                ),
            ));
        }
        positive("thickness", self.thickness)?;
        positive("youngs_modulus", self.youngs_modulus)?;
        if let PdMaterial::StateBased { poisson_ratio: nu } = self.material {
            if !(nu.is_finite() && (MIN_STATE_BASED_NU..0.5).contains(&nu)) {
                return Err(PdError::invalid(
                    "material.poisson_ratio",
                    format!("state-based PD needs a Poisson ratio in [{MIN_STATE_BASED_NU}, 0.5): below 0 its discrete energy is not positive definite on every grid (crate::state_based, MIN_STATE_BASED_NU), from 0.5 on the bulk modulus is unbounded; got {nu}"),
                ));
            }
        }
        if !self.grid_angle.is_finite() {
            return Err(PdError::invalid("grid_angle", "must be finite"));
        }
        let outline = &self.region.outline;
        if outline.len() < 3 {
            return Err(PdError::invalid(
                "region.outline",
                format!(
                    "empty region: the outline needs at least 3 points, got {}",
                    outline.len()
                ),
            ));
        }
        for (k, p) in outline.iter().enumerate() {
            finite_point(&format!("region.outline[{k}]"), *p)?;
        }
        let area = signed_area(outline);
        if area <= 0.0 {
            return Err(PdError::invalid(
                "region.outline",
                format!("signed area {area:.4e} m^2: the outline must be non-degenerate and counter-clockwise"),
            ));
        }
        for (k, h) in self.region.holes.iter().enumerate() {
            match h {
                Hole::Circle { centre, radius } => {
                    finite_point(&format!("region.holes[{k}].centre"), *centre)?;
                    positive(&format!("region.holes[{k}].radius"), *radius)?;
                }
                Hole::Polygon { points } => {
                    if points.len() < 3 || signed_area(points).abs() == 0.0 {
                        return Err(PdError::invalid(
                            format!("region.holes[{k}].points"),
                            "a polygonal hole needs at least 3 points and non-zero area",
                        ));
                    }
                }
            }
        }
        match self.failure {
            Failure::None => {}
            Failure::CriticalStretch { s0 } => positive("failure.s0", s0)?,
            Failure::FractureEnergy { g_c } => positive("failure.g_c", g_c)?,
            Failure::Degradation { s_m, s_c, beta } => {
                positive("failure.s_m", s_m)?;
                positive("failure.s_c", s_c)?;
                if s_m >= s_c {
                    return Err(PdError::invalid(
                        "failure.s_m",
                        format!("s_m = {s_m} must be smaller than s_c = {s_c}"),
                    ));
                }
                if !(beta.is_finite() && beta >= 0.0) {
                    return Err(PdError::invalid(
                        "failure.beta",
                        format!("must be non-negative and finite, got {beta}"),
                    ));
                }
            }
        }
        let delta = self.horizon();
        for (c, line) in self.cracks.iter().enumerate() {
            if line.len() < 2 {
                return Err(PdError::invalid(
                    format!("cracks[{c}]"),
                    format!("a crack needs at least 2 points, got {}", line.len()),
                ));
            }
            for (k, &p) in line.iter().enumerate() {
                finite_point(&format!("cracks[{c}][{k}]"), p)?;
                if !point_in_polygon(p, outline) {
                    let d = dist_point_polygon_boundary(p, outline);
                    if d > delta {
                        return Err(PdError::invalid(
                            format!("cracks[{c}][{k}]"),
                            format!(
                                "crack point {p:?} lies outside the region outline by {d:.4e} m (more than the horizon {delta:.4e} m)"
                            ),
                        ));
                    }
                }
            }
        }
        for (b, bc) in self.boundary.iter().enumerate() {
            let field = format!("boundary[{b}]");
            let ok = match bc {
                BoundaryCondition::Displacement { ux, uy, .. } => {
                    ux.is_none_or(f64::is_finite) && uy.is_none_or(f64::is_finite)
                }
                BoundaryCondition::Force { force, .. } => force.iter().all(|v| v.is_finite()),
                BoundaryCondition::Traction {
                    edge,
                    traction,
                    depth,
                } => {
                    if edge.len() < 2 {
                        return Err(PdError::invalid(
                            format!("{field}.edge"),
                            "a traction edge needs at least 2 points",
                        ));
                    }
                    traction.iter().all(|v| v.is_finite()) && depth.is_none_or(|d| d > 0.0)
                }
            };
            if !ok {
                return Err(PdError::invalid(
                    field,
                    "non-finite value or non-positive depth",
                ));
            }
        }
        self.validate_zones()
    }

    /// The refinement zones ([`crate::mixed`]) and the settings they need.
    fn validate_zones(&self) -> Result<(), PdError> {
        for (k, z) in self.refine_zones.iter().enumerate() {
            crate::refine_zone::check_zone(k, z)?;
        }
        if self.refine_zones.is_empty() {
            return Ok(());
        }
        if self.traction == TractionLoad::TransferFunction {
            return Err(PdError::invalid(
                "refine_zones",
                "transfer-function tractions need a uniform grid; use the body-force layer",
            ));
        }
        Ok(())
    }
}

/// How [`BoundaryCondition::Traction`] conditions load the body ([`crate::traction`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum TractionLoad {
    /// Body force in a layer of real nodes within `depth` of the edge (seed
    /// 000 section 2.3).
    #[default]
    BodyForceLayer,
    /// Seed 001 transfer functions (Eqs. 12, 16, 17, 23), see the module docs.
    TransferFunction,
}

//! `cracks`: straight cracks from a start point (edge cracks start on the
//! outline: their mouth), centred straight cracks, and polylines.
//!
//! Exactly one form per crack:
//! - `start`, `angle_deg`, `length`: from `start` in direction `angle_deg`;
//! - `center`, `angle_deg`, `length`: centred on `center` (two tips);
//! - `points`: a polyline from the first point to the last.
//!
//! The flat layout keeps sweep paths short (`cracks.0.length`).

use serde::{Deserialize, Serialize};

use super::body::Pt;
use crate::geometry::{direction, p2, P2};

/// A crack (open polyline with two faces).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Crack {
    /// Group name; faces are also groups `<name>.upper` and `<name>.lower`
    /// (upper = left of the direction from first to last point).
    pub name: String,
    /// Start point (m) of a straight crack (its mouth if on the outline).
    #[serde(default)]
    pub start: Option<Pt>,
    /// Centre (m) of a straight interior crack.
    #[serde(default)]
    pub center: Option<Pt>,
    /// Direction (degrees, counter-clockwise from +x) of a straight crack.
    #[serde(default)]
    pub angle_deg: Option<f64>,
    /// Total length (m) of a straight crack, > 0.
    #[serde(default)]
    pub length: Option<f64>,
    /// Polyline points (m), at least 2.
    #[serde(default)]
    pub points: Option<Vec<Pt>>,
    /// `Coincident` faces (default) or separated by `Gap(g)` (m, g > 0).
    #[serde(default)]
    pub faces: Faces,
}

/// How the two crack faces are modelled in BEM.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Faces {
    /// Both faces on the crack line (the dual BIE keeps the system regular).
    #[default]
    Coincident,
    /// Faces offset by a total gap (m); seed 002 uses 1e-4 m.
    Gap(f64),
}

/// Which geometric form a crack uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrackForm {
    /// `start` + `angle_deg` + `length`.
    FromStart,
    /// `center` + `angle_deg` + `length`.
    Centered,
    /// `points`.
    Polyline,
}

impl Crack {
    /// The form this crack uses, or a message saying which fields conflict or miss.
    pub fn form(&self) -> Result<CrackForm, String> {
        let straight = self.angle_deg.is_some() || self.length.is_some();
        match (self.start.is_some(), self.center.is_some(), self.points.is_some()) {
            (true, false, false) | (false, true, false) => {
                if self.angle_deg.is_none() || self.length.is_none() {
                    return Err("a straight crack needs `angle_deg` and `length`".into());
                }
                Ok(if self.start.is_some() {
                    CrackForm::FromStart
                } else {
                    CrackForm::Centered
                })
            }
            (false, false, true) if !straight => Ok(CrackForm::Polyline),
            (false, false, true) => {
                Err("`points` cannot be combined with `angle_deg`/`length`".into())
            }
            (false, false, false) => Err(
                "give one form: `start`+`angle_deg`+`length`, `center`+`angle_deg`+`length`, or `points`"
                    .into(),
            ),
            _ => Err("give only one of `start`, `center`, `points`".into()),
        }
    }

    /// The crack as a polyline from its first to its last point (m), or `None`
    /// when the form is incomplete (see [`Crack::form`]).
    pub fn polyline(&self) -> Option<Vec<P2>> {
        let straight = |a: P2| {
            let d = direction(self.angle_deg?) * self.length?;
            Some((a, d))
        };
        match self.form().ok()? {
            CrackForm::FromStart => {
                let (a, d) = straight(p2(self.start?))?;
                Some(vec![a, a + d])
            }
            CrackForm::Centered => {
                let (c, d) = straight(p2(self.center?))?;
                Some(vec![c - d * 0.5, c + d * 0.5])
            }
            CrackForm::Polyline => Some(self.points.as_ref()?.iter().map(|p| p2(*p)).collect()),
        }
    }

    /// Face groups of this crack: `<name>.upper`, `<name>.lower`.
    pub fn face_names(&self) -> [String; 2] {
        [
            format!("{}.upper", self.name),
            format!("{}.lower", self.name),
        ]
    }
}

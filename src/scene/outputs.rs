//! `outputs`: which plots and tables a run writes, and where fields are
//! sampled. Absent = defaults (plots and CSVs on, no extra sampling).

use serde::{Deserialize, Serialize};

use super::body::Pt;

/// Output settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Outputs {
    /// Write plots. Default true.
    pub plots: bool,
    /// Plot formats. Default `[Png, Svg]`.
    pub formats: Vec<PlotFormat>,
    /// Write CSV tables. Default true.
    pub csv: bool,
    /// Mark element end points / nodes on the geometry plot. Default false.
    pub show_mesh: bool,
    /// Rectangular grids of interior points (field output). Default: none.
    pub grids: Vec<Grid>,
    /// Straight sampling lines of interior points. Default: none.
    pub lines: Vec<Line>,
    /// Edge groups whose boundary stresses (hoop stress on holes) are written. Default: none.
    pub boundary_stress: Vec<String>,
    /// Write VTK files for ParaView. Default false.
    pub vtk: bool,
}

impl Default for Outputs {
    fn default() -> Self {
        Outputs {
            plots: true,
            formats: vec![PlotFormat::Png, PlotFormat::Svg],
            csv: true,
            show_mesh: false,
            grids: Vec::new(),
            lines: Vec::new(),
            boundary_stress: Vec::new(),
            vtk: false,
        }
    }
}

/// Plot file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PlotFormat {
    /// Raster PNG.
    Png,
    /// Vector SVG.
    Svg,
}

/// A grid of nx x ny interior points over `[x0, x1] x [y0, y1]`; points
/// outside the body are skipped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    /// Name used in file names (`grid_<name>.csv`).
    pub name: String,
    /// Lower-left corner (m).
    pub from: Pt,
    /// Upper-right corner (m).
    pub to: Pt,
    /// Points along x, >= 1.
    pub nx: usize,
    /// Points along y, >= 1 (nx * ny at most 1000000).
    pub ny: usize,
}

/// `n` interior points evenly spaced from `from` to `to`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Line {
    /// Name used in file names (`line_<name>.csv`).
    pub name: String,
    /// Start (m).
    pub from: Pt,
    /// End (m).
    pub to: Pt,
    /// Number of points, 2 to 1000000.
    pub n: usize,
}

//! From a macro layout (outline, holes, cracks, window specifications) to the coupled
//! model: BEM mesh with the windows cut out, one PD model and one [`Interface`] per window.
//!
//! Interior windows become BEM holes (group `window<i>`); a window touching the outline is
//! cut out of it ([`crate::window::cut_outline`]). A crack whose tip lies in a window is
//! split at the window boundary: the outer part is meshed by BEM (its end on the hole is a
//! mouth, not a tip), the inner part becomes the PD pre-crack, extended by 0.99 delta
//! beyond the boundary so that virtual-real bonds across the crack are cut too.

use pdbem_bem::mesh::{CrackSpec, FaceMode, LoopSpec};
use pdbem_bem::{Mesh, MeshBuilder, V2};
use pdbem_pd::{PdModel, PdProblem};

use crate::error::CouplingError;
use crate::interface::Interface;
use crate::pd_window::{build_problem, EdgeCondition, PdSettings};
use crate::window::{cut_outline, Body, SideKind, Window, WindowSpec};

/// Fraction of the horizon by which PD pre-cracks reach beyond the window boundary.
const CRACK_EXTENSION: f64 = 0.99;

/// A crack of the macro body.
#[derive(Debug, Clone, PartialEq)]
pub struct MacroCrack {
    /// Name (BEM groups `<name>.upper` / `<name>.lower`).
    pub name: String,
    /// Polyline (m).
    pub points: Vec<V2>,
    /// Face mode of the BEM faces.
    pub faces: FaceMode,
    /// BEM element size along the crack (m); capped at the dx of a window it enters.
    pub element_size: f64,
    /// One BEM element per polyline segment: the caller placed the element ends (crack
    /// growth extends the faces by a set number of elements); `element_size` and the
    /// window cap are then ignored.
    pub segment_elements: bool,
}

/// The macro layout.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Outer boundary (counter-clockwise), its edge groups and element sizes.
    pub outline: LoopSpec,
    /// Holes of the body (BEM loops).
    pub holes: Vec<LoopSpec>,
    /// Cracks.
    pub cracks: Vec<MacroCrack>,
    /// Windows.
    pub windows: Vec<WindowSpec>,
    /// PD material and options of every window.
    pub pd: PdSettings,
}

/// One window ready to iterate.
#[derive(Debug, Clone)]
pub struct WindowModel {
    /// Geometry.
    pub window: Window,
    /// The PD problem it was built from.
    pub problem: PdProblem,
    /// PD model (state = last solve).
    pub model: PdModel,
    /// Interface data.
    pub interface: Interface,
    /// BEM group of its interface elements.
    pub group: String,
    /// Its frozen-history solvers, kept between equilibria (built on first use).
    pub solver: pdbem_pd::solvers::frozen::SolverSlot,
}

/// The built coupled geometry.
#[derive(Debug, Clone)]
pub struct Built {
    /// BEM mesh of the body without the windows.
    pub mesh: Mesh,
    /// Windows.
    pub windows: Vec<WindowModel>,
}

/// Name of window `i`'s interface group.
pub fn window_group(i: usize) -> String {
    format!("window{i}")
}

/// Places the windows, meshes the BEM body and builds the PD windows. `outer(i, w)` gives
/// the scene conditions on window i's outer sides.
pub fn build(
    layout: &Layout,
    outer: impl Fn(usize, &Window) -> Vec<EdgeCondition>,
) -> Result<Built, CouplingError> {
    let body = Body {
        outline: layout.outline.points.clone(),
        holes: layout.holes.iter().map(|h| h.points.clone()).collect(),
    };
    let windows = place_all(&layout.windows, &body)?;
    let mut b = MeshBuilder::new();
    let mut outline = (
        layout.outline.points.clone(),
        layout.outline.edge_groups.clone(),
        layout.outline.edge_sizes.clone(),
    );
    let mut holes = layout.holes.clone();
    for (i, w) in windows.iter().enumerate() {
        if w.sides.contains(&SideKind::Outer) {
            outline = cut_outline(i, w, &outline.0, &outline.1, &outline.2, &window_group(i))?;
        } else {
            holes.push(w.hole_loop(&window_group(i)));
        }
    }
    b.add_loop(LoopSpec {
        points: outline.0,
        edge_groups: outline.1,
        edge_sizes: outline.2,
        is_hole: false,
    });
    for h in holes {
        b.add_loop(h);
    }
    let mut pd_cracks: Vec<Vec<Vec<V2>>> = vec![Vec::new(); windows.len()];
    for (ci, c) in layout.cracks.iter().enumerate() {
        let mut line = Some(c.points.clone());
        let mut size = c.element_size;
        let mut window_dx: f64 = 0.0;
        for (wi, w) in windows.iter().enumerate() {
            let Some(pts) = line.clone() else { break };
            if let Some(split) = w.split_crack(ci, &pts, CRACK_EXTENSION * w.delta())? {
                pd_cracks[wi].push(split.pd);
                line = split.bem;
                size = size.min(w.spec.dx);
                window_dx = window_dx.max(w.spec.dx);
            }
        }
        if window_dx > 0.0 {
            // The mesher refines the loop at a crack mouth to the crack's size; below dx
            // that would split the window's interface elements (one per node row).
            size = size.max(window_dx);
        }
        if let Some(points) = line {
            if c.segment_elements {
                // Every segment is one element when the size is at least the longest
                // segment (the mesher takes round(length / size), at least 1); at least dx
                // so the mouth on a window hole does not refine its interface elements.
                size = longest_segment(&points).max(window_dx);
            }
            b.add_crack(CrackSpec {
                name: c.name.clone(),
                points,
                faces: c.faces,
                element_size: size,
                tip: None,
            });
        }
    }
    let mesh = b.build()?;
    let models = windows
        .into_iter()
        .enumerate()
        .map(|(i, w)| {
            let problem = build_problem(&w, &layout.pd, &pd_cracks[i], &outer(i, &w));
            window_model(i, w, problem, &mesh)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Built {
        mesh,
        windows: models,
    })
}

/// Length of the longest segment of a polyline (m).
fn longest_segment(points: &[V2]) -> f64 {
    points
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .fold(0.0, f64::max)
}

fn place_all(specs: &[WindowSpec], body: &Body) -> Result<Vec<Window>, CouplingError> {
    let windows = specs
        .iter()
        .enumerate()
        .map(|(i, s)| Window::place(i, s.clone(), body))
        .collect::<Result<Vec<_>, _>>()?;
    for a in 0..windows.len() {
        for b in a + 1..windows.len() {
            if windows[a].overlaps(&windows[b]) {
                return Err(CouplingError::WindowsOverlap { a, b });
            }
        }
    }
    Ok(windows)
}

fn window_model(
    i: usize,
    window: Window,
    problem: PdProblem,
    mesh: &Mesh,
) -> Result<WindowModel, CouplingError> {
    crate::pd_window::check_refine_zone(&window, &problem)
        .map_err(|r| CouplingError::pd(i, pdbem_pd::PdError::invalid("coupling.refine", r)))?;
    let mut model = PdModel::new(&problem).map_err(|e| CouplingError::pd(i, e))?;
    model.set_load_factor(1.0);
    let group = window_group(i);
    let g = mesh.group(&group).ok_or_else(|| CouplingError::Interface {
        window: i,
        message: format!("no BEM group '{group}'"),
    })?;
    let interface = Interface::new(i, &window, mesh, g, &model)?;
    Ok(WindowModel {
        window,
        problem,
        model,
        interface,
        group,
        solver: Default::default(),
    })
}

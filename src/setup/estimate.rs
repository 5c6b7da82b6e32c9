//! The size budget (issue 17): a cheap estimate of what a run of a validated scene will
//! allocate, computed from the scene alone, before any mesh or PD model is built, and
//! compared with a memory budget. `pdbem check` runs it before the exact
//! [`super::footprint`]; `pdbem run` and `pdbem sweep` before building anything.
//!
//! The estimate follows the one sizing rule of [`super::sizing`] in f64 arithmetic (no
//! loop over elements, no allocation proportional to the counts, saturating):
//! - BEM elements: round(length / size), at least 1, per outline edge and polygon-hole
//!   edge; `per_circle` per circular hole; per crack twice (two faces) the elements of
//!   its length at its size, plus radius / size per tip with `bem.tip_refinement`. The
//!   fine level of a Richardson pair halves every size. Dense bytes 8 (2N)^2.
//! - PD nodes: (extent / dx + 2 ceil(m))^2-like boxes: the body's bounding box at `pd.dx`
//!   (stand-alone PD, full-PD growth at the window spacing) or n x n per window plus the
//!   fictitious layers; directed bonds ~ nodes pi m^2 (m = horizon factor), bytes
//!   [`NODE_BYTES`] per node and [`BOND_BYTES`] per bond ([`STATE_BASED_BOND_BYTES`] for the
//!   state-based model).
//! - Stand-alone PD with `pd.refinement`: the children of its static regions
//!   ([`super::refined_size`]), the whole body at the refined particles' bytes (the
//!   splits of its criteria are checked by each split against the same budget).
//!
//! The budget defaults to half the machine's memory (`MemTotal` of `/proc/meminfo`,
//! 8 GiB when it cannot be read); `--max-memory` overrides it ([`set_budget`]).

use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{bail, Result};

use crate::geometry::{point_segment_distance, polyline_length, P2};
use crate::runner::mode::{mode_of, Mode};
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::{GrowthMode, Placement, Scene};

/// Bytes per PD node (positions, displacements, velocities, forces, masses, flags).
pub const NODE_BYTES: f64 = 256.0;
/// Bytes per directed PD bond (neighbour list, weights, damage, a share of the stiffness).
pub const BOND_BYTES: f64 = 64.0;
/// Bytes per directed bond of the state-based model: [`BOND_BYTES`] plus its per-bond
/// constants and force-pass scratch (`pdbem bench pd` measures 115 bytes of bond data).
pub const STATE_BASED_BOND_BYTES: f64 = 120.0;
/// Budget when the machine's memory cannot be read (8 GiB).
pub const FALLBACK_BUDGET: u64 = 8 << 30;

static BUDGET: AtomicU64 = AtomicU64::new(0);

/// Sets the budget of this process (`--max-memory`); 0 restores the default. The
/// engines take it too: sparse factors (Newton tangents, the refined ramp's
/// preconditioner) and every dense BEM system (a growing crack's mesh is checked at each
/// rebuild) are refused over it before they allocate.
pub fn set_budget(bytes: u64) {
    BUDGET.store(bytes, Ordering::Relaxed);
    pdbem_pd::tangent::set_factor_budget(budget());
    pdbem_bem::system::set_system_budget(budget());
}

/// The budget in bytes: the one set by [`set_budget`], else half of `MemTotal`, else
/// [`FALLBACK_BUDGET`].
pub fn budget() -> u64 {
    match BUDGET.load(Ordering::Relaxed) {
        0 => machine_memory().map(|m| m / 2).unwrap_or(FALLBACK_BUDGET),
        b => b,
    }
}

/// `MemTotal` of `/proc/meminfo` in bytes.
fn machine_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024)).filter(|&b| b > 0)
}

/// Parses a byte count: digits with an optional suffix K, M, G, T (powers of 1024, an
/// optional trailing `B` or `iB`), e.g. `4G`, `512M`, `1073741824`.
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let upper = t.to_ascii_uppercase();
    let core = upper
        .strip_suffix("IB")
        .or_else(|| upper.strip_suffix('B'))
        .unwrap_or(&upper);
    let (digits, shift) = match core.chars().last() {
        Some('K') => (&core[..core.len() - 1], 10),
        Some('M') => (&core[..core.len() - 1], 20),
        Some('G') => (&core[..core.len() - 1], 30),
        Some('T') => (&core[..core.len() - 1], 40),
        _ => (core, 0),
    };
    let bad = || format!("{t:?}: give a byte count like 4G, 512M or 1073741824");
    let v: f64 = digits.trim().parse().map_err(|_| bad())?;
    let bytes = v * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64) {
        return Err(bad());
    }
    Ok(bytes as u64)
}

/// What drives one part of the estimate: the setting to name and how many items it gives.
#[derive(Debug, Clone, PartialEq)]
pub struct Driver {
    /// The setting, e.g. `bem.element_size = 0.0005` or `cracks.0 ('c')`.
    pub setting: String,
    /// What to change.
    pub advice: String,
    /// Elements or nodes it gives.
    pub count: f64,
}

/// The estimated sizes of a run (f64: counts may exceed any integer type).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Estimate {
    /// BEM elements of the largest level.
    pub bem_elements: f64,
    /// Bytes of the dense BEM system, 8 (2N)^2.
    pub bem_bytes: f64,
    /// What gives the most BEM elements.
    pub bem_driver: Option<Driver>,
    /// PD nodes, real and fictitious.
    pub pd_nodes: f64,
    /// Directed PD bonds.
    pub pd_bonds: f64,
    /// What sets the PD grid.
    pub pd_driver: Option<Driver>,
    /// Bytes a refined body (`pd.refinement`) holds beyond `NODE_BYTES` per node and
    /// [`Self::bond_bytes`] per bond ([`add_refined`]).
    pub pd_refined_bytes: f64,
    /// The PD model is state-based (`pd.model: StateBased`): bonds at
    /// [`STATE_BASED_BOND_BYTES`].
    pub pd_state_based: bool,
}

impl Estimate {
    /// Bytes per directed PD bond of the scene's model.
    pub fn bond_bytes(&self) -> f64 {
        if self.pd_state_based {
            STATE_BASED_BOND_BYTES
        } else {
            BOND_BYTES
        }
    }

    /// PD bytes.
    pub fn pd_bytes(&self) -> f64 {
        self.pd_nodes * NODE_BYTES + self.pd_bonds * self.bond_bytes() + self.pd_refined_bytes
    }

    /// Total bytes.
    pub fn bytes(&self) -> f64 {
        self.bem_bytes + self.pd_bytes()
    }

    /// Fails when the estimate exceeds `budget` bytes, naming what drives the size.
    pub fn within(&self, scene: &Scene, budget: u64) -> Result<()> {
        let b = budget as f64;
        if self.bytes() <= b {
            return Ok(());
        }
        let file = scene.file_label();
        let budget_text = bytes_text(b);
        if self.bem_bytes >= self.pd_bytes() {
            let d = self.bem_driver.clone().unwrap_or(Driver {
                setting: "bem.element_size".into(),
                advice: "raise bem.element_size".into(),
                count: self.bem_elements,
            });
            bail!(
                "{}: {} gives about {} of {} BEM elements ({} dense matrix > budget {budget_text}): {}, or raise the budget with --max-memory",
                file.display(),
                d.setting,
                count_text(d.count),
                count_text(self.bem_elements),
                bytes_text(self.bem_bytes),
                d.advice
            );
        }
        let d = self.pd_driver.clone().unwrap_or(Driver {
            setting: "pd".into(),
            advice: "coarsen the PD grid".into(),
            count: self.pd_nodes,
        });
        bail!(
            "{}: {} gives about {} PD nodes and {} bonds ({} > budget {budget_text}): {}, or raise the budget with --max-memory",
            file.display(),
            d.setting,
            count_text(self.pd_nodes),
            count_text(self.pd_bonds),
            bytes_text(self.pd_bytes()),
            d.advice
        )
    }
}

/// Estimates a validated scene and checks it against [`budget`].
pub fn check(scene: &Scene) -> Result<Estimate> {
    let e = of(scene)?;
    e.within(scene, budget())?;
    crate::run_dynamic::check(scene)?;
    Ok(e)
}

/// Most elements the static BEM count walks before it calls the mesh too large (the
/// dense matrix of 1e6 elements is 29 TiB).
pub const COUNT_LIMIT: usize = 1_000_000;

/// The estimate of a validated scene (never builds a mesh or a PD model). Static BEM
/// scenes are counted exactly by walking the local-size mesh without building it
/// ([`pdbem_bem::MeshBuilder::count`]); an error is a feature too small to mesh.
pub fn of(scene: &Scene) -> Result<Estimate> {
    let geo = SceneGeometry::of(scene);
    let mut e = Estimate::default();
    let growth = scene.growth.as_ref().map(|g| g.mode);
    let bem = match mode_of(scene) {
        Mode::Pd => false,
        Mode::Growth => growth != Some(GrowthMode::FullPd),
        _ => true,
    };
    if bem {
        let refine = if mode_of(scene) == Mode::Bem && scene.bem.richardson {
            2.0
        } else {
            1.0
        };
        bem_elements(scene, &geo, refine, &mut e);
        if mode_of(scene) == Mode::Bem {
            static_bem_elements(scene, &geo, refine, &mut e)?;
        }
    }
    let m = scene.pd.as_ref().map(|p| p.horizon_factor).unwrap_or(3.015);
    e.pd_state_based = scene
        .pd
        .as_ref()
        .is_some_and(|p| p.model == crate::scene::PdModelKind::StateBased);
    let layers = 2.0 * m.ceil();
    match (mode_of(scene), growth, &scene.coupling) {
        (Mode::Pd, _, _) => {
            if let Some(pd) = &scene.pd {
                let (w, h) = extent(&geo);
                let (dx, setting, advice) = match (pd.dx, pd.nx) {
                    (Some(dx), _) => (dx, format!("pd.dx = {dx}"), "raise pd.dx"),
                    (None, Some(nx)) => (w / nx as f64, format!("pd.nx = {nx}"), "lower pd.nx"),
                    (None, None) => (f64::NAN, "pd".into(), "give pd.dx"),
                };
                let nodes = (w / dx + layers) * (h / dx + layers);
                add_pd(&mut e, nodes, m, setting, advice);
                add_zones(&mut e, &pd.refine_zones, (w, h), dx, m);
                if let Some(r) = &pd.refinement {
                    add_refined(&mut e, r, &geo, dx, m);
                }
            }
        }
        (Mode::Growth, Some(GrowthMode::FullPd), Some(co)) => {
            let (w, h) = extent(&geo);
            let dx = co.dx();
            let nodes = (w / dx + layers) * (h / dx + layers);
            let setting = format!("coupling.n = {} (full PD at dx = side / n = {dx})", co.n);
            add_pd(
                &mut e,
                nodes,
                m,
                setting,
                "lower coupling.n or raise coupling.side",
            );
        }
        (_, _, Some(co)) => {
            let n = co.n as f64;
            let (per, count) = match &co.placement {
                Placement::AtTips => {
                    let tips: usize = geo.cracks.iter().map(|c| if c.mouth { 1 } else { 2 }).sum();
                    ((n + layers).powi(2), tips as f64)
                }
                Placement::Centered { .. } => ((n + layers).powi(2), 1.0),
                Placement::Region { height, .. } => {
                    ((n + layers) * (height / co.dx() + layers), 1.0)
                }
            };
            let setting = format!("coupling.n = {} ({count} window(s))", co.n);
            add_pd(&mut e, per * count, m, setting, "lower coupling.n");
        }
        _ => {}
    }
    Ok(e)
}

/// Dense-matrix bytes of the static BEM mesh of `scene` at refinement `refine`, by the
/// exact element count (the tolerance loop of [`crate::refine`] asks before each level).
pub fn level(scene: &Scene, refine: f64) -> Result<f64> {
    let geo = SceneGeometry::of(scene);
    let groups = super::bem::mesh_builder(scene, &geo, refine)?
        .count(COUNT_LIMIT)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let n: usize = groups.iter().map(|(_, n)| n).sum();
    Ok(8.0 * (2.0 * n as f64).powi(2))
}

/// Exact element count of the static BEM mesh at `refine` (its local sizes), replacing
/// the uniform-size estimate when the count stays under [`COUNT_LIMIT`]; the largest
/// group is named as the driver.
fn static_bem_elements(
    scene: &Scene,
    geo: &SceneGeometry,
    refine: f64,
    e: &mut Estimate,
) -> Result<()> {
    let builder = super::bem::mesh_builder(scene, geo, refine)?;
    let Ok(groups) = builder.count(COUNT_LIMIT) else {
        // Over the limit: the uniform-size estimate (larger still) names the driver.
        e.bem_elements = e.bem_elements.max(COUNT_LIMIT as f64);
        e.bem_bytes = 8.0 * (2.0 * e.bem_elements).powi(2);
        return Ok(());
    };
    let total: usize = groups.iter().map(|(_, n)| n).sum();
    e.bem_elements = total as f64;
    e.bem_bytes = 8.0 * (2.0 * e.bem_elements).powi(2);
    if let Some((g, n)) = groups.iter().max_by_key(|(_, n)| *n) {
        let crack = scene.cracks.iter().position(|c| &c.name == g);
        let (setting, advice) = match (crack, scene.bem.group_sizes.get(g)) {
            (Some(i), None) => (
                format!("cracks.{i} ('{g}'): its tip zones (1/80 of the tip length scale) and faces"),
                format!("move the tip of '{g}' away from the nearest boundary, or set bem.group_sizes.{g}"),
            ),
            (_, Some(h)) => (
                format!("bem.group_sizes.{g} = {h}"),
                format!("raise bem.group_sizes.{g}"),
            ),
            (None, None) => match scene.bem.element_size {
                Some(h) => (format!("bem.element_size = {h}"), "raise bem.element_size".into()),
                None => (
                    format!("the default element size on '{g}'"),
                    "give a larger bem.element_size".into(),
                ),
            },
        };
        e.bem_driver = Some(Driver {
            setting,
            advice,
            count: *n as f64,
        });
    }
    Ok(())
}

fn add_pd(e: &mut Estimate, nodes: f64, m: f64, setting: String, advice: &str) {
    let nodes = if nodes.is_nan() { f64::INFINITY } else { nodes };
    e.pd_nodes += nodes;
    e.pd_bonds += nodes * std::f64::consts::PI * m * m;
    e.pd_driver = Some(Driver {
        setting,
        advice: advice.into(),
        count: nodes,
    });
}

/// Adds [`super::refined_size::zone_children`] to `e`; the zones name the size's driver
/// when they add more nodes than the grid has.
fn add_zones(e: &mut Estimate, zones: &[crate::scene::PdZone], body: (f64, f64), dx: f64, m: f64) {
    let extra = super::refined_size::zone_children(zones, body, dx);
    let drives = extra > e.pd_nodes;
    e.pd_nodes += extra;
    e.pd_bonds += extra * std::f64::consts::PI * m * m;
    if drives {
        e.pd_driver = Some(Driver {
            setting: format!("pd.refine_zones ({} zone(s))", zones.len()),
            advice: "shrink the zones or lower their levels".into(),
            count: extra,
        });
    }
}

/// Adds [`super::refined_size::refined_children`] to `e`. The whole body is then refined
/// particles, at [`pdbem_pd::refine::PARTICLE_BYTES`] and
/// [`pdbem_pd::refine::BOND_BYTES`], and the last level's split holds the body before it
/// (a quarter of the children) beside it.
fn add_refined(
    e: &mut Estimate,
    r: &crate::scene::PdRefinement,
    geo: &SceneGeometry,
    dx: f64,
    m: f64,
) {
    use pdbem_pd::refine::{BOND_BYTES as REFINED_BOND, PARTICLE_BYTES};
    let (nodes, bonds) = super::refined_size::refined_children(r, geo, dx, m);
    let refined = |n: f64, b: f64| n * PARTICLE_BYTES + b * REFINED_BOND;
    let (n, b) = (e.pd_nodes + nodes, e.pd_bonds + bonds);
    let whole = refined(n, b) + 0.25 * refined(nodes, bonds);
    e.pd_refined_bytes += (whole - (n * NODE_BYTES + b * e.bond_bytes())).max(0.0);
    if nodes <= 0.0 {
        return;
    }
    (e.pd_nodes, e.pd_bonds) = (n, b);
    e.pd_driver = Some(Driver {
        setting: format!(
            "pd.refinement (max_level {}, its circles and near_cracks)",
            r.max_level
        ),
        advice: "lower pd.refinement.max_level or shrink its regions".into(),
        count: nodes,
    });
}

/// Width and height of the body's bounding box (the features' for an infinite body).
fn extent(geo: &SceneGeometry) -> (f64, f64) {
    let mut pts: Vec<P2> = geo
        .outline
        .as_ref()
        .map(|o| o.points.clone())
        .unwrap_or_default();
    if pts.is_empty() {
        for c in &geo.cracks {
            pts.extend(c.points.iter().copied());
        }
    }
    if pts.is_empty() {
        return (0.0, 0.0);
    }
    let (lo, hi) = crate::geometry::bounding_box(&pts);
    (hi.x - lo.x, hi.y - lo.y)
}

/// round(len / h), at least 1, as `subdivide` gives (f64, saturating).
fn pieces(len: f64, h: f64) -> f64 {
    let n = (len / h).round();
    if n.is_nan() {
        f64::INFINITY
    } else {
        n.max(1.0)
    }
}

/// BEM elements of the scene at refinement `refine`, and their largest driver.
fn bem_elements(scene: &Scene, geo: &SceneGeometry, refine: f64, e: &mut Estimate) {
    let b = &scene.bem;
    let base = b.base_size(geo) / refine;
    let size_of = |g: &str| b.group_sizes.get(g).map(|s| s / refine).unwrap_or(base);
    let setting_of = |g: &str| match (b.group_sizes.get(g), b.element_size) {
        (Some(s), _) => (
            format!("bem.group_sizes.{g} = {s}"),
            format!("raise bem.group_sizes.{g}"),
        ),
        (None, Some(h)) => (
            format!("bem.element_size = {h}"),
            "raise bem.element_size".into(),
        ),
        (None, None) => (
            format!(
                "the default element size {:.3e} m (2 % of the body's smaller side) on '{g}'",
                base * refine
            ),
            "give a larger bem.element_size".into(),
        ),
    };
    let mut drivers: Vec<Driver> = Vec::new();
    let mut add = |count: f64, (setting, advice): (String, String)| match drivers
        .iter_mut()
        .find(|d| d.setting == setting)
    {
        Some(d) => d.count += count,
        None => drivers.push(Driver {
            setting,
            advice,
            count,
        }),
    };
    let mut segments: Vec<(P2, P2)> = Vec::new();
    if let Some(o) = &geo.outline {
        let n = o.points.len();
        for k in 0..n {
            let (a, c) = (o.points[k], o.points[(k + 1) % n]);
            segments.push((a, c));
            add(
                pieces((c - a).norm(), size_of(&o.groups[k])),
                setting_of(&o.groups[k]),
            );
        }
        // Patches split edges: at most one more element per patch end.
        if !scene.body.patches.is_empty() {
            add(2.0 * scene.body.patches.len() as f64, setting_of("outline"));
        }
    }
    let per_circle = b
        .elements_per_circle
        .unwrap_or(super::sizing::DEFAULT_ELEMENTS_PER_CIRCLE) as f64
        * refine;
    let mut circles: Vec<(P2, f64)> = Vec::new();
    for (name, h) in &geo.holes {
        match h {
            HoleShape::Circle { center, radius } => {
                circles.push((*center, *radius));
                let setting = match b.elements_per_circle {
                    Some(n) => format!("bem.elements_per_circle = {n}"),
                    None => "the default 128 elements per circle".into(),
                };
                add(
                    per_circle,
                    (setting, "lower bem.elements_per_circle".into()),
                );
            }
            HoleShape::Polygon(p) => {
                let n = p.len();
                for k in 0..n {
                    let (a, c) = (p[k], p[(k + 1) % n]);
                    segments.push((a, c));
                    add(pieces((c - a).norm(), size_of(name)), setting_of(name));
                }
            }
        }
    }
    for (i, cr) in geo.cracks.iter().enumerate() {
        let len = polyline_length(&cr.points);
        let h = match b.group_sizes.get(&cr.name) {
            Some(s) => s / refine,
            None => {
                let l = tip_scale(&cr.points, cr.mouth, len, &segments, &circles);
                (base * refine).min(l * super::sizing::DEFAULT_CRACK_FRACTION) / refine
            }
        };
        let tips = if cr.mouth { 1.0 } else { 2.0 };
        let mut n = pieces(len, h);
        if let Some(t) = &b.tip_refinement {
            let ht = t.element_size / refine;
            if ht < h && t.radius > 0.0 {
                n += tips * pieces(t.radius.min(len), ht);
            }
        }
        let setting = match (b.group_sizes.get(&cr.name), &b.tip_refinement) {
            (_, Some(t)) if t.element_size / refine < h => (
                format!(
                    "bem.tip_refinement (element_size = {}) on cracks.{i} ('{}')",
                    t.element_size, cr.name
                ),
                "raise bem.tip_refinement.element_size or lower its radius".into(),
            ),
            (Some(_), _) => setting_of(&cr.name),
            (None, _) => (
                format!(
                    "cracks.{i} ('{}'): its default size {h:.3e} m (1/80 of its tip length scale)",
                    cr.name
                ),
                format!(
                    "set bem.group_sizes.{} larger, or move the tip away from the boundary",
                    cr.name
                ),
            ),
        };
        add(2.0 * n, setting);
    }
    let total: f64 = drivers.iter().map(|d| d.count).sum();
    e.bem_elements = total;
    e.bem_bytes = 8.0 * (2.0 * total).powi(2);
    e.bem_driver = drivers
        .into_iter()
        .max_by(|a, b| a.count.total_cmp(&b.count));
}

/// The crack's tip length scale (as [`super::sizing`]): its length (half for an interior
/// crack), or the distance from a tip to the outline or a hole if shorter.
fn tip_scale(pts: &[P2], mouth: bool, len: f64, segs: &[(P2, P2)], circles: &[(P2, f64)]) -> f64 {
    let mut l = if mouth { len } else { 0.5 * len };
    let mut tips: Vec<P2> = pts.last().copied().into_iter().collect();
    if !mouth {
        tips.extend(pts.first().copied());
    }
    for t in tips {
        for (a, b) in segs {
            let d = point_segment_distance(&t, a, b);
            if d > 1e-9 * len {
                l = l.min(d);
            }
        }
        for (c, r) in circles {
            let d = ((t - c).norm() - r).abs();
            if d > 1e-9 * len {
                l = l.min(d);
            }
        }
    }
    l
}

/// A count with three significant digits.
pub fn count_text(n: f64) -> String {
    if n < 1e6 {
        format!("{n:.0}")
    } else {
        format!("{n:.3e}")
    }
}

/// Bytes with binary units (KiB to PiB, then powers of ten).
pub fn bytes_text(b: f64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut v = b;
    for u in units {
        if v < 1024.0 {
            return format!("{v:.3} {u}");
        }
        v /= 1024.0;
    }
    format!("{b:.3e} B")
}

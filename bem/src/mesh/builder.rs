//! Mesh generation from loops and cracks.

use pdbem_geometry::{point_segment_projection, signed_area};

use super::breaks::{crack_stations, edge_breaks, edge_pieces, too_many};
use super::size_field::{SizeField, SizeSource};
pub use super::spec::{CrackSpec, FaceMode, TipRefinement, MAX_ELEMENTS};
use super::{Crack, Element, Mesh, V2};
use crate::BemError;

/// A closed polygonal loop: the outer boundary or a hole.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopSpec {
    /// Vertices (orientation is normalised by the builder).
    pub points: Vec<V2>,
    /// Group name of each edge (edge i runs from point i to point i+1).
    pub edge_groups: Vec<String>,
    /// Target element size of each edge; an edge shorter than its size is one element.
    pub edge_sizes: Vec<f64>,
    /// True for a hole (clockwise), false for the outer boundary (counter-clockwise).
    pub is_hole: bool,
}

impl LoopSpec {
    /// The outer boundary `[x0, x0 + w] x [y0, y0 + h]` in elements of about `size`, its
    /// edges in the groups `bottom`, `right`, `top` and `left`.
    pub fn rectangle(x0: f64, y0: f64, w: f64, h: f64, size: f64) -> Self {
        Self {
            points: vec![
                V2::new(x0, y0),
                V2::new(x0 + w, y0),
                V2::new(x0 + w, y0 + h),
                V2::new(x0, y0 + h),
            ],
            edge_groups: ["bottom", "right", "top", "left"]
                .map(String::from)
                .to_vec(),
            edge_sizes: vec![size; 4],
            is_hole: false,
        }
    }
}

/// Collects loops and cracks and builds the [`Mesh`].
#[derive(Debug, Clone, Default)]
pub struct MeshBuilder {
    loops: Vec<LoopSpec>,
    cracks: Vec<CrackSpec>,
    field: Option<SizeField>,
}

impl MeshBuilder {
    /// Empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a closed loop.
    pub fn add_loop(&mut self, l: LoopSpec) -> &mut Self {
        self.loops.push(l);
        self
    }

    /// Adds a crack.
    pub fn add_crack(&mut self, c: CrackSpec) -> &mut Self {
        self.cracks.push(c);
        self
    }

    /// Meshes every edge and crack by the local size field `f` (sizes capped by the edge
    /// and crack sizes; [`super::size_field`]). Crack mouths and `CrackSpec::tip` become
    /// sources of the field. Without a field, edges and cracks are uniform with the
    /// refinements of [`subdivide`].
    pub fn set_size_field(&mut self, f: SizeField) -> &mut Self {
        self.field = Some(f);
        self
    }

    /// Elements per group name (crack faces counted under the crack's name), without
    /// building anything; an error when the total would pass `limit`.
    pub fn count(&self, limit: usize) -> Result<Vec<(String, usize)>, BemError> {
        let mut out: Vec<(String, usize)> = Vec::new();
        let mut total = 0usize;
        let mut add = |name: &str, n: usize| -> Result<(), BemError> {
            total = total.saturating_add(n);
            if total > limit {
                return Err(BemError::Mesh(format!(
                    "more than {limit} elements (at '{name}')"
                )));
            }
            match out.iter_mut().find(|(g, _)| g == name) {
                Some(e) => e.1 += n,
                None => out.push((name.to_string(), n)),
            }
            Ok(())
        };
        let Layout {
            loops,
            cuts,
            ends,
            field,
        } = self.layout()?;
        for (li, l) in loops.iter().enumerate() {
            for ei in 0..l.points.len() {
                let (a, b) = edge(l, ei);
                let (size, cut) = (l.edge_sizes[ei], &cuts[li][ei]);
                let n = edge_breaks(a, b, size, cut, field.as_ref(), limit, |_, _| ())
                    .ok_or_else(|| too_many(&l.edge_groups[ei], limit))?;
                add(&l.edge_groups[ei], n)?;
            }
        }
        for (c, on) in self.cracks.iter().zip(ends) {
            let n = crack_stations(c, on, field.as_ref(), limit)
                .ok_or_else(|| too_many(&c.name, limit))?
                .len()
                - 1;
            add(&c.name, 2 * n)?;
        }
        Ok(out)
    }

    /// Oriented loops, mouth cuts per loop edge, which crack ends sit on a loop, and the
    /// size field with the mouth and tip sources.
    fn layout(&self) -> Result<Layout, BemError> {
        let loops: Vec<LoopSpec> = self.loops.iter().map(oriented).collect::<Result<_, _>>()?;
        let tol = self.tolerance();
        // Mouths: (loop, edge, parameter interval removed) per crack end on a loop.
        let mut cuts: Vec<Vec<Vec<(f64, f64, f64)>>> = loops
            .iter()
            .map(|l| vec![Vec::new(); l.points.len()])
            .collect();
        let mut ends = Vec::new();
        for c in &self.cracks {
            check_crack(c)?;
            let gap = match c.faces {
                FaceMode::Coincident => 0.0,
                FaceMode::Gap(g) => g,
            };
            let mut on = [false, false];
            for (k, &p) in [c.points[0], *c.points.last().unwrap()].iter().enumerate() {
                if let Some((li, ei, t)) = find_on_loop(&loops, p, tol) {
                    on[k] = true;
                    let l = &loops[li];
                    let (a, b) = edge(l, ei);
                    let half = 0.5 * gap / (b - a).norm();
                    cuts[li][ei].push((t - half, t + half, c.element_size));
                }
            }
            ends.push(on);
        }
        let field = self.field.as_ref().map(|f| {
            let mut extra = Vec::new();
            for (c, on) in self.cracks.iter().zip(&ends) {
                let ps = [c.points[0], *c.points.last().unwrap()];
                for k in 0..2 {
                    if on[k] {
                        let h = c.element_size;
                        extra.push(SizeSource::point(ps[k], h, 3.0 * h));
                    } else if let Some(t) = c.tip {
                        extra.push(SizeSource::point(ps[k], t.size, t.radius));
                    }
                }
            }
            f.with(extra)
        });
        Ok(Layout {
            loops,
            cuts,
            ends,
            field,
        })
    }

    /// Builds the mesh.
    pub fn build(&self) -> Result<Mesh, BemError> {
        let mut mesh = Mesh::default();
        let Layout {
            loops,
            cuts,
            ends,
            field,
        } = self.layout()?;
        for (li, l) in loops.iter().enumerate() {
            let start = mesh.elements.len();
            for ei in 0..l.points.len() {
                let g = group_index(&mut mesh.groups, &l.edge_groups[ei]);
                let (a, b) = edge(l, ei);
                let pieces = edge_pieces(a, b, l.edge_sizes[ei], &cuts[li][ei], field.as_ref())
                    .ok_or_else(|| too_many(&l.edge_groups[ei], MAX_ELEMENTS))?;
                for (p, q) in pieces {
                    mesh.elements.push(Element::new(p, q, g));
                }
            }
            mesh.loops.push(start..mesh.elements.len());
        }
        for (c, on) in self.cracks.iter().zip(ends) {
            add_crack_faces(&mut mesh, c, on, field.as_ref())?;
        }
        Ok(mesh)
    }

    /// Geometric tolerance: 1e-9 of the largest extent.
    fn tolerance(&self) -> f64 {
        let mut ext: f64 = 0.0;
        for l in &self.loops {
            for p in &l.points {
                ext = ext.max(p.x.abs()).max(p.y.abs());
            }
        }
        for c in &self.cracks {
            for p in &c.points {
                ext = ext.max(p.x.abs()).max(p.y.abs());
            }
        }
        1e-9 * ext.max(1e-300)
    }
}

/// What [`MeshBuilder::build`] and [`MeshBuilder::count`] share.
struct Layout {
    /// Loops in the orientation DESIGN.md requires.
    loops: Vec<LoopSpec>,
    /// Per loop and edge: (start, end, crack element size) of each mouth cut.
    cuts: Vec<Vec<Vec<(f64, f64, f64)>>>,
    /// Per crack: whether its start and its end sit on a loop (mouths).
    ends: Vec<[bool; 2]>,
    /// The builder's size field with the mouth and tip sources added.
    field: Option<SizeField>,
}

fn edge(l: &LoopSpec, i: usize) -> (V2, V2) {
    (l.points[i], l.points[(i + 1) % l.points.len()])
}

fn group_index(groups: &mut Vec<String>, name: &str) -> usize {
    if let Some(i) = groups.iter().position(|g| g == name) {
        i
    } else {
        groups.push(name.to_string());
        groups.len() - 1
    }
}

/// Loop with the orientation DESIGN.md requires (edge data carried along when reversed).
fn oriented(l: &LoopSpec) -> Result<LoopSpec, BemError> {
    let n = l.points.len();
    if n < 3 || l.edge_groups.len() != n || l.edge_sizes.len() != n {
        return Err(BemError::Mesh(format!(
            "a loop needs at least 3 points and one group and size per edge (points {n}, groups {}, sizes {})",
            l.edge_groups.len(),
            l.edge_sizes.len()
        )));
    }
    if let Some(s) = l.edge_sizes.iter().find(|s| s.is_nan() || **s <= 0.0) {
        return Err(BemError::Mesh(format!("element size {s} must be positive")));
    }
    let area = signed_area(&l.points);
    if area == 0.0 {
        return Err(BemError::Mesh("loop of zero area".into()));
    }
    let want_ccw = !l.is_hole;
    if (area > 0.0) == want_ccw {
        return Ok(l.clone());
    }
    // Reverse: edge i (p_i -> p_{i+1}) becomes edge n-1-i of the reversed loop.
    let mut points = l.points.clone();
    points.reverse();
    let mut groups = l.edge_groups.clone();
    let mut sizes = l.edge_sizes.clone();
    // Reversed points q_k = p_{n-1-k}; edge k runs q_k -> q_{k+1} = p_{n-1-k} -> p_{n-2-k},
    // which is old edge n-2-k (mod n).
    groups = (0..n)
        .map(|k| groups[(2 * n - 2 - k) % n].clone())
        .collect();
    sizes = (0..n).map(|k| sizes[(2 * n - 2 - k) % n]).collect();
    Ok(LoopSpec {
        points,
        edge_groups: groups,
        edge_sizes: sizes,
        is_hole: l.is_hole,
    })
}

fn check_crack(c: &CrackSpec) -> Result<(), BemError> {
    if c.points.len() < 2 {
        return Err(BemError::Mesh(format!(
            "crack '{}' needs at least 2 points",
            c.name
        )));
    }
    if c.points.windows(2).any(|w| (w[1] - w[0]).norm() == 0.0) {
        return Err(BemError::Mesh(format!(
            "crack '{}' has a zero-length segment",
            c.name
        )));
    }
    if c.element_size.is_nan() || c.element_size <= 0.0 {
        return Err(BemError::Mesh(format!(
            "crack '{}': element size {} must be positive",
            c.name, c.element_size
        )));
    }
    if let FaceMode::Gap(g) = c.faces {
        if g.is_nan() || g <= 0.0 {
            return Err(BemError::Mesh(format!(
                "crack '{}': gap {g} must be positive",
                c.name
            )));
        }
    }
    Ok(())
}

fn find_on_loop(loops: &[LoopSpec], p: V2, tol: f64) -> Option<(usize, usize, f64)> {
    for (li, l) in loops.iter().enumerate() {
        for ei in 0..l.points.len() {
            let (a, b) = edge(l, ei);
            // A zero-length edge matches nothing (its projection parameter is 0/0).
            if a == b {
                continue;
            }
            let (d, t) = point_segment_projection(&p, &a, &b);
            if d <= tol {
                return Some((li, ei, t));
            }
        }
    }
    None
}

fn add_crack_faces(
    mesh: &mut Mesh,
    c: &CrackSpec,
    on: [bool; 2],
    field: Option<&SizeField>,
) -> Result<(), BemError> {
    let gap = match c.faces {
        FaceMode::Coincident => 0.0,
        FaceMode::Gap(g) => g,
    };
    let pts = crack_stations(c, on, field, MAX_ELEMENTS)
        .ok_or_else(|| too_many(&c.name, MAX_ELEMENTS))?;
    let np = pts.len();
    let nseg = c.points.len() - 1;
    // Left normal at each break point (averaged at polyline vertices).
    let seg_normal = |k: usize| {
        let d = (c.points[k + 1] - c.points[k]).normalize();
        V2::new(-d.y, d.x)
    };
    let offset = |i: usize| -> V2 {
        let is_tip = (i == 0 && !on[0]) || (i == np - 1 && !on[1]);
        if gap == 0.0 || is_tip {
            return V2::zeros();
        }
        let k = pts[i].2;
        let nrm = if i > 0 && k > 0 && pts[i - 1].2 == k - 1 {
            (seg_normal(k - 1) + seg_normal(k)).normalize()
        } else {
            seg_normal(k.min(nseg - 1))
        };
        nrm * (0.5 * gap)
    };
    let gu = group_index(&mut mesh.groups, &format!("{}.upper", c.name));
    let gl = group_index(&mut mesh.groups, &format!("{}.lower", c.name));
    let mut crack = Crack {
        name: c.name.clone(),
        points: c.points.clone(),
        start_is_tip: !on[0],
        end_is_tip: !on[1],
        upper: Vec::new(),
        lower: Vec::new(),
        stations: Vec::new(),
        gap,
    };
    for i in 0..np - 1 {
        let (p, q) = (pts[i].0, pts[i + 1].0);
        let (op, oq) = (offset(i), offset(i + 1));
        crack.upper.push(mesh.elements.len());
        mesh.elements.push(Element::new(p + op, q + oq, gu));
        crack.lower.push(mesh.elements.len());
        mesh.elements.push(Element::new(q - oq, p - op, gl));
        crack.stations.push(0.5 * (pts[i].1 + pts[i + 1].1));
    }
    mesh.cracks.push(crack);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(w: f64, h: f64, size: f64) -> LoopSpec {
        LoopSpec::rectangle(0.0, 0.0, w, h, size)
    }

    #[test]
    fn rectangle_is_counter_clockwise_with_outward_normals() {
        let mut b = MeshBuilder::new();
        b.add_loop(rect(2.0, 1.0, 0.25));
        let m = b.build().unwrap();
        assert_eq!(m.len(), 24);
        let bottom = m.group("bottom").unwrap();
        for e in m.elements.iter().filter(|e| e.group == bottom) {
            assert!((e.normal - V2::new(0.0, -1.0)).norm() < 1e-14);
        }
    }

    #[test]
    fn reversed_loop_keeps_edge_names() {
        let mut l = rect(2.0, 1.0, 0.5);
        l.points.reverse();
        l.edge_groups = ["top", "right", "bottom", "left"]
            .map(String::from)
            .to_vec();
        let mut b = MeshBuilder::new();
        b.add_loop(l);
        let m = b.build().unwrap();
        let top = m.group("top").unwrap();
        for e in m.elements.iter().filter(|e| e.group == top) {
            assert!((e.normal - V2::new(0.0, 1.0)).norm() < 1e-14, "{:?}", e);
        }
    }

    #[test]
    fn edge_crack_splits_the_edge_at_its_mouth() {
        let mut b = MeshBuilder::new();
        b.add_loop(rect(2.0, 1.0, 0.3));
        b.add_crack(CrackSpec {
            name: "c".into(),
            points: vec![V2::new(0.77, 1.0), V2::new(0.77, 0.5)],
            faces: FaceMode::Gap(1e-4),
            element_size: 0.05,
            tip: None,
        });
        let m = b.build().unwrap();
        let c = &m.cracks[0];
        assert!(!c.start_is_tip && c.end_is_tip);
        assert_eq!(c.upper.len(), 10);
        let top = m.group("top").unwrap();
        let total: f64 = m
            .elements
            .iter()
            .filter(|e| e.group == top)
            .map(|e| e.h)
            .sum();
        assert!((total - (2.0 - 1e-4)).abs() < 1e-12);
        // Upper face (left of downward direction = +x side) has normal pointing to -x.
        let u = &m.elements[c.upper[3]];
        assert!((u.normal - V2::new(-1.0, 0.0)).norm() < 1e-12);
        assert!(u.mid.x > 0.77);
        let l = &m.elements[c.lower[3]];
        assert!((l.mid.y - u.mid.y).abs() < 1e-14);
    }
}

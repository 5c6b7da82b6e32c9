//! Load-displacement output of PD and coupled runs (issue 19): for every boundary group of
//! the scene, the force it puts on the body (N; the reaction of a support, the applied
//! resultant of a load) and the mean displacement of its nodes or elements (m), after
//! every load step.
//!
//! - PD: [`pdbem_pd::reaction`] (reactions from nodal equilibrium at the prescribed
//!   components, loads as the layer's body-force resultant).
//! - BEM body (static and coupled runs): the force of a group is the thickness times the
//!   sum of t_e h_e over its elements (t = sigma . n on the boundary), the displacement
//!   the length-weighted mean of u_e; a group inside a PD window of a coupled run gets the
//!   scene's applied resultant and no displacement. The solve is linear, so the record is
//!   the unloaded state and the solved one.
//!
//! Files: `load_displacement.csv` (`step,load` then `<group>.<kind>.fx,fy,ux,uy` per
//! group), the plot `load_displacement` (force against displacement along the force,
//! for every group that moves), and `summary.load_displacement` (the last state and the
//! imbalance |sum of forces| / max |force|, zero in equilibrium).

use anyhow::Result;
use serde_json::{json, Value};

use crate::output::csv::{num, CsvTable};
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::scene::{Component, Scene};
use pdbem_pd::reaction::{BcKind, BcResultant};
use pdbem_pd::solvers::StepRecord;

/// Largest imbalance that passes without a note. Measured on the cases: 3e-10 to 4e-11
/// (implicit PD: `pd_bar_tension`, `pd_cantilever`), 1.1e-3 (`pd_three_point_bend`, ADR
/// at its tolerance), 3.5e-3 (`coupled_beam_shear`: the support's reaction against the
/// load the PD window carries, the interface's force transfer). Above 1 % a reaction is
/// not the load it balances.
pub const IMBALANCE_LIMIT: f64 = 1e-2;

/// Curves with more points than this are drawn as lines without markers.
const MARKED_POINTS: usize = 40;

/// One state of one group: force (N) and mean displacement (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Force on the body (N).
    pub force: [f64; 2],
    /// Mean displacement (m).
    pub displacement: [f64; 2],
}

/// The record of one boundary group over the load steps.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupCurve {
    /// Scene boundary group (`on`), or `pin`.
    pub group: String,
    /// Support (prescribed displacement) or load.
    pub kind: BcKind,
    /// One state per step of [`LoadDisplacement::loads`].
    pub states: Vec<State>,
    /// False for a group of a coupled run that a PD window carries: its force is the
    /// scene's applied resultant and its displacement is not recorded.
    pub displacement_known: bool,
}

/// Load factors and the groups' records.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LoadDisplacement {
    /// Load factor of each step.
    pub loads: Vec<f64>,
    /// One curve per (group, kind).
    pub groups: Vec<GroupCurve>,
    /// The largest, over the states, sum of the magnitudes of the forces the record is
    /// made of (N): each PD condition's resultant, each BEM element's force. A group
    /// whose loads balance among themselves (a pressurised hole) has a net force of
    /// round-off, and the imbalance is measured against this instead.
    pub gross: f64,
}

fn kind_name(k: BcKind) -> &'static str {
    match k {
        BcKind::Support => "support",
        BcKind::Load => "load",
    }
}

impl LoadDisplacement {
    /// From the steps of a PD solve; `labels` name the problem's boundary conditions
    /// (those of one group and kind are summed, their displacements averaged by nodes).
    pub fn from_pd(labels: &[String], steps: &[StepRecord]) -> LoadDisplacement {
        let mut out = LoadDisplacement::default();
        for (s, step) in steps.iter().enumerate() {
            out.loads.push(step.load);
            let gross: f64 = step
                .resultants
                .iter()
                .map(|r| r.force[0].hypot(r.force[1]))
                .sum();
            out.gross = out.gross.max(gross);
            let mut nodes: Vec<usize> = vec![0; out.groups.len()];
            for (r, label) in step.resultants.iter().zip(labels) {
                let g = out.group_index(label, r.kind, s);
                if nodes.len() <= g {
                    nodes.resize(g + 1, 0);
                }
                accumulate(&mut out.groups[g].states[s], r, &mut nodes[g]);
            }
        }
        out
    }

    /// The unloaded state and the solved one of a linear BEM solve at `load`.
    pub fn from_bem(
        scene: &Scene,
        mesh: &pdbem_bem::Mesh,
        solution: &pdbem_bem::Solution,
        load: f64,
    ) -> LoadDisplacement {
        let mut out = LoadDisplacement {
            loads: vec![0.0, load],
            groups: Vec::new(),
            gross: 0.0,
        };
        for bc in &scene.boundary {
            let support = [bc.x, bc.y]
                .iter()
                .any(|c| matches!(c, Component::Displacement(_)));
            let kind = if support {
                BcKind::Support
            } else {
                BcKind::Load
            };
            if out
                .groups
                .iter()
                .any(|c| c.group == bc.on && c.kind == kind)
            {
                continue;
            }
            let zero = State {
                force: [0.0; 2],
                displacement: [0.0; 2],
            };
            let groups: Vec<usize> = (0..mesh.groups.len())
                .filter(|&g| scene.covers(&bc.on, &mesh.groups[g]))
                .collect();
            if groups.is_empty() {
                // Inside a PD window: the window carries the group's load.
                let f = crate::setup::pd::applied_resultant(scene, &bc.on);
                out.groups.push(GroupCurve {
                    group: bc.on.clone(),
                    kind,
                    states: vec![
                        zero,
                        State {
                            force: [load * f[0], load * f[1]],
                            displacement: [0.0; 2],
                        },
                    ],
                    displacement_known: false,
                });
                continue;
            }
            let (mut f, mut u, mut len) = ([0.0; 2], [0.0; 2], 0.0);
            for (e, el) in mesh
                .elements
                .iter()
                .enumerate()
                .filter(|(_, e)| groups.contains(&e.group))
            {
                for c in 0..2 {
                    f[c] += scene.material.thickness * solution.t[e][c] * el.h;
                    u[c] += solution.u[e][c] * el.h;
                }
                out.gross +=
                    scene.material.thickness * solution.t[e][0].hypot(solution.t[e][1]) * el.h;
                len += el.h;
            }
            let solved = State {
                force: f,
                displacement: [
                    u[0] / len.max(f64::MIN_POSITIVE),
                    u[1] / len.max(f64::MIN_POSITIVE),
                ],
            };
            out.groups.push(GroupCurve {
                group: bc.on.clone(),
                kind,
                states: vec![zero, solved],
                displacement_known: true,
            });
        }
        out
    }

    fn group_index(&mut self, label: &str, kind: BcKind, step: usize) -> usize {
        let i = match self
            .groups
            .iter()
            .position(|g| g.group == label && g.kind == kind)
        {
            Some(i) => i,
            None => {
                self.groups.push(GroupCurve {
                    group: label.to_string(),
                    kind,
                    states: Vec::new(),
                    displacement_known: true,
                });
                self.groups.len() - 1
            }
        };
        let states = &mut self.groups[i].states;
        while states.len() <= step {
            states.push(State {
                force: [0.0; 2],
                displacement: [0.0; 2],
            });
        }
        i
    }

    /// |sum of the forces| at the last state over the largest |force| of any group at
    /// any state, or [`Self::gross`] when larger (0 without forces). The scale is the
    /// run's, not the last state's: a plate cracked through by its last step carries
    /// round-off reactions (1e-10 N after 2.6e3 N), whose sum is not an imbalance of the
    /// loads; nor is the round-off net force of a pressurised hole, the only load of its
    /// body (it was noted as an imbalance of 1.00).
    pub fn imbalance(&self) -> f64 {
        let sum = self
            .groups
            .iter()
            .filter_map(|g| g.states.last())
            .fold([0.0f64; 2], |s, st| {
                [s[0] + st.force[0], s[1] + st.force[1]]
            });
        let scale = self
            .groups
            .iter()
            .flat_map(|g| g.states.iter())
            .map(|st| st.force[0].hypot(st.force[1]))
            .fold(self.gross, f64::max);
        if scale == 0.0 {
            0.0
        } else {
            sum[0].hypot(sum[1]) / scale
        }
    }

    /// `load_displacement.csv`.
    pub fn table(&self) -> CsvTable {
        let mut head = vec!["step".to_string(), "load".to_string()];
        for g in &self.groups {
            for q in ["fx", "fy", "ux", "uy"] {
                head.push(format!("{}.{}.{q}", g.group, kind_name(g.kind)));
            }
        }
        let refs: Vec<&str> = head.iter().map(String::as_str).collect();
        let mut t = CsvTable::new(&refs);
        for (s, load) in self.loads.iter().enumerate() {
            let mut row = vec![s.to_string(), num(*load)];
            for g in &self.groups {
                let st = g.states[s];
                row.extend([st.force[0], st.force[1]].map(num));
                if g.displacement_known {
                    row.extend([st.displacement[0], st.displacement[1]].map(num));
                } else {
                    row.extend([String::new(), String::new()]);
                }
            }
            t.push(row);
        }
        t
    }

    /// The summary's `load_displacement`: the last state of every group and the
    /// imbalance.
    pub fn summary(&self) -> Value {
        let groups: Vec<Value> = self
            .groups
            .iter()
            .filter_map(|g| {
                let s = g.states.last()?;
                let u = g.displacement_known.then_some(s.displacement);
                Some(json!({"group": g.group, "kind": kind_name(g.kind),
                            "force": s.force, "displacement": u}))
            })
            .collect();
        json!({"steps": self.loads.len(), "imbalance": self.imbalance(), "groups": groups})
    }

    /// Force against displacement along the force, one curve per group that moves and
    /// carries a force (a fixed support has no curve: its reaction is in the table; nor
    /// has a support whose reaction is below 1e-6 of the largest force, a pin of a
    /// self-balanced body).
    pub fn plot(&self, title: &str) -> Option<XyPlot> {
        let mut p = XyPlot::new(
            title,
            "mean displacement along the force (m)",
            "force on the body (N)",
        );
        let size = |g: &GroupCurve| {
            g.states
                .iter()
                .map(|s| s.force[0].hypot(s.force[1]))
                .fold(0.0, f64::max)
        };
        let largest = self.groups.iter().map(size).fold(0.0, f64::max);
        for g in self.groups.iter().filter(|g| g.displacement_known) {
            // A pin against rigid motion of a self-balanced body carries round-off only:
            // its "direction" is noise, so it gets no curve (it stays in the table).
            if size(g) <= 1e-6 * largest {
                continue;
            }
            let Some(dir) = g.states.iter().rev().find_map(|s| unit(s.force)) else {
                continue;
            };
            // From the unloaded body (every solve starts at u = 0).
            let pts: Vec<(f64, f64)> = std::iter::once((0.0, 0.0))
                .chain(
                    g.states
                        .iter()
                        .map(|s| (dot(s.displacement, dir), dot(s.force, dir))),
                )
                .collect();
            if pts.iter().all(|q| q.0 == 0.0) {
                continue;
            }
            let style = if pts.len() > MARKED_POINTS {
                SeriesStyle::Line
            } else {
                SeriesStyle::LineMarkers
            };
            let label = format!("{} ({})", g.group, kind_name(g.kind));
            p.series.push(Series::new(label, pts, style));
        }
        (!p.series.is_empty()).then_some(p)
    }
}

fn accumulate(s: &mut State, r: &BcResultant, nodes: &mut usize) {
    let (n0, n1) = (*nodes as f64, (*nodes + r.nodes) as f64);
    for c in 0..2 {
        s.force[c] += r.force[c];
        s.displacement[c] = if n1 > 0.0 {
            (s.displacement[c] * n0 + r.displacement[c] * r.nodes as f64) / n1
        } else {
            0.0
        };
    }
    *nodes += r.nodes;
}

fn unit(v: [f64; 2]) -> Option<[f64; 2]> {
    let l = v[0].hypot(v[1]);
    (l > 0.0 && l.is_finite()).then(|| [v[0] / l, v[1] / l])
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Writes the CSV, the plot and the summary field, and a note when the last state of a
/// finite body is out of balance by more than [`IMBALANCE_LIMIT`] (an infinite plate
/// balances a net force on its holes and crack faces at infinity: a Griffith crack with
/// one face pressed had the note).
pub fn write(
    scene: &Scene,
    ctx: &crate::runner::context::RunContext,
    ld: &LoadDisplacement,
    summary: &mut crate::runner::summary::RunSummary,
) -> Result<()> {
    if ld.groups.is_empty() {
        return Ok(());
    }
    summary
        .extra
        .insert("load_displacement".into(), ld.summary());
    let imb = ld.imbalance();
    // An infinite plate carries a net force on its holes and crack faces at infinity.
    let infinite = crate::scene::shapes::SceneGeometry::of(scene)
        .outline
        .is_none();
    if imb > IMBALANCE_LIMIT && !infinite {
        summary.notes.push(format!(
            "load_displacement: the boundary forces do not balance: |sum| = {:.2e} of the \
             largest (limit {IMBALANCE_LIMIT:.0e}): the reactions are not the loads they \
             balance (an equilibrium not converged at the last load step: tighten the \
             solver tolerance; in a coupled run, the interface's force transfer)",
            imb
        ));
    }
    if scene.outputs.csv {
        ctx.writer.write_csv("load_displacement.csv", &ld.table())?;
    }
    if scene.outputs.plots {
        // A ramp that stopped early (`complete: false`) says so where its curve ends.
        let end = match summary.incomplete() {
            Some(_) => ", stopped at the last point",
            None => "",
        };
        if let Some(p) = ld.plot(&format!("{}: load-displacement{end}", scene.name)) {
            crate::runner::report::save_plot(
                &ctx.writer,
                "load_displacement",
                &p,
                &scene.outputs.formats,
                summary,
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(group: &str, kind: BcKind, force: [f64; 2], disp: [f64; 2]) -> GroupCurve {
        GroupCurve {
            group: group.into(),
            kind,
            states: vec![State {
                force,
                displacement: disp,
            }],
            displacement_known: true,
        }
    }

    /// A plate cracked through by its last step: the reactions fall from 2.6e3 N to
    /// round-off, whose sum is no imbalance of the run's loads; a last state out of
    /// balance by 2 % of the run's force is one; a pressurised hole is not.
    #[test]
    fn the_imbalance_is_measured_against_the_runs_largest_force() {
        let state = |fy: f64| State {
            force: [0.0, fy],
            displacement: [0.0, 0.0],
        };
        let group = |name: &str, fys: &[f64]| GroupCurve {
            group: name.into(),
            kind: BcKind::Support,
            states: fys.iter().map(|&f| state(f)).collect(),
            displacement_known: true,
        };
        let cracked = LoadDisplacement {
            loads: vec![7.3, 7.4, 7.5],
            groups: vec![
                group("top", &[2639.16, 856.94, 7.9e-10]),
                group("bottom", &[-2639.16, -856.94, -4.0e-10]),
            ],
            gross: 0.0,
        };
        let imb = cracked.imbalance();
        assert!(imb < 1e-12, "{imb}");
        let unbalanced = LoadDisplacement {
            loads: vec![1.0, 2.0],
            groups: vec![
                group("top", &[1000.0, 2000.0]),
                group("bottom", &[-1000.0, -1960.0]),
            ],
            gross: 0.0,
        };
        let imb = unbalanced.imbalance();
        assert!((imb - 0.02).abs() < 1e-12, "{imb}");
        assert!(imb > IMBALANCE_LIMIT);
        // A pressurised hole, the only load of a free body: its segments' forces add up
        // to 6.3e4 N and cancel to round-off; against that, no imbalance (1.00 before).
        let hole = LoadDisplacement {
            loads: vec![1.0],
            groups: vec![group("hole0", &[3.1e-11]), group("pin", &[-1.2e-11])],
            gross: 6.3e4,
        };
        let imb = hole.imbalance();
        assert!(imb < 1e-12, "{imb}");
    }

    /// A self-balanced plate: the two loads get curves, the pin (round-off reaction, a
    /// rigid drift of its node) does not.
    #[test]
    fn a_pin_of_a_self_balanced_body_gets_no_curve() {
        let ld = LoadDisplacement {
            loads: vec![1.0],
            groups: vec![
                curve("top", BcKind::Load, [0.0, 7e5], [0.0, 3e-5]),
                curve("bottom", BcKind::Load, [0.0, -7e5], [0.0, -1e-6]),
                curve("pin", BcKind::Support, [2e-7, -3e-5], [0.0, 2e-5]),
            ],
            gross: 1.4e6,
        };
        let p = ld.plot("t").expect("a plot");
        let labels: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels.len(), 2, "{labels:?}");
        assert!(labels.iter().all(|l| !l.starts_with("pin")), "{labels:?}");
    }
}

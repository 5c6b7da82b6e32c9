//! ParaView output of a growth run (`outputs.vtk: true`): every field snapshot as
//! `snapshot_<label>.vtu` (the stem of its plot), the crack paths and the PD window
//! outlines as line cells (`paths.vtu`, `windows.vtu`, each cell with its 0-based load
//! step), and `growth.pvd`, the snapshots in the order they were taken (load steps and
//! window relocations) as a time series ParaView steps through.

use anyhow::Result;

use super::{FieldSnapshot, GrowthHistory};
use crate::runner::context::RunContext;
use crate::vtk::{point_cloud, pvd, segments, Field};

/// The file stem of a snapshot (shared with its plot): `snapshot_<label>` when the label
/// names its step, else `snapshot_<label>_step<NNN>`.
pub fn snapshot_stem(s: &FieldSnapshot) -> String {
    if s.label.contains("step") {
        format!("snapshot_{}", s.label)
    } else {
        format!("snapshot_{}_step{:03}", s.label, s.step)
    }
}

/// Writes the snapshots, paths, windows and the collection.
pub fn write(ctx: &RunContext, h: &GrowthHistory) -> Result<()> {
    let w = &ctx.writer;
    let mut seen = std::collections::HashSet::new();
    let mut entries = Vec::new();
    for s in &h.snapshots {
        let stem = snapshot_stem(s);
        if !seen.insert(stem.clone()) {
            continue;
        }
        let name = if s.label.starts_with("damage") {
            "damage"
        } else {
            "displacement_magnitude"
        };
        let bytes = point_cloud(&s.points, vec![(name, Field::Scalars(s.values.clone()))])
            .map_err(anyhow::Error::msg)?;
        let file = format!("{stem}.vtu");
        w.write_bytes(&file, &bytes)?;
        entries.push((entries.len() as f64, file));
    }
    w.write_bytes("growth.pvd", pvd(&entries).as_bytes())?;
    let (mut ends, mut tip, mut step) = (Vec::new(), Vec::new(), Vec::new());
    for (k, p) in h.paths.iter().enumerate() {
        for q in p.points.windows(2) {
            ends.push(([q[0].x, q[0].y], [q[1].x, q[1].y]));
            tip.push(k as f64);
            step.push(q[1].step as f64);
        }
    }
    let bytes = segments(
        &ends,
        vec![("tip", Field::Scalars(tip)), ("step", Field::Scalars(step))],
    )
    .map_err(anyhow::Error::msg)?;
    w.write_bytes("paths.vtu", &bytes)?;
    let (mut ends, mut step) = (Vec::new(), Vec::new());
    for o in &h.windows {
        for i in 0..4 {
            ends.push((o.corners[i], o.corners[(i + 1) % 4]));
            step.push(o.step as f64);
        }
    }
    let bytes =
        segments(&ends, vec![("step", Field::Scalars(step))]).map_err(anyhow::Error::msg)?;
    w.write_bytes("windows.vtu", &bytes)?;
    Ok(())
}

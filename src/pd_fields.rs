//! The field outputs of a stand-alone PD run, shared by the regular grid
//! ([`crate::run_pd`]) and refined particles ([`crate::run_refined`]): `nodes.csv`,
//! `nodes.vtu` (with `outputs.vtk`) and the damage and |u| plots.

use anyhow::Result;

use crate::output::csv::{num, CsvTable};
use crate::plot::ScatterField;
use crate::runner::context::RunContext;
use crate::runner::report::save_plot;
use crate::runner::summary::RunSummary;
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Node CSV and damage / displacement plots of the nodes at `x` with displacements `u`
/// and damage `phi`.
pub(crate) fn write_fields(
    scene: &Scene,
    ctx: &RunContext,
    (x, u, phi): (&[[f64; 2]], &[[f64; 2]], &[f64]),
    summary: &mut RunSummary,
) -> Result<()> {
    let n = x.len();
    let mut t = CsvTable::new(&["x", "y", "ux", "uy", "damage"]);
    for i in 0..n {
        t.push(vec![
            num(x[i][0]),
            num(x[i][1]),
            num(u[i][0]),
            num(u[i][1]),
            num(phi[i]),
        ]);
    }
    ctx.writer.write_csv("nodes.csv", &t)?;
    if scene.outputs.vtk {
        use crate::vtk::Field;
        let bytes = crate::vtk::point_cloud(
            &x[..n],
            vec![
                ("displacement", Field::Vectors(u[..n].to_vec())),
                ("damage", Field::Scalars(phi[..n].to_vec())),
            ],
        )
        .map_err(anyhow::Error::msg)?;
        ctx.writer.write_bytes("nodes.vtu", &bytes)?;
    }
    if !scene.outputs.plots {
        return Ok(());
    }
    let geo = SceneGeometry::of(scene);
    let mut loops = Vec::new();
    if let Some(o) = &geo.outline {
        let mut l: Vec<(f64, f64)> = o.points.iter().map(|p| (p.x, p.y)).collect();
        l.push(l[0]);
        loops.push(l);
    }
    let points: Vec<(f64, f64)> = (0..n).map(|i| (x[i][0], x[i][1])).collect();
    let damage = ScatterField {
        title: format!("{}: damage", scene.name),
        unit: "m".into(),
        value_label: "damage phi (-)".into(),
        points: points.clone(),
        values: phi[..n].to_vec(),
        range: Some((0.0, 1.0)),
        loops: loops.clone(),
        marker_px: 0,
        ..Default::default()
    };
    save_plot(
        &ctx.writer,
        "damage",
        &damage,
        &scene.outputs.formats,
        summary,
    )?;
    let umag = ScatterField {
        title: format!("{}: displacement magnitude", scene.name),
        unit: "m".into(),
        value_label: "|u| (m)".into(),
        points,
        values: (0..n).map(|i| u[i][0].hypot(u[i][1])).collect(),
        range: None,
        loops,
        marker_px: 0,
        ..Default::default()
    };
    save_plot(
        &ctx.writer,
        "displacement",
        &umag,
        &scene.outputs.formats,
        summary,
    )?;
    Ok(())
}

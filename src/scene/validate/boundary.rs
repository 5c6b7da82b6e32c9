//! Rules of names, `boundary` and `load`: unique group names, known groups,
//! finite values, normal/shear only with free components, and something that
//! loads the body.

use super::Checker;
use crate::scene::{BoundaryCondition, Component, Outline, Scene};

/// Checks names, boundary conditions and the load.
pub fn check(c: &mut Checker, scene: &Scene) {
    check_names(c, scene);
    let groups = scene.edge_groups();
    for (i, bc) in scene.boundary.iter().enumerate() {
        check_condition(c, i, bc, &groups);
        if scene.boundary[..i].iter().any(|o| o.on == bc.on) {
            c.fail(
                format!("boundary.{i}.on"),
                format!("{:?}", bc.on),
                "this group already has a condition: merge the two",
            );
        } else if let Some(j) = scene.boundary[..i]
            .iter()
            .position(|o| scene.covers(&o.on, &bc.on) || scene.covers(&bc.on, &o.on))
        {
            c.fail(
                format!("boundary.{i}.on"),
                format!("{:?}", bc.on),
                format!(
                    "overlaps boundary.{j}.on = {:?} (`outline` is every outline edge and patch, a crack's name both its faces): give each piece of the boundary one condition",
                    scene.boundary[j].on
                ),
            );
        }
    }
    check_load(c, scene);
    check_something_loads(c, scene);
}

/// Crack, hole and patch names are unique, do not clash with other groups,
/// and crack names contain no '.' (face groups append `.upper` / `.lower`).
fn check_names(c: &mut Checker, scene: &Scene) {
    let mut seen: Vec<String> = scene.body.outline.edge_names();
    seen.push("outline".into());
    let mut claim = |c: &mut Checker, path: String, name: String| {
        if name.is_empty() {
            c.fail(path, "\"\"", "name must not be empty");
        } else if seen.contains(&name) {
            c.fail(
                path,
                format!("{name:?}"),
                "name already used by another edge group",
            );
        } else {
            seen.push(name);
        }
    };
    for (i, p) in scene.body.patches.iter().enumerate() {
        claim(c, format!("body.patches.{i}.name"), p.name.clone());
    }
    for (i, h) in scene.body.holes.iter().enumerate() {
        claim(c, format!("body.holes.{i}.name"), h.name(i));
    }
    for (i, cr) in scene.cracks.iter().enumerate() {
        if cr.name.contains('.') {
            c.fail(
                format!("cracks.{i}.name"),
                format!("{:?}", cr.name),
                "crack names must not contain '.' (faces are named <crack>.upper/.lower)",
            );
        }
        claim(c, format!("cracks.{i}.name"), cr.name.clone());
    }
}

fn check_condition(c: &mut Checker, i: usize, bc: &BoundaryCondition, groups: &[String]) {
    let path = format!("boundary.{i}");
    if !groups.contains(&bc.on) {
        let known = if groups.is_empty() {
            "none (an infinite plate without cracks or holes)".to_string()
        } else {
            groups.join(", ")
        };
        c.fail(
            format!("{path}.on"),
            format!("{:?}", bc.on),
            format!("unknown edge group; known groups: {known}"),
        );
    }
    for (name, comp) in [("x", bc.x), ("y", bc.y)] {
        if let Component::Displacement(v) | Component::Traction(v) = comp {
            c.finite(&format!("{path}.{name}"), v);
        }
    }
    for (name, v) in [("normal", bc.normal), ("shear", bc.shear)] {
        let Some(v) = v else { continue };
        c.finite(&format!("{path}.{name}"), v);
        if bc.x != Component::Free || bc.y != Component::Free {
            c.fail_at(
                format!("{path}.{name}"),
                "normal/shear tractions replace the x/y components: leave x and y Free",
            );
        }
    }
}

fn check_load(c: &mut Checker, scene: &Scene) {
    c.finite("load.initial", scene.load.initial);
    c.finite("load.step", scene.load.step);
    c.at_least("load.count", scene.load.count, 1, "number of load steps");
}

/// Something must load the body: a non-zero boundary value, remote stress or an
/// explicit-dynamics velocity, and a non-zero load factor in some step.
fn check_something_loads(c: &mut Checker, scene: &Scene) {
    let remote = match scene.body.outline {
        Outline::Infinite { sxx, syy, sxy } => sxx != 0.0 || syy != 0.0 || sxy != 0.0,
        _ => false,
    };
    // An explicit-dynamics impact (`pd.solver.velocities`) sets the body moving.
    let impact = scene.pd.as_ref().is_some_and(|pd| match &pd.solver {
        crate::scene::PdSolver::Explicit(p) => !p.velocities.is_empty(),
        _ => false,
    });
    let loaded = remote || impact || scene.boundary.iter().any(BoundaryCondition::is_loading);
    if !loaded {
        let why = if scene.boundary.is_empty() {
            "nothing to solve: the body has no boundary condition and no remote stress"
        } else {
            "nothing to solve: every boundary value is zero and there is no remote stress"
        };
        c.fail_at("boundary", why);
        return;
    }
    let factors = scene.load.factors();
    if !factors.is_empty() && factors.iter().all(|f| *f == 0.0) {
        c.fail_at("load", "nothing to solve: every load factor is zero");
    }
}

//! What `pdbem run` prints when it is done: the run in one line (mode, size, wall time),
//! then per tip K_I, K_II (Pa m^0.5) and the kink angle with their reference errors, per
//! crack the CMOD, the growth result and the notes. Numbers have units and four
//! significant digits ([`crate::plot::ticks::human`]); positions are rounded to four
//! digits of their size, so a round-off 5e-16 prints as 0. Printed with and without
//! `--quiet` (which silences progress only).

use std::io::Write;

use serde_json::Value;

use crate::plot::ticks::human;
use crate::runner::RunSummary;

/// The lines of a run's printed summary.
pub fn summary_lines(s: &RunSummary) -> Vec<String> {
    let mut out = vec![format!(
        "{}: {}, {}",
        s.scene,
        describe_mode(s),
        seconds(s.wall_time_s)
    )];
    for t in &s.tips {
        // Round-off of a K that is zero by symmetry prints as 0.
        let keq = t.k1.hypot(t.k2);
        let k = |v: f64| human(if v.abs() <= 1e-9 * keq { 0.0 } else { v }, 4);
        out.push(format!(
            "  tip {} at {} m: K_I {} Pa m^0.5, K_II {} Pa m^0.5, kink {} deg{}",
            t.name,
            point(t.position),
            k(t.k1),
            k(t.k2),
            human(t.kink_deg, 4),
            tip_errors(t)
        ));
    }
    for c in &s.cracks {
        if let Some(v) = c.cmod {
            let err = c
                .cmod_err
                .map(|e| format!(" (error {})", percent(e)))
                .unwrap_or_default();
            out.push(format!("  crack {}: CMOD {} m{err}", c.name, human(v, 4)));
        }
    }
    if s.mode == "growth" {
        out.extend(growth_lines(s));
    }
    if s.mode == "pd" {
        out.extend(pd_lines(s));
    }
    out.extend(s.notes.iter().map(|n| format!("  note: {n}")));
    out
}

/// Mode and size: `BEM, 920 elements`, `PD, 1000 nodes, 12548 bonds`, `coupled, 760 BEM
/// elements, 400 PD nodes`, `growth (pd-bem)`.
fn describe_mode(s: &RunSummary) -> String {
    let int = |k: &str| s.extra.get(k).and_then(Value::as_u64);
    let elements = s.elements.map(|e| format!("{e} BEM elements"));
    match s.mode.as_str() {
        "bem" => format!("BEM, {} elements", s.elements.unwrap_or(0)),
        "pd" => match (int("nodes"), int("bonds")) {
            (Some(n), Some(b)) => format!("PD, {n} nodes, {b} bonds"),
            _ => "PD".into(),
        },
        "coupled" => {
            let pd = int("pd_nodes").map(|n| format!(", {n} PD nodes"));
            format!(
                "PD-BEM coupled, {}{}",
                elements.unwrap_or_default(),
                pd.unwrap_or_default()
            )
        }
        "growth" => {
            let mode = s.extra.get("growth_mode").and_then(Value::as_str);
            format!("growth ({})", mode.unwrap_or("?"))
        }
        other => other.to_string(),
    }
}

/// A stand-alone PD run's fracture result: first broken bond, crack initiation (Pa when
/// the scene applies tractions, else the load factor), kink per tip.
fn pd_lines(s: &RunSummary) -> Vec<String> {
    let num = |k: &str| s.extra.get(k).and_then(Value::as_f64);
    let unit = match s.extra.get("load_unit").and_then(Value::as_str) {
        Some("Pa") => " Pa",
        _ => " (load factor)",
    };
    let mut out = Vec::new();
    if let Some(f) = num("first_break_load") {
        out.push(format!("  first bonds broke at load {}{unit}", human(f, 4)));
    }
    if let Some(f) = num("initiation_load") {
        let unstable = s.extra.get("unstable_growth").and_then(Value::as_bool);
        let how = if unstable == Some(true) {
            " (equilibrium lost: unstable growth)"
        } else {
            ""
        };
        out.push(format!(
            "  crack initiation at load {}{unit}{how}",
            human(f, 4)
        ));
    } else if s.extra.contains_key("initiation_load") {
        out.push("  no crack initiation within the load ramp".into());
    }
    if let Some(Value::Array(k)) = s.extra.get("kink_deg_per_tip") {
        let list: Vec<String> = k
            .iter()
            .map(|v| v.as_f64().map_or("-".into(), |d| human(d, 3)))
            .collect();
        if !list.is_empty() {
            out.push(format!("  kink per tip: {} deg", list.join(", ")));
        }
    }
    out
}

fn seconds(t: f64) -> String {
    format!("{} s", human(t, 3))
}

fn percent(e: f64) -> String {
    format!("{:+.2} %", 100.0 * e)
}

/// ` (reference: K_I +4.74 %, K_II +2.39 %, kink +0.47 deg)`, or nothing.
fn tip_errors(t: &crate::runner::TipResult) -> String {
    let mut parts = Vec::new();
    if let Some(e) = t.k1_err {
        parts.push(format!("K_I {}", percent(e)));
    }
    if let Some(e) = t.k2_err {
        parts.push(format!("K_II {}", percent(e)));
    }
    if let Some(e) = t.kink_err_deg {
        parts.push(format!("kink {:+.2} deg", e));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" (against the reference: {})", parts.join(", "))
    }
}

/// `(x, y)` rounded to four significant digits of the point's size.
pub fn point(p: [f64; 2]) -> String {
    let size = p[0].abs().max(p[1].abs());
    if !(size > 0.0 && size.is_finite()) {
        return format!("({}, {})", p[0], p[1]);
    }
    let d = (3 - size.log10().floor() as i32).clamp(0, 15) as usize;
    let f = |v: f64| {
        let t = format!("{v:.d$}");
        let t = if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        };
        if t == "-0" {
            "0".to_string()
        } else {
            t
        }
    };
    format!("({}, {})", f(p[0]), f(p[1]))
}

/// The growth fields: steps, initiation and failure loads, relocations, where tips ended.
fn growth_lines(s: &RunSummary) -> Vec<String> {
    let g = |k: &str| s.extra.get(k).cloned().unwrap_or(Value::Null);
    let load = |v: Value| v.as_f64().map_or("none".into(), |x| human(x, 4));
    let failed = g("failure").as_bool() == Some(true);
    let failure = if failed {
        format!("failure at load factor {}", load(g("failure_load")))
    } else {
        "no failure".into()
    };
    let mut out = vec![format!(
        "  {} load steps, initiation at load factor {}, {failure}, {} window relocations",
        g("steps"),
        load(g("initiation_load")),
        g("relocations")
    )];
    for t in g("tips_final").as_array().into_iter().flatten() {
        let pos = t["position"]
            .as_array()
            .and_then(|a| Some([a.first()?.as_f64()?, a.get(1)?.as_f64()?]))
            .map_or("?".into(), point);
        // A tip that did not end at the outline, a hole or another crack is inside the
        // body: arrested or growing at the last load, or where it was tracked when the body
        // failed by another way (a PD ligament that gave way in its window, another tip).
        let inside = if failed {
            "inside the body when it failed"
        } else {
            "inside the body"
        };
        let ended = t["ended"]
            .as_str()
            .map_or(inside.to_string(), |w| format!("ended: {w}"));
        out.push(format!(
            "  tip {}: at {pos} m, grew {} m, {ended}",
            t["name"].as_str().unwrap_or("?"),
            t["extension"].as_f64().map_or("?".into(), |x| human(x, 4))
        ));
    }
    out
}

/// Writes `text` to standard output. A reader that closed the pipe (`pdbem ... | head`)
/// ends the output quietly: `print!` would panic there. Other write errors go to stderr.
pub fn out(text: &str) {
    let mut o = std::io::stdout().lock();
    if let Err(e) = o.write_all(text.as_bytes()).and_then(|()| o.flush()) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("error: cannot write to standard output: {e}");
        }
    }
}

/// [`out`] with a line end, for `println!`-style output.
#[macro_export]
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::console::out(&format!("{}\n", format_args!($($arg)*)))
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn growth_summary_reads_like_a_report() {
        let mut s = RunSummary {
            scene: "g".into(),
            mode: "growth".into(),
            wall_time_s: 11.029,
            ..Default::default()
        };
        for (k, v) in [
            ("growth_mode", json!("pd-bem")),
            ("steps", json!(2)),
            ("initiation_load", json!(3.3499999999999996)),
            ("failure", json!(true)),
            ("failure_load", json!(3.3499999999999996)),
            ("relocations", json!(14)),
            (
                "tips_final",
                json!([{"name": "crack.end", "position": [10.02888908982704, 4.996003610813204e-16],
                        "extension": 8.002635590020764, "ended": "outline"}]),
            ),
        ] {
            s.extra.insert(k.into(), v);
        }
        let text = summary_lines(&s).join("\n");
        assert!(text.contains("g: growth (pd-bem), 11 s"), "{text}");
        assert!(text.contains("initiation at load factor 3.35"), "{text}");
        assert!(
            text.contains("at (10.03, 0) m, grew 8.003 m, ended: outline"),
            "{text}"
        );
        assert!(!text.contains("99999") && !text.contains("e-16"), "{text}");
        // A tip tracked inside the body when it failed another way (its PD ligament gave
        // way in the window) was reported as "still growing".
        s.extra.insert(
            "tips_final".into(),
            json!([{"name": "crack.end", "position": [10.05, 0.95], "extension": 7.055, "ended": null}]),
        );
        let text = summary_lines(&s).join("\n");
        assert!(
            text.contains("grew 7.055 m, inside the body when it failed"),
            "{text}"
        );
        s.extra.insert("failure".into(), json!(false));
        let text = summary_lines(&s).join("\n");
        assert!(
            text.contains("grew 7.055 m, inside the body\n") || text.ends_with("inside the body"),
            "{text}"
        );
    }

    #[test]
    fn tips_carry_units_and_pd_runs_their_size() {
        let mut s = RunSummary {
            scene: "p".into(),
            mode: "pd".into(),
            wall_time_s: 0.075,
            ..Default::default()
        };
        s.extra.insert("nodes".into(), json!(1000));
        s.extra.insert("bonds".into(), json!(12548));
        s.tips.push(crate::runner::TipResult {
            name: "c.end".into(),
            position: [0.5433012701892219, 0.275],
            k1: 31134907.487,
            k2: 17572638.95,
            kink_deg: -42.754802,
            k1_err: Some(0.04743),
            ..Default::default()
        });
        let text = summary_lines(&s).join("\n");
        assert!(
            text.starts_with("p: PD, 1000 nodes, 12548 bonds, 0.075 s"),
            "{text}"
        );
        assert!(
            text.contains("tip c.end at (0.5433, 0.275) m: K_I 3.113e7 Pa m^0.5, K_II 1.757e7 Pa m^0.5, kink -42.75 deg (against the reference: K_I +4.74 %)"),
            "{text}"
        );
        assert!(!text.contains(" - elements"));
        s.tips.clear();
        s.extra.insert("first_break_load".into(), json!(13e6));
        s.extra.insert("initiation_load".into(), json!(15e6));
        s.extra.insert("load_unit".into(), json!("Pa"));
        s.extra
            .insert("kink_deg_per_tip".into(), json!([-46.27, null]));
        let text = summary_lines(&s).join("\n");
        assert!(
            text.contains("  first bonds broke at load 1.3e7 Pa"),
            "{text}"
        );
        assert!(
            text.contains("  crack initiation at load 1.5e7 Pa"),
            "{text}"
        );
        assert!(text.contains("  kink per tip: -46.3, - deg"), "{text}");
    }
}

//! The one `validate()` of a scene: every rule, each reported with the dotted
//! field path, the value and the reason (STYLE.md: "one `validate()` whose
//! messages state the violated constraint").
//!
//! Rules by section: `material`, `body` (outline, holes, patches),
//! `cracks`, `boundary` (conditions, load, "nothing to solve"),
//! `sections` (bem, reference, outputs), `pd` (pd, coupling, growth), `face_loads`
//! (no crack-face conditions where PD models the crack), `strain` (the
//! loads' nominal strain, a PD body's distance from the origin), `limits` (upper bounds
//! of counts and sampling coordinates, safe output names).

mod body;
mod boundary;
mod cracks;
mod face_loads;
mod growth;
pub mod limits;
mod material;
mod pd;
mod pd_refinement;
mod pd_zones;
mod sections;
pub mod strain;
mod window_refine;

use super::error::Issue;
use super::Scene;

/// Collects issues while walking the scene.
#[derive(Debug, Default)]
pub struct Checker {
    /// Issues found so far.
    pub issues: Vec<Issue>,
}

impl Checker {
    /// Records an issue with a value.
    pub fn fail(
        &mut self,
        path: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) {
        self.issues.push(Issue {
            path: path.into(),
            value: Some(shown(value.to_string())),
            reason: reason.into(),
        });
    }

    /// Records an issue without a value.
    pub fn fail_at(&mut self, path: impl Into<String>, reason: impl Into<String>) {
        self.issues.push(Issue {
            path: path.into(),
            value: None,
            reason: reason.into(),
        });
    }

    /// Requires a finite number; returns whether it was.
    pub fn finite(&mut self, path: &str, v: f64) -> bool {
        if v.is_finite() {
            true
        } else {
            self.fail(path, v, "must be a finite number");
            false
        }
    }

    /// Requires a finite number > 0 (`what` names the quantity in the message).
    pub fn positive(&mut self, path: &str, v: f64, what: &str) -> bool {
        if !self.finite(path, v) {
            return false;
        }
        if v <= 0.0 {
            self.fail(path, v, format!("{what} must be > 0"));
            return false;
        }
        true
    }

    /// Requires an integer >= `min`.
    pub fn at_least(&mut self, path: &str, v: usize, min: usize, what: &str) -> bool {
        if v < min {
            self.fail(path, v, format!("{what} must be at least {min}"));
            return false;
        }
        true
    }
}

/// Checks every rule of a scene and returns all violations (empty = valid).
pub fn check(scene: &Scene) -> Vec<Issue> {
    let mut c = Checker::default();
    check_name(&mut c, &scene.name);
    material::check(&mut c, scene);
    let body_ok = body::check(&mut c, scene);
    if body_ok {
        strain::check_feature_origin(&mut c, scene);
        cracks::check(&mut c, scene);
    }
    boundary::check(&mut c, scene);
    if body_ok {
        strain::check(&mut c, scene);
        strain::check_origin(&mut c, scene);
    }
    sections::check(&mut c, scene, body_ok);
    pd::check(&mut c, scene);
    face_loads::check(&mut c, scene);
    growth::check(&mut c, scene);
    limits::check(&mut c, scene);
    c.issues
}

/// The name must be usable as a folder name.
fn check_name(c: &mut Checker, name: &str) {
    let ok = safe_file_name(name);
    if !ok {
        c.fail(
            "name",
            format!("{name:?}"),
            "use letters, digits, '_', '-', '.' only (it names the run folder)",
        );
    }
}

/// Quotes a point for messages.
pub fn fmt_pt(p: &crate::geometry::P2) -> String {
    format!("({}, {})", p.x, p.y)
}

/// A name usable as (part of) a file or folder name: letters, digits, '_', '-' and '.',
/// not empty, not starting with '.'.
pub(super) fn safe_file_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|ch| ch.is_ascii_alphanumeric() || matches!(ch, '_' | '-' | '.'))
        && !name.starts_with('.')
}

/// A value as an issue shows it: a number whose plain decimal form runs long (1e-300
/// prints 300 zeros) in exponent form, anything else as it is. Integers keep their
/// digits up to the 20 of `u64::MAX`: a fraction is shortened past 16 characters, a
/// digit string past 21.
fn shown(value: String) -> String {
    let long = if value.contains('.') { 16 } else { 21 };
    match value.parse::<f64>() {
        Ok(v) if value.len() > long && v.is_finite() => format!("{v:e}"),
        _ => value,
    }
}

#[cfg(test)]
mod tests {
    use super::shown;

    #[test]
    fn long_numbers_show_in_exponent_form_and_integers_keep_their_digits() {
        assert_eq!(shown(1e-300f64.to_string()), "1e-300");
        assert_eq!(shown(1e300f64.to_string()), "1e300");
        assert_eq!(shown(0.1f64.to_string()), "0.1");
        assert_eq!(shown(u64::MAX.to_string()), "18446744073709551615");
        assert_eq!(shown("top".into()), "top");
    }
}

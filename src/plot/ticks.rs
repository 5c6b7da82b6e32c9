//! Tick positions and tick labels of every plot axis and colour bar.
//!
//! - [`linear_ticks`]: 1-2-5 steps, at most a given number of ticks, each tick an exact
//!   integer multiple of the step (no accumulated `0.30000000000000004`);
//! - [`log_ticks`]: powers of ten, with 2 and 5 (or 1..9) between them when the axis
//!   spans few decades, and linear ticks inside one decade, so a log axis always has at
//!   least three labelled ticks;
//! - [`Ticks`]: positions plus labels. A linear axis is labelled in plain decimals when
//!   its largest tick lies in [1e-3, 1e5), else in scientific notation with one exponent
//!   for the whole axis (`0.5e7, 1.0e7, 1.5e7`); the digits after the point are exactly
//!   those the step needs. Log-axis ticks are labelled one by one with at most three
//!   significant digits (`0.3`, `20`, `5e-6`). Zero is `0`, never `-0.0`.
//!
//! Units belong in the axis description (`K_I (Pa m^0.5)`), not in the labels.
//! [`Ticked`] hands the positions to plotters.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};

/// A plotters axis (linear or log) whose ticks are given: the mesh draws exactly these,
/// so plots do not depend on the library's own tick search.
#[derive(Debug, Clone)]
pub struct Ticked<R> {
    inner: R,
    ticks: Vec<f64>,
}

impl<R: Ranged<ValueType = f64>> Ticked<R> {
    /// Axis `inner` with the tick positions `ticks`.
    pub fn new(inner: impl Into<R>, ticks: &Ticks) -> Ticked<R> {
        Ticked {
            inner: inner.into(),
            ticks: ticks.values.clone(),
        }
    }
}

impl<R: Ranged<ValueType = f64>> Ranged for Ticked<R> {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }

    fn axis_pixel_range(&self, limit: (i32, i32)) -> std::ops::Range<i32> {
        self.inner.axis_pixel_range(limit)
    }
}

/// Tick positions with their labels.
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    /// Tick positions, increasing.
    pub values: Vec<f64>,
    /// One label per tick.
    pub labels: Vec<String>,
}

impl Ticks {
    /// Ticks of a linear axis over `[lo, hi]`, at most `max` of them (at least 2).
    pub fn linear(lo: f64, hi: f64, max: usize) -> Ticks {
        let (values, step) = linear_ticks(lo, hi, max);
        let top = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let labels = values.iter().map(|v| linear_label(*v, step, top)).collect();
        Ticks { values, labels }
    }

    /// No ticks (figures drawn without text).
    pub fn none() -> Ticks {
        Ticks {
            values: Vec::new(),
            labels: Vec::new(),
        }
    }

    /// Ticks of a linear axis with labels, or none without `labels`.
    pub fn linear_if(labels: bool, lo: f64, hi: f64, max: usize) -> Ticks {
        if labels {
            Ticks::linear(lo, hi, max)
        } else {
            Ticks::none()
        }
    }

    /// Ticks of a log axis over `[lo, hi]` (both > 0).
    pub fn log(lo: f64, hi: f64) -> Ticks {
        let values = log_ticks(lo, hi);
        let labels = values.iter().map(|v| log_label(*v)).collect();
        Ticks { values, labels }
    }

    /// The label of the tick nearest to `v` (for plotters' label callbacks).
    pub fn label_of(&self, v: f64) -> String {
        let nearest = self.values.iter().enumerate().min_by(|a, b| {
            (a.1 - v)
                .abs()
                .partial_cmp(&(b.1 - v).abs())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        match nearest {
            Some((i, _)) => self.labels[i].clone(),
            None => String::new(),
        }
    }
}

/// The 1-2-5 step that gives at most `max` intervals over `span`.
fn nice_step(span: f64, max: usize) -> f64 {
    let raw = span / max.max(1) as f64;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= raw * (1.0 - 1e-12))
        .unwrap_or(10.0 * p)
}

/// Ticks of `[lo, hi]` at a 1-2-5 step, at most `max` of them, and the step. Degenerate
/// or non-finite ranges give the ends alone.
pub fn linear_ticks(lo: f64, hi: f64, max: usize) -> (Vec<f64>, f64) {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        let v: Vec<f64> = [lo, hi].into_iter().filter(|v| v.is_finite()).collect();
        return (v, 0.0);
    }
    let max = max.max(2);
    let mut step = nice_step(span, max - 1);
    loop {
        let (k0, k1) = ((lo / step).ceil() as i64, (hi / step).floor() as i64);
        if (k1 - k0 + 1) as usize <= max {
            // Integer multiples, rounded to the step's last digit.
            let digits = (-(step.log10().floor()) as i32 + 1).clamp(0, 300);
            let values = (k0..=k1)
                .map(|k| round_to(k as f64 * step, digits))
                .collect();
            return (values, step);
        }
        step = nice_step(step * 1.5, 1);
    }
}

/// `v` rounded to `digits` decimals (exact enough for labels; beyond f64 range no-op).
fn round_to(v: f64, digits: i32) -> f64 {
    if digits > 15 {
        let p = 10f64.powi(digits.min(300));
        let r = (v * p).round() / p;
        return if r.is_finite() { r } else { v };
    }
    let p = 10f64.powi(digits);
    (v * p).round() / p
}

/// Ticks of a log axis over `[lo, hi]`: powers of ten (every n-th beyond 10 decades),
/// plus 2 and 5 times them below 3 decades, 1..9 times them within about one decade,
/// and linear ticks when that still gives fewer than 3.
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    if !(lo > 0.0 && hi.is_finite()) {
        return linear_ticks(lo, hi, 6).0;
    }
    let (e0, e1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let decades = (hi / lo).log10();
    let mults: &[f64] = if decades > 3.0 {
        &[1.0]
    } else if decades > 1.2 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    };
    let every = ((e1 - e0) as usize).div_ceil(10).max(1) as i32;
    let mut out = Vec::new();
    for e in e0..=e1 {
        if mults.len() == 1 && e.rem_euclid(every) != 0 {
            continue;
        }
        for m in mults {
            let v = parse_sci(*m, e);
            if v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12) {
                out.push(v);
            }
        }
    }
    if out.len() < 3 {
        return linear_ticks(lo, hi, 6).0;
    }
    out
}

/// `m * 10^e` as the f64 nearest to its decimal text (`3e-1` is 0.3, not 0.30000000000000004).
fn parse_sci(m: f64, e: i32) -> f64 {
    format!("{m}e{e}").parse().unwrap_or(m * 10f64.powi(e))
}

/// Label of tick `v` on a linear axis of step `step` whose largest |tick| is `top`.
pub fn linear_label(v: f64, step: f64, top: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    if v == 0.0 || (step > 0.0 && v.abs() < 1e-6 * step) {
        return "0".into();
    }
    let s = if step > 0.0 && step.is_finite() {
        step.log10().floor() as i32
    } else {
        v.abs().log10().floor() as i32 - 3
    };
    let top = if top > 0.0 && top.is_finite() {
        top
    } else {
        v.abs()
    };
    let e = top.log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (-s).clamp(0, 12) as usize;
        return clean_zero(format!("{v:.decimals$}"));
    }
    let decimals = (e - s).clamp(0, 6) as usize;
    let m = v / 10f64.powi(e);
    format!("{}e{e}", clean_zero(format!("{m:.decimals$}")))
}

/// Label of a log-axis tick: at most three significant digits.
pub fn log_label(v: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    if v == 0.0 {
        return "0".into();
    }
    let e = v.abs().log10().floor() as i32;
    if (-3..4).contains(&e) {
        let decimals = (2 - e).clamp(0, 5) as usize;
        return trim(format!("{v:.decimals$}"));
    }
    let mut m = v / 10f64.powi(e);
    let mut e = e;
    if trim(format!("{m:.2}")).trim_start_matches('-') == "10" {
        m /= 10.0;
        e += 1;
    }
    format!("{}e{e}", trim(format!("{m:.2}")))
}

/// Removes trailing zeros after a decimal point (and the point itself).
fn trim(s: String) -> String {
    if !s.contains('.') {
        return clean_zero(s);
    }
    clean_zero(s.trim_end_matches('0').trim_end_matches('.').to_string())
}

/// `-0`, `-0.00` become `0`, `0.00`.
fn clean_zero(s: String) -> String {
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// A number for text meant for people (console summaries, legends): `sig` significant
/// digits, plain decimals for magnitudes in [1e-3, 1e5), else scientific; trailing zeros
/// dropped. `3.3499999999999996` with 4 digits is `3.35`, `4.996e-16` is `5e-16`.
pub fn human(v: f64, sig: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let sig = sig.clamp(1, 15);
    let e = v.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (sig as i32 - 1 - e).clamp(0, 15) as usize;
        return trim(format!("{v:.decimals$}"));
    }
    let s = format!("{v:.prec$e}", prec = sig - 1);
    match s.split_once('e') {
        Some((m, x)) => format!("{}e{x}", trim(m.to_string())),
        None => s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scales() -> Vec<f64> {
        (-12..=12).map(|e| 10f64.powi(e)).collect()
    }

    /// Every label reads back as its tick, labels differ, and none is long.
    fn assert_readable(t: &Ticks, what: &str) {
        assert!(t.values.len() >= 3, "{what}: {t:?}");
        for (v, l) in t.values.iter().zip(&t.labels) {
            let back: f64 = l.parse().unwrap_or_else(|_| panic!("{what}: label {l}"));
            let tol = 1e-6 * v.abs().max(1e-300) + 1e-9 * (t.values[1] - t.values[0]).abs();
            assert!((back - v).abs() <= tol, "{what}: {l} for {v}");
            assert!(l.len() <= 9, "{what}: long label {l}");
            assert!(!l.starts_with("-0") || l.len() > 2, "{what}: {l}");
        }
        let mut u = t.labels.clone();
        u.dedup();
        assert_eq!(
            u.len(),
            t.labels.len(),
            "{what}: repeated labels {:?}",
            t.labels
        );
    }

    #[test]
    fn linear_axes_from_1e_minus_12_to_1e12_positive_negative_and_mixed() {
        for s in scales() {
            for (lo, hi) in [
                (0.0, 4.0 * s),
                (-3.0 * s, -0.5 * s),
                (-2.0 * s, 7.0 * s),
                (1.0 * s, 1.3 * s),
                (0.3 * s, 0.9 * s),
            ] {
                let t = Ticks::linear(lo, hi, 8);
                assert!(t.values.len() <= 8, "{lo}..{hi}: {t:?}");
                assert!(t
                    .values
                    .iter()
                    .all(|v| *v >= lo - 1e-9 * s && *v <= hi + 1e-9 * s));
                assert_readable(&t, &format!("linear {lo:e}..{hi:e}"));
            }
        }
    }

    #[test]
    fn log_axes_from_1e_minus_12_to_1e12() {
        for s in scales() {
            for (lo, hi) in [
                (s, 1e3 * s),
                (0.09 * s, 0.31 * s),
                (0.2 * s, 0.9 * s),
                (s, 1e24 * s),
            ] {
                let t = Ticks::log(lo, hi);
                assert!(t.values.len() <= 30, "{lo}..{hi}: {t:?}");
                assert_readable(&t, &format!("log {lo:e}..{hi:e}"));
            }
        }
    }

    #[test]
    fn the_labels_the_issue_complained_about() {
        // An element-size sweep's log axis: 0.3, not 0.30000000000000004.
        let t = Ticks::log(0.05, 0.5);
        assert!(t.labels.contains(&"0.3".to_string()), "{:?}", t.labels);
        assert!(t.labels.contains(&"0.09".to_string()), "{:?}", t.labels);
        // An absolute error of 5e-6 is not 0.0.
        let t = Ticks::linear(0.0, 1.2e-5, 8);
        assert!(t
            .labels
            .iter()
            .any(|l| l == "0.4e-5" || l == "4e-6" || l == "0.6e-5"));
        assert!(t.labels.iter().filter(|l| *l == "0").count() == 1);
        // Displacements of a steel plate and von Mises stresses.
        let t = Ticks::linear(0.0, 3.2e-4, 8);
        assert!(
            t.labels.iter().all(|l| l == "0" || l.contains("e-4")),
            "{:?}",
            t.labels
        );
        let t = Ticks::linear(0.0, 1.8e6, 8);
        assert!(t.labels.contains(&"1.5e6".to_string()), "{:?}", t.labels);
        assert_eq!(
            Ticks::linear(-1.0, 1.0, 5).labels,
            ["-1.0", "-0.5", "0", "0.5", "1.0"]
        );
    }

    #[test]
    fn human_numbers() {
        assert_eq!(human(3.3499999999999996, 4), "3.35");
        assert_eq!(human(10.02888908982704, 4), "10.03");
        assert_eq!(human(4.996003610813204e-16, 3), "5e-16");
        assert_eq!(human(-2.5e7, 3), "-2.5e7");
        assert_eq!(human(0.0, 3), "0");
        assert_eq!(human(1234.6, 4), "1235");
        assert_eq!(human(0.00123456, 3), "0.00123");
    }
}

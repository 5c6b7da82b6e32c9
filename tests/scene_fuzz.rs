//! Scene fuzzing (issue 17): deterministic mutations of every case file in `cases/`
//! through the validation entry point ([`Scene::from_ron_str`]), the summary `pdbem check`
//! prints and the size estimate ([`pdbem::setup::estimate`]; never a solve).
//!
//! Mutations: every line deleted or duplicated; numbers swapped for 0, -0, +-1e308,
//! 5e-324, NaN, inf, 2^32, 2^64 - 1; enum variants swapped or misspelt; truncation at
//! several points; whole sections with extreme values added; random bytes (a fixed-seed xorshift); unicode. Asserts: no panic, and
//! every rejection names a position (line:col) or a field path.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use pdbem::scene::{Scene, SceneError};

const FILE: &str = "fuzz.ron";
const NUMBERS: [&str; 11] = [
    "0",
    "-0",
    "1e308",
    "-1e308",
    "5e-324",
    "NaN",
    "inf",
    "-inf",
    "4294967296",
    "18446744073709551615",
    "-1",
];
/// Whole sections with extreme values, added at the top of a scene (a duplicate of a
/// section the case has is a syntax error with a position).
const SECTIONS: [&str; 10] = [
    "load: (count: 18446744073709551615)",
    "load: (initial: 1e308, step: 1e308, count: 100000)",
    "bem: (element_size: 5e-324)",
    "bem: (tip_refinement: (element_size: 5e-324, radius: 1e308), elements_per_circle: 100000)",
    "pd: (nx: 100000, horizon_factor: 6)",
    "pd: (dx: 5e-324)",
    "coupling: (side: 1e308, n: 5000, psi: 5e-324)",
    "outputs: (grids: [(name: \"g\", from: (-1e12, -1e12), to: (1e12, 1e12), nx: 1000, ny: 1000)])",
    "outputs: (lines: [(name: \"\", from: (0, 0), to: (0, 0), n: 0)])",
    "growth: (da: 5e-324, elements_per_extension: 10000, snapshot_steps: [18446744073709551615])",
];
const UNICODE: [&str; 6] = [
    "\u{e9}",
    "\u{202e}",
    "\u{1f600}",
    "\u{0}",
    "\u{feff}",
    "\u{ffff}",
];

/// Fixed-seed xorshift64.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Byte ranges of the number literals of `text` (outside comments and strings).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += 1;
                }
                i += 1;
            }
            c if c.is_ascii_digit()
                || (c == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)) =>
            {
                let prev_ident = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
                let start = i;
                i += 1;
                while i < b.len()
                    && (b[i].is_ascii_digit()
                        || matches!(b[i], b'.' | b'e' | b'E' | b'_')
                        || (matches!(b[i], b'-' | b'+') && matches!(b[i - 1], b'e' | b'E')))
                {
                    i += 1;
                }
                if !prev_ident {
                    out.push((start, i));
                }
            }
            _ => i += 1,
        }
    }
    out
}

/// Byte ranges of identifiers starting with an upper-case letter (enum variants).
fn variants(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += 1;
            }
            i += 1;
            continue;
        }
        if b[i].is_ascii_alphabetic()
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'))
        {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            if b[start].is_ascii_uppercase() && text[start..i] != *"E" {
                out.push((start, i));
            }
            continue;
        }
        i += 1;
    }
    out
}

fn splice(text: &str, (a, b): (usize, usize), with: &str) -> String {
    format!("{}{with}{}", &text[..a], &text[b..])
}

/// Char boundary at or below `i`.
fn boundary(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// The mutations of one case text.
fn mutations(text: &str, all_variants: &[String], rng: &mut XorShift) -> Vec<String> {
    let mut out = Vec::new();
    let lines: Vec<&str> = text.lines().collect();
    for i in 0..lines.len() {
        let mut del = lines.clone();
        del.remove(i);
        out.push(del.join("\n"));
        let mut dup = lines.clone();
        dup.insert(i, lines[i]);
        out.push(dup.join("\n"));
    }
    for (k, r) in numbers(text).into_iter().enumerate() {
        // Every number gets three of the values, in turn all of them.
        for j in 0..3 {
            out.push(splice(text, r, NUMBERS[(3 * k + j) % NUMBERS.len()]));
        }
    }
    for r in variants(text) {
        let v = &all_variants[rng.below(all_variants.len())];
        out.push(splice(text, r, v));
        out.push(splice(text, r, &format!("{}x", &text[r.0..r.1])));
        out.push(splice(text, r, &text[r.0..r.1].to_ascii_lowercase()));
    }
    if let Some(open) = text.find("\n(").map(|i| i + 2) {
        for sec in SECTIONS {
            out.push(format!("{}{sec},{}", &text[..open], &text[open..]));
        }
    }
    for k in 1..10 {
        out.push(text[..boundary(text, text.len() * k / 10)].to_string());
    }
    for _ in 0..20 {
        let mut bytes = text.as_bytes().to_vec();
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(bytes.len());
            bytes[at] = (rng.next() & 0xff) as u8;
        }
        out.push(String::from_utf8_lossy(&bytes).into_owned());
    }
    for u in UNICODE {
        let at = boundary(text, rng.below(text.len()));
        out.push(format!("{}{u}{}", &text[..at], &text[at..]));
        // Inside a string (names).
        if let Some(q) = text.find("name: \"") {
            let at = q + 7;
            out.push(format!("{}{u}{}", &text[..at], &text[at..]));
        }
    }
    out
}

/// Why a rejection is unnamed, if it is.
fn unnamed(e: &SceneError) -> Option<String> {
    match e {
        SceneError::Syntax { line, column, .. } if *line >= 1 && *column >= 1 => None,
        SceneError::Invalid { issues, .. }
            if !issues.is_empty() && issues.iter().all(|i| !i.path.is_empty()) =>
        {
            None
        }
        other => Some(format!(
            "rejection without a position or field path: {other}"
        )),
    }
}

/// Parse, validate, describe and estimate one text; `Err` says what went wrong.
fn exercise(text: &str, accepted: &mut usize) -> Result<(), String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| match Scene::from_ron_str(text, FILE) {
        Ok(scene) => {
            *accepted += 1;
            let _ = pdbem::cli::describe(&scene);
            let e = match pdbem::setup::estimate::of(&scene) {
                Ok(e) => e,
                // A scene-level refusal (a feature too small to mesh) names its crack.
                Err(err) => {
                    let msg = format!("{err:#}");
                    return (!msg.contains("cracks.")).then(|| format!("estimate: {msg}"));
                }
            };
            let _ = e.within(&scene, 1 << 30);
            if e.bytes().is_nan() {
                return Some("the estimate is NaN".to_string());
            }
            None
        }
        Err(e) => unnamed(&e),
    }));
    match outcome {
        Ok(None) => Ok(()),
        Ok(Some(why)) => Err(why),
        Err(p) => Err(format!(
            "panic: {}",
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        )),
    }
}

#[test]
fn mutated_cases_never_panic_and_every_rejection_is_named() {
    let mut cases: Vec<_> = std::fs::read_dir("cases")
        .expect("cases/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    cases.sort();
    assert!(cases.len() >= 10, "found only {} cases", cases.len());
    let texts: Vec<String> = cases
        .iter()
        .map(|p| std::fs::read_to_string(p).expect("readable case"))
        .collect();
    let mut all_variants: Vec<String> = texts
        .iter()
        .flat_map(|t| variants(t).into_iter().map(|r| t[r.0..r.1].to_string()))
        .collect();
    all_variants.sort();
    all_variants.dedup();
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let start = Instant::now();
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let (mut count, mut accepted, mut failures) = (0usize, 0usize, Vec::new());
    for (path, text) in cases.iter().zip(&texts) {
        for m in mutations(text, &all_variants, &mut rng) {
            count += 1;
            if let Err(why) = exercise(&m, &mut accepted) {
                failures.push(format!(
                    "{}: {why}\n--- mutated text ---\n{m}\n",
                    path.display()
                ));
            }
        }
    }
    std::panic::set_hook(hook);
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "scene fuzz: {count} mutations ({accepted} valid) in {secs:.2} s, {} failures",
        failures.len()
    );
    assert!(count >= 2000, "only {count} mutations");
    assert!(
        accepted >= count / 10,
        "only {accepted} of {count} mutations are valid scenes"
    );
    assert!(
        failures.is_empty(),
        "{} of {count} mutations failed; the first ones:\n{}",
        failures.len(),
        failures
            .iter()
            .take(5)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

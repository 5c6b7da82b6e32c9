//! `docs/scene.md` documents every field and variant the scene parser accepts, and the
//! links of README.md and docs/ point at files of the repository.
//!
//! The list of fields comes from serde itself ([`pdbem::scene::schema::scene_schema`]):
//! each struct or enum `T` needs a heading in docs/scene.md that names it in backticks
//! (`` ### `Material` ``), and its section (up to the next heading of the same or a
//! higher level) names every field or variant in backticks.

use std::path::{Path, PathBuf};

use pdbem::scene::schema::scene_schema;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The section of `doc` under the heading that names `` `name` ``.
fn section<'a>(doc: &'a str, name: &str) -> Option<&'a str> {
    let tag = format!("`{name}`");
    let lines: Vec<(usize, &str)> = doc
        .lines()
        .scan(0usize, |pos, l| {
            let start = *pos;
            *pos += l.len() + 1;
            Some((start, l))
        })
        .collect();
    let level = |l: &str| l.chars().take_while(|c| *c == '#').count();
    let (k, &(start, head)) = lines
        .iter()
        .enumerate()
        .find(|(_, (_, l))| l.starts_with('#') && l.contains(&tag))?;
    let end = lines[k + 1..]
        .iter()
        .find(|(_, l)| l.starts_with('#') && level(l) <= level(head))
        .map_or(doc.len(), |(p, _)| *p);
    Some(&doc[start..end])
}

#[test]
fn every_scene_field_and_variant_is_documented() {
    let doc = std::fs::read_to_string(repo().join("docs/scene.md")).expect("docs/scene.md");
    let mut missing = Vec::new();
    let schema = scene_schema();
    assert!(schema.len() > 30, "the tracer found only {schema:?}");
    for t in &schema {
        let Some(text) = section(&doc, &t.name) else {
            missing.push(format!("no heading naming `{}`", t.name));
            continue;
        };
        for m in &t.members {
            if !text.contains(&format!("`{m}`")) {
                let what = if t.is_enum { "variant" } else { "field" };
                missing.push(format!("{what} `{m}` of `{}`", t.name));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "docs/scene.md misses:\n{}",
        missing.join("\n")
    );
}

/// Relative markdown links `](path)` and backticked `../`-paths of a file.
fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for part in text.split("](").skip(1) {
        if let Some(end) = part.find(')') {
            let target = &part[..end];
            if !target.starts_with("http") && !target.starts_with('#') {
                out.push(target.split('#').next().unwrap_or("").to_string());
            }
        }
    }
    out
}

#[test]
fn readme_and_docs_link_only_to_files_in_the_repository() {
    let mut bad = Vec::new();
    let mut files = vec![repo().join("README.md")];
    for e in std::fs::read_dir(repo().join("docs")).expect("docs/") {
        files.push(e.expect("entry").path());
    }
    for f in files {
        let text = std::fs::read_to_string(&f).expect("readable");
        let dir = f.parent().unwrap_or(Path::new("."));
        for l in links(&text) {
            if !dir.join(&l).exists() {
                bad.push(format!("{}: link to {l}", f.display()));
            }
        }
        if text.contains("../shared/") {
            bad.push(format!("{}: points outside the repository", f.display()));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn plot_legends_name_no_file_outside_the_repository() {
    // Legends and summaries once cited REFERENCES.md, which is not part of a clone.
    let report = std::fs::read_to_string(repo().join("src/runner/report.rs")).expect("report.rs");
    for line in report.lines().filter(|l| !l.trim_start().starts_with("//")) {
        assert!(!line.contains("REFERENCES.md"), "{line}");
    }
}

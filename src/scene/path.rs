//! Dotted paths into a scene, for `pdbem sweep --vary FIELD=v1,v2,...`.
//!
//! The scene is serialised to JSON, the value at the path replaced, the JSON
//! deserialised and the scene validated again. Path rules:
//! - segments are object keys or array indices: `cracks.0.length`;
//! - enum variants are transparent: `body.outline.width` reaches the
//!   `width` of a `Rectangle`, `pd.solver.tolerance` that of the solver
//!   variant (the variant name may also be written: `body.outline.Rectangle.width`);
//! - setting a number on a newtype variant sets its content:
//!   `cracks.0.faces=1e-5` changes the gap of `Gap(..)`.
//!
//! Values are JSON (`0.1`, `true`, `[1, 2]`, `"text"`), RON tuples `(1, 2)`,
//! or bare words taken as strings (unit variants: `Strain`).

use serde_json::Value;

use super::{Scene, SceneError};

/// Parses a command-line value: JSON, a RON tuple `(a, b)`, or a bare string.
pub fn parse_value(text: &str) -> Value {
    let t = text.trim();
    if let Ok(v) = serde_json::from_str::<Value>(t) {
        return v;
    }
    if t.starts_with('(') && t.ends_with(')') {
        let json = format!("[{}]", &t[1..t.len() - 1]);
        if let Ok(v) = serde_json::from_str::<Value>(&json) {
            return v;
        }
    }
    Value::String(t.to_string())
}

/// Returns a copy of `scene` with each `(path, value)` set, validated, with the notes of
/// the edited scene ([`Scene::add_notes`]).
pub fn with_overrides(scene: &Scene, overrides: &[(String, Value)]) -> Result<Scene, SceneError> {
    let file = scene.file_label();
    let mut json = scene.to_json();
    for (path, value) in overrides {
        set_path(&mut json, path, value.clone()).map_err(|reason| SceneError::Path {
            file: file.clone(),
            path: path.clone(),
            reason,
        })?;
    }
    let mut out: Scene = serde_json::from_value(json).map_err(|e| SceneError::Path {
        file: file.clone(),
        path: overrides
            .iter()
            .map(|(p, _)| p.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        reason: format!("the new value does not fit the scene: {e}"),
    })?;
    out.source = scene.source.clone();
    out.validate()?;
    out.normalise();
    out.add_notes();
    Ok(out)
}

/// Sets the value at a dotted path in a JSON tree; the message says which
/// segment failed and what was available there.
pub fn set_path(root: &mut Value, path: &str, value: Value) -> Result<(), String> {
    if path.is_empty() {
        return Err("empty path".into());
    }
    let segments: Vec<&str> = path.split('.').collect();
    let mut node = root;
    let mut walked = String::new();
    for seg in &segments {
        node = step(node, seg, &walked)?;
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(seg);
    }
    assign(node, value, &walked)
}

/// Descends one segment (through a transparent enum variant if needed).
fn step<'a>(node: &'a mut Value, seg: &str, walked: &str) -> Result<&'a mut Value, String> {
    let here = if walked.is_empty() {
        "the scene"
    } else {
        walked
    };
    if node.is_null() {
        return Err(format!(
            "{here} is not set in the scene; write it in the file first"
        ));
    }
    if let Value::Array(items) = node {
        let len = items.len();
        let i: usize = seg
            .parse()
            .map_err(|_| format!("{here} is a list: expected an index, found '{seg}'"))?;
        return items
            .get_mut(i)
            .ok_or_else(|| format!("index {i} out of range: {here} has {len} entries"));
    }
    let Some(map) = node.as_object() else {
        return Err(format!(
            "{here} is a value, not a section: nothing called '{seg}' inside"
        ));
    };
    let direct = map.contains_key(seg);
    let via_variant = !direct
        && variant_key(map)
            .is_some_and(|k| map[k].as_object().is_some_and(|m| m.contains_key(seg)));
    if !direct && !via_variant {
        let keys = available_keys(node);
        return Err(format!("no field '{seg}' in {here}; available: {keys}"));
    }
    let map = node
        .as_object_mut()
        .ok_or_else(|| format!("{here} is not a section"))?;
    if direct {
        return map
            .get_mut(seg)
            .ok_or_else(|| format!("no field '{seg}' in {here}"));
    }
    let inner = variant_content(map).ok_or_else(|| format!("{here} is not a variant"))?;
    step(inner, seg, walked)
}

/// True for an enum variant name (starts with an upper-case letter).
fn is_variant_name(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_uppercase()) && s.chars().all(|c| c.is_ascii_alphanumeric())
}

/// The key of a single-key object whose key is an enum variant name.
fn variant_key(map: &serde_json::Map<String, Value>) -> Option<&String> {
    if map.len() != 1 {
        return None;
    }
    map.keys().next().filter(|k| is_variant_name(k))
}

/// The content of a single-key object whose key is an enum variant name.
fn variant_content(map: &mut serde_json::Map<String, Value>) -> Option<&mut Value> {
    if map.len() != 1 {
        return None;
    }
    let (k, v) = map.iter_mut().next()?;
    is_variant_name(k).then_some(v)
}

fn available_keys(node: &Value) -> String {
    let Value::Object(map) = node else {
        return String::new();
    };
    let mut keys: Vec<String> = map.keys().cloned().collect();
    if map.len() == 1 {
        if let Some(Value::Object(inner)) = map.values().next() {
            keys.extend(inner.keys().cloned());
        }
    }
    keys.join(", ")
}

/// Replaces the value, checking that numbers stay numbers and that newtype
/// variants keep their variant.
fn assign(node: &mut Value, value: Value, path: &str) -> Result<(), String> {
    if let Value::Object(map) = node {
        if let Some(inner) = variant_content(map) {
            if inner.is_number() && value.is_number() {
                *inner = value;
                return Ok(());
            }
            // Switching a struct-carrying variant by name: `pd.solver=Adr`
            // becomes `Adr` with default parameters.
            if inner.is_object() && value.as_str().is_some_and(is_variant_name) {
                let name = value.as_str().unwrap_or_default().to_string();
                *node = serde_json::json!({ name: {} });
                return Ok(());
            }
        }
    }
    match (&*node, &value) {
        (Value::Number(_), v) if !v.is_number() => Err(format!("{path} is a number; '{v}' is not")),
        (Value::Bool(_), v) if !v.is_boolean() => {
            Err(format!("{path} is true/false; '{v}' is not"))
        }
        _ => {
            *node = value;
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tuple_and_bare_values() {
        assert_eq!(parse_value("(1, 2.5)"), serde_json::json!([1, 2.5]));
        assert_eq!(parse_value("0.1"), serde_json::json!(0.1));
        assert_eq!(parse_value("Strain"), serde_json::json!("Strain"));
    }

    #[test]
    fn transparent_variant_and_newtype_content() {
        let mut v =
            serde_json::json!({"outline": {"Rectangle": {"width": 1.0}}, "faces": {"Gap": 1e-4}});
        set_path(&mut v, "outline.width", serde_json::json!(2.0)).expect("settable");
        set_path(&mut v, "faces", serde_json::json!(1e-5)).expect("settable");
        assert_eq!(v["outline"]["Rectangle"]["width"], serde_json::json!(2.0));
        assert_eq!(v["faces"]["Gap"], serde_json::json!(1e-5));
    }
}

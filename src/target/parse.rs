//! Path-aware parsing of target JSON.
//!
//! The JSON is first read into a [`serde_json::Value`]; each part is then
//! deserialized on its own so that every error can be prefixed with the JSON
//! path of the part (`target.grid`, `target.field.terms[1].field`,
//! `target.mask[0]`, ...). Range checks happen afterwards in
//! [`Target::validate`](crate::target::Target::validate).

use serde::de::DeserializeOwned;
use serde_json::Value;

use crate::target::error::TargetError;
use crate::target::field::{FieldSpec, Interpolation, SumTerm, FIELD_KINDS};
use crate::target::grid::{Grid, MaskRegion};
use crate::target::Target;

/// Keys allowed in the top-level target object.
const TOP_KEYS: &[&str] = &["name", "grid", "field", "weights", "mask"];

/// Short JSON type name of a value, for error messages.
fn type_name(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// Deserializes `v` with serde, prefixing any error with `path`.
fn at<T: DeserializeOwned>(v: &Value, path: &str) -> Result<T, TargetError> {
    T::deserialize(v).map_err(|e| TargetError::invalid(path, e.to_string()))
}

/// `v` as an object, or an error naming `path`.
fn object<'a>(v: &'a Value, path: &str) -> Result<&'a serde_json::Map<String, Value>, TargetError> {
    v.as_object().ok_or_else(|| {
        TargetError::invalid(path, format!("must be a JSON object, got {}", type_name(v)))
    })
}

/// Rejects keys of `obj` not in `allowed`.
fn check_keys(
    obj: &serde_json::Map<String, Value>,
    path: &str,
    allowed: &[&str],
) -> Result<(), TargetError> {
    match obj.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(TargetError::invalid(
            format!("{path}.{k}"),
            format!("unknown field (expected one of {})", allowed.join(", ")),
        )),
        None => Ok(()),
    }
}

/// Parses a target from JSON text (no range validation).
pub(crate) fn parse_target(s: &str) -> Result<Target, TargetError> {
    let root: Value = serde_json::from_str(s).map_err(TargetError::Syntax)?;
    let obj = object(&root, "target")?;
    check_keys(obj, "target", TOP_KEYS)?;

    let name = match obj.get("name") {
        None | Some(Value::Null) => String::new(),
        Some(Value::String(s)) => s.clone(),
        Some(v) => {
            return Err(TargetError::invalid(
                "target.name",
                format!("must be a string, got {}", type_name(v)),
            ))
        }
    };
    let grid = match obj.get("grid") {
        None | Some(Value::Null) => None,
        Some(v) => Some(parse_grid(v, "target.grid")?),
    };
    let field = match obj.get("field") {
        None | Some(Value::Null) => {
            return Err(TargetError::invalid(
                "target.field",
                format!(
                    "missing (required; an object with \"kind\" one of {})",
                    FIELD_KINDS.join(", ")
                ),
            ))
        }
        Some(v) => parse_field(v, "target.field")?,
    };
    let weights = match obj.get("weights") {
        None | Some(Value::Null) => None,
        Some(v) => Some(at(v, "target.weights")?),
    };
    let mask = match obj.get("mask") {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::Array(items)) => items
            .iter()
            .enumerate()
            .map(|(i, item)| at::<MaskRegion>(item, &format!("target.mask[{i}]")))
            .collect::<Result<_, _>>()?,
        Some(v) => {
            return Err(TargetError::invalid(
                "target.mask",
                format!(
                "must be an array of regions ({{\"circle\": ...}} or {{\"rect\": ...}}), got {}",
                type_name(v)
            ),
            ))
        }
    };
    Ok(Target {
        name,
        grid,
        field,
        weights,
        mask,
    })
}

/// Parses a grid object, giving each key its own path.
fn parse_grid(v: &Value, path: &str) -> Result<Grid, TargetError> {
    let obj = object(v, path)?;
    check_keys(obj, path, &["x", "y", "n"])?;
    let get = |key: &str, what: &str| {
        obj.get(key).ok_or_else(|| {
            TargetError::invalid(
                format!("{path}.{key}"),
                format!("missing (required: {what})"),
            )
        })
    };
    Ok(Grid {
        x: at(get("x", "[xmin, xmax] in metres")?, &format!("{path}.x"))?,
        y: at(get("y", "[ymin, ymax] in metres")?, &format!("{path}.y"))?,
        n: at(get("n", "[nx, ny], each ≥ 2")?, &format!("{path}.n"))?,
    })
}

/// Keys allowed in a field object of the given kind (including `kind`).
///
/// Must match the variants of [`FieldSpec`]; a test checks this.
pub(crate) fn kind_keys(kind: &str) -> &'static [&'static str] {
    match kind {
        "line_sink" => &["kind", "center", "strength", "angle", "offset"],
        "saddle" => &["kind", "center", "strength", "angle"],
        "whirlpool" => &["kind", "center", "strength", "rotation"],
        "trans" => &["kind", "center", "strength", "direction"],
        "squeeze_trans" => &["kind", "center", "strength", "angle", "transport"],
        "jet" => &["kind", "center", "strength", "direction", "width"],
        "sum" => &["kind", "terms"],
        "sampled" => &["kind", "points", "vectors", "interpolation"],
        // sink, source, circle, scaled_circle
        _ => &["kind", "center", "strength"],
    }
}

/// Deserializes an array of `[x, y]` pairs element by element so that
/// errors name the index.
fn pairs_at(v: &Value, path: &str) -> Result<(), TargetError> {
    match v {
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                at::<[f64; 2]>(item, &format!("{path}[{i}]")).map_err(|_| {
                    TargetError::invalid(
                        format!("{path}[{i}]"),
                        format!("must be a pair of numbers [a, b], got {item}"),
                    )
                })?;
            }
            Ok(())
        }
        other => Err(TargetError::invalid(
            path,
            format!("must be an array of [a, b] pairs, got {}", type_name(other)),
        )),
    }
}

/// Parses one field object found at JSON path `path`.
fn parse_field(v: &Value, path: &str) -> Result<FieldSpec, TargetError> {
    let obj = object(v, path)?;
    let kind_path = format!("{path}.kind");
    let kind = match obj.get("kind") {
        None => {
            return Err(TargetError::invalid(
                kind_path,
                format!("missing (expected one of {})", FIELD_KINDS.join(", ")),
            ))
        }
        Some(Value::String(k)) => k.as_str(),
        Some(other) => {
            return Err(TargetError::invalid(
                kind_path,
                format!("must be a string, got {}", type_name(other)),
            ))
        }
    };
    if !FIELD_KINDS.contains(&kind) {
        return Err(TargetError::invalid(
            kind_path,
            format!(
                "unknown kind \"{kind}\" (expected one of {})",
                FIELD_KINDS.join(", ")
            ),
        ));
    }
    let allowed = kind_keys(kind);
    if let Some(k) = obj.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(TargetError::invalid(
            format!("{path}.{k}"),
            format!(
                "unknown field for kind \"{kind}\" (expected one of {})",
                allowed.join(", ")
            ),
        ));
    }
    match kind {
        "sum" => {}
        "sampled" => {
            for key in ["points", "vectors"] {
                match obj.get(key) {
                    Some(v) => pairs_at(v, &format!("{path}.{key}"))?,
                    None => {
                        return Err(TargetError::invalid(
                            format!("{path}.{key}"),
                            "missing (required for kind \"sampled\")",
                        ))
                    }
                }
            }
            if let Some(v) = obj.get("interpolation") {
                at::<Interpolation>(v, &format!("{path}.interpolation"))?;
            }
            return at(v, path);
        }
        _ => {
            // Check each parameter on its own so that type errors name it.
            for (key, value) in obj {
                let p = format!("{path}.{key}");
                match key.as_str() {
                    "kind" => {}
                    "center" => {
                        at::<[f64; 2]>(value, &p).map_err(|_| {
                            TargetError::invalid(
                                &p,
                                format!("must be a point [x, y] in metres, got {value}"),
                            )
                        })?;
                    }
                    _ => {
                        if !value.is_number() {
                            return Err(TargetError::invalid(
                                p,
                                format!("must be a number, got {}", type_name(value)),
                            ));
                        }
                    }
                }
            }
            return at(v, path);
        }
    }
    // `sum` is parsed by hand so that errors inside terms get full paths.
    let terms_path = format!("{path}.terms");
    let items = match obj.get("terms") {
        Some(Value::Array(items)) => items,
        None => {
            return Err(TargetError::invalid(
                terms_path,
                "missing (required for kind \"sum\")",
            ))
        }
        Some(other) => {
            return Err(TargetError::invalid(
                terms_path,
                format!("must be an array of terms, got {}", type_name(other)),
            ))
        }
    };
    let mut terms = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let tp = format!("{terms_path}[{i}]");
        let tobj = object(item, &tp)?;
        check_keys(tobj, &tp, &["weight", "field"])?;
        let weight = match tobj.get("weight") {
            None => 1.0,
            Some(Value::Number(n)) => n.as_f64().unwrap_or(f64::NAN),
            Some(other) => {
                return Err(TargetError::invalid(
                    format!("{tp}.weight"),
                    format!("must be a number, got {}", type_name(other)),
                ))
            }
        };
        let field = match tobj.get("field") {
            Some(f) => parse_field(f, &format!("{tp}.field"))?,
            None => {
                return Err(TargetError::invalid(
                    format!("{tp}.field"),
                    "missing (required in every sum term)",
                ))
            }
        };
        terms.push(SumTerm { weight, field });
    }
    Ok(FieldSpec::Sum { terms })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A field object of `kind` using every key [`kind_keys`] allows.
    fn full_object(kind: &str) -> Value {
        let mut obj = serde_json::Map::new();
        for &key in kind_keys(kind) {
            let v = match key {
                "kind" => Value::from(kind),
                "center" => serde_json::json!([0.01, -0.01]),
                "terms" => serde_json::json!([{"weight": 2, "field": {"kind": "sink"}}]),
                "points" => serde_json::json!([[0, 0], [1, 0]]),
                "vectors" => serde_json::json!([[0, 1], [1, 0]]),
                "interpolation" => Value::from("nearest"),
                _ => Value::from(0.5),
            };
            obj.insert(key.to_string(), v);
        }
        Value::Object(obj)
    }

    #[test]
    fn kind_keys_match_the_serde_enum() {
        for &kind in FIELD_KINDS {
            let v = full_object(kind);
            let spec: FieldSpec =
                serde_json::from_value(v.clone()).unwrap_or_else(|e| panic!("{kind}: {e}"));
            assert_eq!(spec.kind(), kind);
            // Serializing writes every field, so the key sets must agree.
            let back = serde_json::to_value(&spec).unwrap();
            let mut got: Vec<&String> = back.as_object().unwrap().keys().collect();
            let mut want: Vec<String> = kind_keys(kind).iter().map(|s| s.to_string()).collect();
            got.sort();
            want.sort();
            assert_eq!(got, want.iter().collect::<Vec<_>>(), "{kind}");
            // And the path-aware parser agrees with serde.
            assert_eq!(parse_field(&v, "f").unwrap(), spec, "{kind}");
        }
    }

    #[test]
    fn parameter_errors_name_the_parameter() {
        let msg = |v: Value| parse_field(&v, "target.field").unwrap_err().to_string();
        let m = msg(serde_json::json!({"kind": "sink", "strenght": 2}));
        assert!(
            m.starts_with("target.field.strenght: unknown field for kind \"sink\""),
            "{m}"
        );
        let m = msg(serde_json::json!({"kind": "sink", "strength": "big"}));
        assert!(
            m.starts_with("target.field.strength: must be a number"),
            "{m}"
        );
        let m = msg(serde_json::json!({"kind": "jet", "center": [1]}));
        assert!(m.starts_with("target.field.center: must be a point"), "{m}");
        let m = msg(serde_json::json!({"kind": "sampled", "points": [[0, 0], [1]], "vectors": []}));
        assert!(
            m.starts_with("target.field.points[1]: must be a pair"),
            "{m}"
        );
        let m = msg(
            serde_json::json!({"kind": "sampled", "points": [], "vectors": [], "interpolation": "cubic"}),
        );
        assert!(
            m.starts_with("target.field.interpolation: unknown variant"),
            "{m}"
        );
        let m = msg(serde_json::json!({"kind": "sampled", "vectors": []}));
        assert!(m.starts_with("target.field.points: missing"), "{m}");
    }

    #[test]
    fn grid_errors_name_the_key() {
        let m = parse_grid(
            &serde_json::json!({"x": [0, 1], "y": [0, 1], "n": [-3, 2]}),
            "target.grid",
        )
        .unwrap_err()
        .to_string();
        assert!(m.starts_with("target.grid.n: "), "{m}");
        let m = parse_grid(
            &serde_json::json!({"x": [0, 1], "n": [3, 2]}),
            "target.grid",
        )
        .unwrap_err()
        .to_string();
        assert!(m.starts_with("target.grid.y: missing"), "{m}");
    }
}

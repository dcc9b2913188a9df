//! Typed JSON inputs (scenes, targets): serde with unknown keys rejected,
//! and every error located by its JSON path (`scene.motion.rotation.amplitude`).
//!
//! `from_str` deserialises a file's text with `serde_path_to_error`, so an
//! error anywhere in a plain struct, array or externally tagged enum carries
//! its path. Internally tagged objects (`{"type": "sine", "accel": 1}`) are
//! buffered by serde, which loses the path below them; they are read with
//! `tagged` instead, which looks up the tag, reads every other key through
//! a path-tracking `Body` and hands a located error back up as a serde
//! custom error, so the path survives any nesting (a `sum` target inside a
//! `sum`). Messages are then worded as the rest of the crate words them
//! (`must be a number, got string "big"`, `unknown field (expected one of …)`),
//! with numbers short ([`num`]). A key given twice in one object is an
//! error at that key (serde_json's `Value` would keep the last silently).
//! Ranges are not checked here: each input
//! has its own `validate` pass after this one.

use std::path::Path;

use serde::de::{DeserializeOwned, Deserializer, Error as _, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use serde_json::map::Entry;
use serde_json::{Map, Number, Value};
use serde_path_to_error::Segment;

/// Largest input file read (target, scene, schedule): 64 MiB. A sampled
/// target of 5000 points takes well under 1 MiB, so the cap only stops an
/// endless or mistaken input (`/dev/zero`, a disk image) before it fills
/// memory.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Reads the file at `path` whole, refusing (with an `InvalidInput` error
/// that states the rule) anything that is not a regular file — a FIFO would
/// block forever, a device may never end — and any file of more than `cap`
/// bytes. The read itself is bounded by `cap`, so a file that grows while
/// it is read is refused too, never read without end.
pub(crate) fn read_capped(path: &Path, cap: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let refuse = |why: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, why);
    let not_regular = || {
        refuse("not a regular file (a FIFO, device or folder); inputs must be regular files".into())
    };
    // Checked before opening: opening a FIFO blocks until a writer comes.
    if !std::fs::metadata(path)?.is_file() {
        return Err(not_regular());
    }
    let file = std::fs::File::open(path)?;
    if !file.metadata()?.is_file() {
        return Err(not_regular());
    }
    let mut bytes = Vec::new();
    file.take(cap + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(refuse(format!(
            "larger than the cap of {} MiB on this input",
            cap >> 20
        )));
    }
    Ok(bytes)
}

/// [`read_capped`] at [`MAX_INPUT_BYTES`], as UTF-8 text.
pub(crate) fn read_input(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read_capped(path, MAX_INPUT_BYTES)?)
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}

/// A located input error: the JSON path (starting with the root name, e.g.
/// `target.field.strength`) and what is wrong there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct InputError {
    /// JSON path of the offending value or key.
    pub path: String,
    /// What is wrong and what is allowed.
    pub message: String,
}

/// Marks a path carried inside a serde custom error message (see [`tagged`]).
const MARK: char = '\u{1}';

/// Deserialises `text` as a `T`, naming `root` as the top of every path.
pub(crate) fn from_str<T: DeserializeOwned>(text: &str, root: &str) -> Result<T, InputError> {
    let mut de = serde_json::Deserializer::from_str(text);
    let located = |path: String, e: &serde_json::Error| {
        let (sub, message) = if e.is_syntax() || e.is_eof() {
            (String::new(), syntax_message(text, e))
        } else {
            let raw = e.to_string();
            let raw = raw.rsplit_once(" at line ").map_or(raw.as_str(), |r| r.0);
            let (sub, message) = unmark(raw);
            (sub.to_string(), message.to_string())
        };
        tidy(format!("{root}{path}{sub}"), &message)
    };
    let Unique(value) = serde_path_to_error::deserialize(&mut de)
        .map_err(|e| located(path_string(e.path()), e.inner()))?;
    de.end().map_err(|e| located(String::new(), &e))?;
    // serde reads a struct from an array too; a file is an object.
    if !value.is_object() {
        return Err(InputError {
            path: root.to_string(),
            message: format!("must be a JSON object, got {}", describe(&value)),
        });
    }
    read(value, "").map_err(|(path, message)| tidy(format!("{root}{path}"), &message))
}

/// A JSON value read with every object's keys checked for repeats: the
/// text is read once, straight into a [`Value`] (no second pass), and a key
/// given twice in one object is an error located at that key
/// (`target.grid.n: duplicate key "n" ...`). `serde_json::Value` itself
/// keeps the last of a repeated key without a word, so a file with
/// `"name": "a", "name": "b"` would be read as `"b"`.
struct Unique(Value);

impl<'de> Deserialize<'de> for Unique {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(UniqueVisitor).map(Unique)
    }
}

/// Builds the [`Value`] of [`Unique`]; the same values `Value` builds.
struct UniqueVisitor;

impl<'de> Visitor<'de> for UniqueVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::Number(v.into()))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::Number(v.into()))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(Number::from_f64(v).map_or(Value::Null, Value::Number))
    }

    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_owned()))
    }

    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }

    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        Unique::deserialize(d).map(|u| u.0)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
        while let Some(Unique(v)) = seq.next_element()? {
            items.push(v);
        }
        Ok(Value::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            match out.entry(key) {
                Entry::Occupied(e) => {
                    let message = format!(
                        "duplicate key \"{}\" (a key may appear only once in an object)",
                        short(e.key())
                    );
                    return Err(marked(&format!(".{}", e.key()), &message));
                }
                Entry::Vacant(e) => {
                    let Unique(v) = map.next_value()?;
                    e.insert(v);
                }
            }
        }
        Ok(Value::Object(out))
    }
}

/// `path` written as `.key[3].key` (relative, empty at the root).
fn path_string(path: &serde_path_to_error::Path) -> String {
    let mut s = String::new();
    for segment in path {
        match segment {
            Segment::Seq { index } => s.push_str(&format!("[{index}]")),
            Segment::Map { key } => s.push_str(&format!(".{key}")),
            Segment::Enum { variant } => s.push_str(&format!(".{variant}")),
            Segment::Unknown => {}
        }
    }
    s
}

/// Splits a message `MARK path MARK rest` into (path, rest).
fn unmark(message: &str) -> (&str, &str) {
    message
        .strip_prefix(MARK)
        .and_then(|m| m.split_once(MARK))
        .unwrap_or(("", message))
}

/// A located error below the value being read (relative path, message),
/// as a serde error of any deserializer.
fn marked<E: serde::de::Error>(sub: &str, message: &str) -> E {
    E::custom(format_args!("{MARK}{sub}{MARK}{message}"))
}

/// Deserialises `value` (found at relative path `at`), returning a located
/// error (relative path, message) on failure.
fn read<T: DeserializeOwned>(value: Value, at: &str) -> Result<T, (String, String)> {
    serde_path_to_error::deserialize(&value).map_err(|e| {
        let raw = e.inner().to_string();
        let (sub, message) = unmark(&raw);
        let message = match keys_at(&value, e.path()) {
            Some(keys) if message.ends_with("expected map with a single key") => format!(
                "must be an object with a single key, the kind it describes, got {} keys{}",
                keys.len(),
                if keys.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", keys.join(", "))
                }
            ),
            _ => message.to_string(),
        };
        (format!("{at}{}{sub}", path_string(e.path())), message)
    })
}

/// The keys (quoted) of the object at `path` in `value`, if it is one.
fn keys_at(value: &Value, path: &serde_path_to_error::Path) -> Option<Vec<String>> {
    let mut v = value;
    for segment in path {
        v = match segment {
            Segment::Seq { index } => v.get(*index)?,
            Segment::Map { key } => v.get(key.as_str())?,
            Segment::Enum { .. } | Segment::Unknown => v,
        };
    }
    Some(v.as_object()?.keys().map(|k| format!("\"{k}\"")).collect())
}

/// The keys of one JSON object, read one by one with their paths. Reads
/// never fail on the spot: the first problem is kept and reported once the
/// whole object has been read, after any key nobody asked for, so a
/// misspelt key is reported as such rather than as the key it replaces
/// being missing.
pub(crate) struct Body {
    map: Map<String, Value>,
    asked: Vec<&'static str>,
    error: Option<(String, String)>,
}

impl Body {
    fn fail(&mut self, sub: String, message: String) {
        self.error.get_or_insert((sub, message));
    }

    /// A required key (its type's default is returned after an error).
    pub(crate) fn get<T: DeserializeOwned + Default>(&mut self, key: &'static str) -> T {
        self.asked.push(key);
        match self.map.remove(key) {
            Some(v) => self.or_fail(v, key),
            None => {
                self.fail(format!(".{key}"), "missing (required)".into());
                T::default()
            }
        }
    }

    /// An optional key with its default.
    pub(crate) fn or<T: DeserializeOwned + Default>(&mut self, key: &'static str, default: T) -> T {
        self.asked.push(key);
        match self.map.remove(key) {
            Some(v) => self.or_fail(v, key),
            None => default,
        }
    }

    fn or_fail<T: DeserializeOwned + Default>(&mut self, v: Value, key: &str) -> T {
        read(v, &format!(".{key}")).unwrap_or_else(|(sub, message)| {
            self.fail(sub, message);
            T::default()
        })
    }

    /// Every remaining key, read as one `T` (a struct that rejects unknown
    /// keys itself).
    pub(crate) fn rest<T: DeserializeOwned>(&mut self) -> Option<T> {
        let map = std::mem::take(&mut self.map);
        read(Value::Object(map), "")
            .map_err(|(sub, message)| self.fail(sub, message))
            .ok()
    }
}

/// Reads an object key by key with `build` (see [`Body`]); keys `build`
/// did not ask for are errors naming them and the keys allowed. `what`
/// names the object in that message (`for type "sine"`).
pub(crate) fn fields<'de, D, T>(
    map: Map<String, Value>,
    known: &[&'static str],
    what: &str,
    build: impl FnOnce(&mut Body) -> Option<T>,
) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
{
    let mut body = Body {
        map,
        asked: known.to_vec(),
        error: None,
    };
    let value = build(&mut body);
    if let Some(key) = body.map.keys().next() {
        let message = format!(
            "unknown field{what} (expected one of {})",
            body.asked.join(", ")
        );
        return Err(marked(&format!(".{key}"), &message));
    }
    match (body.error, value) {
        (Some((sub, message)), _) => Err(marked(&sub, &message)),
        (None, Some(v)) => Ok(v),
        (None, None) => Err(D::Error::custom("could not be read")),
    }
}

/// Reads an internally tagged object `{tag: kind, ...}`: `kinds` lists the
/// allowed values of the tag, `build` reads the other keys of the kind it
/// is given.
pub(crate) fn tagged<'de, D, T>(
    d: D,
    tag: &'static str,
    kinds: &[&str],
    build: impl FnOnce(&str, &mut Body) -> Option<T>,
) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
{
    let mut map = Map::<String, Value>::deserialize(d)?;
    let expected = kinds.join(", ");
    let kind = match map.remove(tag) {
        Some(Value::String(k)) if kinds.contains(&k.as_str()) => k,
        Some(Value::String(k)) => {
            let message = format!("unknown {tag} \"{k}\" (expected one of {expected})");
            return Err(marked(&format!(".{tag}"), &message));
        }
        None => {
            let message = format!("missing (required: one of {expected})");
            return Err(marked(&format!(".{tag}"), &message));
        }
        Some(other) => {
            let message = format!("must be one of {expected}, got {}", describe(&other));
            return Err(marked(&format!(".{tag}"), &message));
        }
    };
    let what = format!(" for {tag} \"{kind}\"");
    fields::<D, T>(map, &[tag], &what, |body| build(&kind, body))
}

/// Reads `value` (already taken from the input) as a `T`, keeping the
/// path of an error below it.
pub(crate) fn nested<'de, D, T>(value: Value) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: DeserializeOwned,
{
    read(value, "").map_err(|(sub, message)| marked(&sub, &message))
}

/// A JSON value described for an error message (`string "big"`, `an array`).
pub(crate) fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("{b}"),
        Value::Number(n) => n.as_f64().map_or_else(|| n.to_string(), num),
        Value::String(s) => format!("string \"{}\"", short(s)),
        Value::Array(_) => "an array".into(),
        Value::Object(_) => "an object".into(),
    }
}

/// A number for an error message, short: as written when that takes at
/// most 8 characters, else in scientific notation with at most 5
/// significant digits (`1e308`, never 309 digits).
pub fn num(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 8 {
        return plain;
    }
    let sci = format!("{v:e}");
    if sci.len() <= 10 {
        sci
    } else {
        format!("{v:.4e}")
    }
}

/// At most 40 characters of `s`.
pub(crate) fn short(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// Rewords serde's messages in the crate's terms and moves the key of an
/// unknown or missing field into the path.
fn tidy(mut path: String, message: &str) -> InputError {
    let words = |s: &str| {
        let s = if s.starts_with("struct ") {
            "an object"
        } else {
            s
        };
        s.replace('`', "\"")
            .replace("f64", "a number")
            .replace("usize", "a non-negative integer")
            .replace("u32", "a non-negative integer")
            .replace("u64", "a non-negative integer")
            .replace("a sequence", "an array")
            .replace("sequence", "an array")
            .replace("a map", "an object")
            .replace("map", "an object")
    };
    let key_of = |rest: &str| rest.split('`').next().unwrap_or("").to_string();
    let push_key = |path: &mut String, key: &str| {
        if !path.ends_with(&format!(".{key}")) {
            path.push('.');
            path.push_str(key);
        }
    };
    let message = if let Some(rest) = message.strip_prefix("unknown field `") {
        push_key(&mut path, &key_of(rest));
        match rest.split_once(", expected ") {
            Some((_, allowed)) => {
                let list = allowed.trim_start_matches("one of ").replace('`', "");
                format!(
                    "unknown field (expected one of {})",
                    list.replace(" or ", ", ")
                )
            }
            None => "unknown field (this object takes no fields)".to_string(),
        }
    } else if let Some(rest) = message.strip_prefix("missing field `") {
        push_key(&mut path, &key_of(rest));
        "missing (required)".to_string()
    } else if let Some((got, want)) = ["invalid type: ", "invalid value: ", "invalid length "]
        .iter()
        .find_map(|p| message.strip_prefix(p))
        .and_then(|rest| rest.split_once(", expected "))
    {
        let got = got
            .strip_prefix("floating point ")
            .or_else(|| got.strip_prefix("integer "))
            .unwrap_or(got);
        let got = match got.trim_matches('`').parse::<f64>() {
            Ok(x) => num(x),
            Err(_) => words(got),
        };
        format!("must be {}, got {got}", words(want))
    } else if let Some(rest) = message.strip_prefix("unknown variant ") {
        let (got, want) = rest.split_once(", expected ").unwrap_or((rest, ""));
        format!("unknown value {} (expected {})", words(got), words(want))
    } else {
        message.to_string()
    };
    InputError { path, message }
}

/// The message of a JSON syntax error; `NaN`, `Infinity` and numbers out
/// of a 64-bit float's range are named as such.
fn syntax_message(text: &str, e: &serde_json::Error) -> String {
    // serde_json reports the 1-based line and column (bytes) of the
    // offending character.
    let mut offset = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        if i + 1 == e.line() {
            offset += e.column().saturating_sub(1).min(line.len());
            break;
        }
        offset += line.len();
    }
    let bytes = text.as_bytes();
    let is_tok = |b: u8| b.is_ascii_alphanumeric() || b == b'+' || b == b'-' || b == b'.';
    let mut start = offset.min(bytes.len());
    while start > 0 && is_tok(bytes[start - 1]) {
        start -= 1;
    }
    let mut end = start;
    while end < bytes.len() && is_tok(bytes[end]) {
        end += 1;
    }
    let token = short(&text[start..end]);
    let bare = token.trim_start_matches(['+', '-']).to_ascii_lowercase();
    if matches!(bare.as_str(), "nan" | "inf" | "infinity") {
        format!("must be a finite number, got {token} (JSON has no NaN or Infinity)")
    } else if token.parse::<f64>().is_ok_and(|x| x.is_infinite()) {
        format!("must be a finite number, got {token} (out of range for a 64-bit float)")
    } else {
        format!("invalid JSON: {e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Outer {
        a: Vec<Inner>,
        #[serde(default)]
        n: usize,
    }

    #[derive(Debug, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Inner {
        shape: Shape,
    }

    #[derive(Debug, PartialEq)]
    enum Shape {
        Dot,
        Disc { radius: f64 },
        Many(Vec<Shape>),
    }

    impl<'de> Deserialize<'de> for Shape {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            tagged(d, "type", &["dot", "disc", "many"], |kind, b| {
                Some(match kind {
                    "dot" => Shape::Dot,
                    "disc" => Shape::Disc {
                        radius: b.get("radius"),
                    },
                    _ => Shape::Many(b.get::<Vec<Shape>>("of")),
                })
            })
        }
    }

    fn err(text: &str) -> String {
        let e = from_str::<Outer>(text, "top").unwrap_err();
        format!("{}: {}", e.path, e.message)
    }

    #[test]
    fn paths_reach_through_tagged_objects() {
        let ok: Outer = from_str(
            r#"{"a": [{"shape": {"type": "many", "of": [{"type": "dot"}, {"radius": 2, "type": "disc"}]}}]}"#,
            "top",
        )
        .unwrap();
        assert_eq!(
            ok.a[0].shape,
            Shape::Many(vec![Shape::Dot, Shape::Disc { radius: 2.0 }])
        );
        let nest = |inner: &str| {
            format!(
                r#"{{"a": [{{"shape": {{"type": "dot"}}}}, {{"shape": {{"type": "many", "of": [{{"type": "dot"}}, {inner}]}}}}]}}"#
            )
        };
        let cases = [
            (nest(r#"{"type": "disc", "radius": "big"}"#), "top.a[1].shape.of[1].radius: must be a number, got string \"big\""),
            (nest(r#"{"type": "disc", "radus": 2}"#), "top.a[1].shape.of[1].radus: unknown field for type \"disc\" (expected one of type, radius)"),
            (nest(r#"{"type": "disc"}"#), "top.a[1].shape.of[1].radius: missing (required)"),
            (nest(r#"{"type": "square"}"#), "top.a[1].shape.of[1].type: unknown type \"square\" (expected one of dot, disc, many)"),
            (nest(r#"{"radius": 1}"#), "top.a[1].shape.of[1].type: missing (required: one of dot, disc, many)"),
            (nest(r#"{"type": "disc", "radius": NaN}"#), "top.a[1].shape.of[1].radius: must be a finite number, got NaN (JSON has no NaN or Infinity)"),
            (nest(r#"{"type": "disc", "radius": -1e999}"#), "top.a[1].shape.of[1].radius: must be a finite number, got -1e999 (out of range"),
            (nest("3"), "top.a[1].shape.of[1]: must be an object, got 3"),
            (r#"{"a": [], "m": 1}"#.into(), "top.m: unknown field (expected one of a, n)"),
            (r#"{"n": 1}"#.into(), "top.a: missing (required)"),
            (r#"{"a": [], "n": -3}"#.into(), "top.n: must be a non-negative integer, got -3"),
            (r#"{"a": [], "n": 1e300}"#.into(), "top.n: must be a non-negative integer, got 1e300"),
            (r#"{"a": {}}"#.into(), "top.a: must be an array, got an object"),
            (r#"{"a": []} x"#.into(), "top: invalid JSON: trailing characters"),
            (r#"{"a": [}"#.into(), "top.a[0]: invalid JSON: expected value"),
            (r#"{"a": [], "n": 1, "n": 2}"#.into(), "top.n: duplicate key \"n\" (a key may appear only once"),
            (nest(r#"{"type": "disc", "radius": 1, "radius": 2}"#), "top.a[1].shape.of[1].radius: duplicate key \"radius\""),
            (nest(r#"{"type": "disc", "type": "dot"}"#), "top.a[1].shape.of[1].type: duplicate key \"type\""),
        ];
        for (text, want) in cases {
            let got = err(&text);
            assert!(got.starts_with(want), "{text}\n got {got:?}\nwant {want:?}");
        }
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(1e308), "1e308");
        assert_eq!(num(-2.5e-300), "-2.5e-300");
        assert_eq!(num(0.005), "0.005");
        assert_eq!(num(f64::NAN), "NaN");
        assert_eq!(num(1234.5), "1234.5");
        assert_eq!(num(0.0001013211836423378), "1.0132e-4");
        assert_eq!(num(1e5), "100000");
    }
}

#[cfg(test)]
#[path = "../tests/unit/inputs.rs"]
mod inputs_tests;

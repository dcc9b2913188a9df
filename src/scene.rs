//! Scenes: a plate motion, the physics around it and a sampling grid, read
//! from JSON, computed into a field (`platefield field SCENE.json`).
//!
//! ```text
//! {
//!   "name": "linesink",                         optional, used as the plot title
//!   "description": "...",                       optional, free text
//!   "motion": {"type": "screw" | "signals" | "primitive", ...},
//!   "kind": "force" | "velocity",
//!   "grid": {"x": [xmin, xmax], "y": [ymin, ymax], "n": [nx, ny]},   metres
//!   "friction": {"static": 0.3, "kinetic": 0.3},   optional; a number μ means both
//!   "gravity": 9.81,                            optional (m/s²)
//!   "model": "full" | "paper" | {"centripetal": b, "tilt": b, "coriolis": b, "moving": b},
//!   "phases": 30,                               optional, start phases of force fields
//!   "numerics": {"steps_per_cycle": 64, ...}    optional, every field defaulted
//! }
//! ```
//!
//! Motions ([`crate::motion::Motion`], plus library primitives):
//!
//! * `{"type": "screw", "axis": [kx, ky, kz], "point": [hx, hy, hz], "period": T,
//!   "rotation": WAVE, "translation": WAVE}` — rotation ψ(t) about the axis
//!   through h (rad) and translation d(t) along it (m); waveforms default to
//!   `zero`.
//! * `{"type": "signals", "period": T, "linear": {"x": TERMS, "y": TERMS, "z": TERMS},
//!   "angular": {...}}` — plate-centre translational acceleration (m/s²) and
//!   angular acceleration about the world axes (rad/s²); TERMS is a list of
//!   `{"amplitude": A, "phase": φ, "harmonic": n}` meaning A sin(n·2πt/T + φ)
//!   (phase defaults to 0, harmonic to 1).
//! * `{"type": "primitive", "kind": "LineSink", "omega": .., "amplitude": ..,
//!   "translation": .., "depth": .., "rotation_deg": .., "shift": [..]}` — a
//!   library primitive ([`crate::basis::Primitive`]); every field but `kind`
//!   defaults to the paper's value.
//!
//! Waveforms WAVE: `{"type": "zero"}`, `{"type": "sine", "accel": A}`
//! (q'' = A sin ωt), `{"type": "square", "accel": α}` (the paper's eq. 1),
//! `{"type": "rest_to_rest", "amplitude": q0}` (q = q0(1 − cos ωt)),
//! `{"type": "fourier", "terms": TERMS, "offset": 0}`.
//!
//! Parsing goes through [`serde_json::Value`] so that every error names its
//! JSON path and the allowed range (`scene.grid.n[0]: must be in 1..=1001,
//! got -3`); JSON syntax errors are located too, and `NaN` / `Infinity`
//! (which JSON does not have) are reported at their path. Ranges are then
//! checked by the `validate` methods of the parts.

use std::fmt::Write as _;
use std::path::Path;

use serde::{Serialize, Serializer};
use serde_json::{Map, Value};

use crate::basis::library::progress_bar;
use crate::basis::{Primitive, PrimitiveKind};
use crate::dynamics::{Friction, Model, Numerics};
use crate::error::{finite, positive, Error, Result};
use crate::field::{Field, FieldKind, FieldSettings, Grid};
use crate::motion::{Axes, FourierTerm, Motion, Screw, Signals, Waveform, V3};

/// Keys allowed at the top level of a scene.
const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "motion",
    "kind",
    "grid",
    "friction",
    "gravity",
    "model",
    "phases",
    "numerics",
];

/// Allowed range of `phases`.
pub const PHASES: std::ops::RangeInclusive<u64> = 1..=1000;
/// Allowed range of each grid count.
pub const GRID_N: std::ops::RangeInclusive<u64> = 1..=1001;
/// Allowed range of a Fourier term's harmonic number.
pub const HARMONIC: std::ops::RangeInclusive<u64> = 1..=100_000;

/// The motion of a scene: a kinematic motion, or a library primitive.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneMotion {
    /// A screw or six-signal motion.
    Motion(Motion),
    /// A library primitive with its parameters.
    Primitive(Primitive),
}

impl SceneMotion {
    /// The plate motion.
    pub fn to_motion(&self) -> Motion {
        match self {
            SceneMotion::Motion(m) => m.clone(),
            SceneMotion::Primitive(p) => p.motion(),
        }
    }

    /// JSON paths (under `path`) of the parameters that set the motion's
    /// amplitude, for error messages.
    pub fn amplitude_fields(&self, path: &str) -> Vec<String> {
        let wave = |name: &str, w: &Waveform| -> Option<String> {
            match w {
                Waveform::Zero => None,
                Waveform::Sine { .. } | Waveform::Square { .. } => {
                    Some(format!("{path}.{name}.accel"))
                }
                Waveform::RestToRest { .. } => Some(format!("{path}.{name}.amplitude")),
                Waveform::Fourier { .. } => Some(format!("{path}.{name}.terms[].amplitude")),
            }
        };
        match self {
            SceneMotion::Motion(Motion::Screw(s)) => [
                wave("rotation", &s.rotation),
                wave("translation", &s.translation),
            ]
            .into_iter()
            .flatten()
            .collect(),
            SceneMotion::Motion(Motion::Signals(s)) => {
                let mut out = Vec::new();
                for (group, axes) in [("linear", &s.linear), ("angular", &s.angular)] {
                    for (axis, terms) in [("x", &axes.x), ("y", &axes.y), ("z", &axes.z)] {
                        if terms.iter().any(|t| t.amplitude != 0.0) {
                            out.push(format!("{path}.{group}.{axis}[].amplitude"));
                        }
                    }
                }
                out
            }
            SceneMotion::Primitive(p) => {
                let mut out = vec![format!("{path}.amplitude")];
                if p.translation.is_some()
                    || Primitive::default_translation(p.kind) != 0.0
                    || p.kind == PrimitiveKind::Trans
                {
                    out.push(format!("{path}.translation"));
                }
                out
            }
        }
    }
}

impl Serialize for SceneMotion {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            SceneMotion::Motion(m) => m.serialize(s),
            SceneMotion::Primitive(p) => {
                let mut v = serde_json::to_value(p).map_err(serde::ser::Error::custom)?;
                if let Value::Object(o) = &mut v {
                    o.insert("type".into(), "primitive".into());
                }
                v.serialize(s)
            }
        }
    }
}

/// A scene: everything `platefield field` needs to compute one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    /// Optional name (the plot title).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Optional free-text description.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The plate motion.
    pub motion: SceneMotion,
    /// Force or velocity field.
    pub kind: FieldKind,
    /// Sampling grid (m).
    pub grid: Grid,
    /// Friction coefficients (default μ_s = μ_k = 0.3).
    pub friction: Friction,
    /// Gravity (m/s², default 9.81).
    pub gravity: f64,
    /// Model switches (default `full`).
    pub model: Model,
    /// Start phases of force fields (default 30).
    pub phases: usize,
    /// Integrator settings (defaults of [`Numerics`]).
    pub numerics: Numerics,
}

impl Scene {
    /// Parses and validates a scene from JSON text; errors name the JSON
    /// path (`scene.motion.period: ...`).
    pub fn from_json_str(text: &str) -> Result<Scene> {
        let root: Value = serde_json::from_str(text).map_err(|e| syntax_error(text, &e))?;
        let scene = parse_scene(&root)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads, parses and validates a scene file; errors are prefixed with
    /// the file path.
    pub fn load(path: &Path) -> Result<Scene> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        Scene::from_json_str(&text).map_err(|e| match e {
            Error::Invalid { field, message } => Error::Invalid {
                field: format!("{}: {field}", path.display()),
                message,
            },
            other => other,
        })
    }

    /// Range checks (the parts' own `validate` methods).
    pub fn validate(&self) -> Result<()> {
        match &self.motion {
            SceneMotion::Motion(m) => m.validate("scene.motion")?,
            SceneMotion::Primitive(p) => {
                p.validate("scene.motion")?;
                p.motion().validate("scene.motion")?;
            }
        }
        self.grid.validate("scene.grid")?;
        self.friction.validate("scene.friction")?;
        positive("scene.gravity", self.gravity)?;
        self.numerics.validate("scene.numerics")?;
        positive("scene.numerics.steady_accept", self.numerics.steady_accept)?;
        if !PHASES.contains(&(self.phases as u64)) {
            return Err(Error::invalid(
                "scene.phases",
                format!(
                    "must be in {}..={}, got {}",
                    PHASES.start(),
                    PHASES.end(),
                    self.phases
                ),
            ));
        }
        Ok(())
    }

    /// The scene as JSON (every default written out); parses back to the
    /// same scene.
    pub fn to_json(&self) -> Value {
        serde_json::to_value(self).unwrap_or(Value::Null)
    }

    /// The field settings of this scene.
    pub fn settings(&self) -> FieldSettings {
        FieldSettings {
            friction: self.friction,
            gravity: self.gravity,
            model: self.model,
            numerics: self.numerics,
            phases: self.phases,
            ..FieldSettings::default()
        }
    }

    /// Computes the field (with a progress bar on a terminal unless
    /// `quiet`). A scene in which the part leaves the plate at every grid
    /// point is physically invalid and an error naming the motion's
    /// amplitude parameters.
    pub fn compute(&self, quiet: bool) -> Result<Field> {
        let motion = self.motion.to_motion();
        let settings = self.settings();
        let bar = progress_bar(self.grid.len() as u64, quiet);
        bar.set_message(match self.kind {
            FieldKind::Force => "force",
            FieldKind::Velocity => "velocity",
        });
        let tick = || bar.inc(1);
        let field = Field::compute(&motion, &self.grid, self.kind, &settings, &tick);
        bar.finish_and_clear();
        let stats = field.stats();
        if stats.samples > 0 && stats.contact_lost == stats.samples {
            let fields = self.motion.amplitude_fields("scene.motion");
            let normal = self.min_normal(&motion);
            return Err(Error::Physical(format!(
                "the part leaves the plate (N < 0) at every grid point{}; reduce the amplitude ({})",
                if normal < 0.0 {
                    format!(" (lowest N at rest on the plate: {normal:.4} m/s²)")
                } else {
                    String::new()
                },
                if fields.is_empty() {
                    "scene.motion".to_string()
                } else {
                    fields.join(", ")
                }
            )));
        }
        Ok(field)
    }

    /// Lowest normal force per unit mass on a part at rest on the plate
    /// (u = 0) over the grid points and 256 instants of the cycle.
    fn min_normal(&self, motion: &Motion) -> f64 {
        let (g, model) = (self.gravity, self.model);
        let period = motion.period();
        let kin: Vec<_> = (0..256)
            .map(|i| motion.kinematics(period * i as f64 / 256.0, g, model.tilt))
            .collect();
        self.grid
            .points()
            .iter()
            .flat_map(|p| {
                let r = V3::new(p[0], p[1], 0.0);
                kin.iter()
                    .map(move |k| k.acceleration_at(&r, model.centripetal).z - k.gravity.z)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Title for plots: the scene's name, else `fallback`, with the kind
    /// and the model.
    pub fn title(&self, fallback: &str) -> String {
        let name = self.name.as_deref().unwrap_or(fallback);
        let kind = match self.kind {
            FieldKind::Force => "force field",
            FieldKind::Velocity => "velocity field",
        };
        format!("{name}: {kind}, model {}", self.model.name())
    }

    /// A short readable summary of the scene and its computed field.
    pub fn summary(&self, field: &Field, seconds: f64) -> String {
        let g = &self.grid;
        let st = field.stats();
        let (kind, units) = match self.kind {
            FieldKind::Force => ("force (zero-velocity)", "m/s²"),
            FieldKind::Velocity => ("velocity (steady state)", "m/s"),
        };
        let motion = match &self.motion {
            SceneMotion::Motion(Motion::Screw(s)) => format!(
                "screw, axis {:?} through {:?} m, T = {} s",
                s.axis, s.point, s.period
            ),
            SceneMotion::Motion(Motion::Signals(s)) => {
                format!("six signals, T = {} s", s.period)
            }
            SceneMotion::Primitive(p) => {
                format!("primitive {}, T = {:.6} s", p.kind.name(), p.period())
            }
        };
        let mut s = String::new();
        if let Some(name) = &self.name {
            let _ = writeln!(s, "scene:   {name}");
        }
        let _ = writeln!(s, "motion:  {motion}");
        let _ = writeln!(
            s,
            "grid:    {}×{} over x ∈ [{}, {}] m, y ∈ [{}, {}] m",
            g.n[0], g.n[1], g.x[0], g.x[1], g.y[0], g.y[1]
        );
        let _ = writeln!(
            s,
            "field:   {kind}, model {}, μ_s = {}, μ_k = {}, g = {} m/s²{}",
            self.model.name(),
            self.friction.stat,
            self.friction.kinetic,
            self.gravity,
            match self.kind {
                FieldKind::Force => format!(", {} start phases", self.phases),
                FieldKind::Velocity => String::new(),
            }
        );
        let _ = writeln!(
            s,
            "valid:   {} of {} samples (contact lost {}, not converged {}, frozen invalid {})",
            st.valid, st.samples, st.contact_lost, st.not_converged, st.frozen_invalid
        );
        let _ = writeln!(s, "max |f|: {:.6e} {units}", st.max_magnitude);
        let _ = writeln!(s, "time:    {seconds:.3} s");
        s
    }
}

// ---------------------------------------------------------------------------
// Path-aware parsing.

type Obj = Map<String, Value>;

/// Short JSON type name of a value, for error messages.
fn type_name(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("{b}"),
        Value::Number(n) => format!("{n}"),
        Value::String(s) => format!("the string \"{s}\""),
        Value::Array(_) => "an array".into(),
        Value::Object(_) => "an object".into(),
    }
}

fn object<'a>(v: &'a Value, path: &str, what: &str) -> Result<&'a Obj> {
    v.as_object().ok_or_else(|| {
        Error::invalid(
            path,
            format!("must be an object ({what}), got {}", type_name(v)),
        )
    })
}

fn check_keys(obj: &Obj, path: &str, allowed: &[&str]) -> Result<()> {
    match obj.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(Error::invalid(
            format!("{path}.{k}"),
            format!("unknown field (expected one of {})", allowed.join(", ")),
        )),
        None => Ok(()),
    }
}

fn required<'a>(obj: &'a Obj, path: &str, key: &str, what: &str) -> Result<&'a Value> {
    obj.get(key)
        .ok_or_else(|| Error::invalid(format!("{path}.{key}"), format!("missing ({what})")))
}

fn number(v: &Value, path: &str, what: &str) -> Result<f64> {
    match v.as_f64() {
        Some(x) => finite(path, x),
        None => Err(Error::invalid(
            path,
            format!("must be a finite number ({what}), got {}", type_name(v)),
        )),
    }
}

fn number_or(obj: &Obj, path: &str, key: &str, default: f64, what: &str) -> Result<f64> {
    match obj.get(key) {
        None => Ok(default),
        Some(v) => number(v, &format!("{path}.{key}"), what),
    }
}

fn integer(v: &Value, path: &str, range: &std::ops::RangeInclusive<u64>) -> Result<u64> {
    let (lo, hi) = (range.start(), range.end());
    if let Some(n) = v.as_u64() {
        if range.contains(&n) {
            return Ok(n);
        }
    }
    let message = match v {
        Value::Number(n) if n.is_i64() || n.is_u64() => format!("must be in {lo}..={hi}, got {n}"),
        Value::Number(n) => format!("must be an integer in {lo}..={hi}, got {n}"),
        other => format!(
            "must be an integer in {lo}..={hi}, got {}",
            type_name(other)
        ),
    };
    Err(Error::invalid(path, message))
}

fn integer_or(
    obj: &Obj,
    path: &str,
    key: &str,
    default: usize,
    range: &std::ops::RangeInclusive<u64>,
) -> Result<usize> {
    match obj.get(key) {
        None => Ok(default),
        Some(v) => Ok(integer(v, &format!("{path}.{key}"), range)? as usize),
    }
}

fn boolean(v: &Value, path: &str) -> Result<bool> {
    v.as_bool()
        .ok_or_else(|| Error::invalid(path, format!("must be true or false, got {}", type_name(v))))
}

fn string<'a>(v: &'a Value, path: &str, what: &str) -> Result<&'a str> {
    v.as_str().ok_or_else(|| {
        Error::invalid(
            path,
            format!("must be a string ({what}), got {}", type_name(v)),
        )
    })
}

fn array<'a>(v: &'a Value, path: &str, what: &str) -> Result<&'a Vec<Value>> {
    v.as_array().ok_or_else(|| {
        Error::invalid(
            path,
            format!("must be an array ({what}), got {}", type_name(v)),
        )
    })
}

/// Exactly `N` numbers.
fn numbers<const N: usize>(v: &Value, path: &str, what: &str) -> Result<[f64; N]> {
    let items = array(v, path, what)?;
    if items.len() != N {
        return Err(Error::invalid(
            path,
            format!("must have {N} numbers ({what}), got {}", items.len()),
        ));
    }
    let mut out = [0.0; N];
    for (i, item) in items.iter().enumerate() {
        out[i] = number(item, &format!("{path}[{i}]"), what)?;
    }
    Ok(out)
}

fn optional_string(obj: &Obj, key: &str) -> Result<Option<String>> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => Ok(Some(
            string(v, &format!("scene.{key}"), "free text")?.to_string(),
        )),
    }
}

fn parse_scene(root: &Value) -> Result<Scene> {
    let path = "scene";
    let obj = object(root, path, "a scene with motion, kind and grid")?;
    check_keys(obj, path, TOP_KEYS)?;
    let motion = parse_motion(
        required(
            obj,
            path,
            "motion",
            "the plate motion: {\"type\": \"screw\" | \"signals\" | \"primitive\", ...}",
        )?,
        "scene.motion",
    )?;
    let kind = match string(
        required(
            obj,
            path,
            "kind",
            "the field kind: \"force\" or \"velocity\"",
        )?,
        "scene.kind",
        "\"force\" or \"velocity\"",
    )? {
        "force" => FieldKind::Force,
        "velocity" => FieldKind::Velocity,
        other => {
            return Err(Error::invalid(
                "scene.kind",
                format!("unknown field kind \"{other}\" (expected force, velocity)"),
            ))
        }
    };
    let grid = parse_grid(
        required(
            obj,
            path,
            "grid",
            "{\"x\": [xmin, xmax], \"y\": [ymin, ymax], \"n\": [nx, ny]} in metres",
        )?,
        "scene.grid",
    )?;
    let friction = match obj.get("friction") {
        None => Friction::uniform(0.3),
        Some(v) => parse_friction(v, "scene.friction")?,
    };
    let gravity = number_or(obj, path, "gravity", 9.81, "m/s², > 0")?;
    let model = match obj.get("model") {
        None => Model::FULL,
        Some(v) => parse_model(v, "scene.model")?,
    };
    let phases = integer_or(obj, path, "phases", 30, &PHASES)?;
    let numerics = match obj.get("numerics") {
        None => Numerics::default(),
        Some(v) => parse_numerics(v, "scene.numerics")?,
    };
    Ok(Scene {
        name: optional_string(obj, "name")?,
        description: optional_string(obj, "description")?,
        motion,
        kind,
        grid,
        friction,
        gravity,
        model,
        phases,
        numerics,
    })
}

fn parse_grid(v: &Value, path: &str) -> Result<Grid> {
    let obj = object(
        v,
        path,
        "{\"x\": [xmin, xmax], \"y\": [ymin, ymax], \"n\": [nx, ny]}",
    )?;
    check_keys(obj, path, &["x", "y", "n"])?;
    let x = numbers::<2>(
        required(obj, path, "x", "[xmin, xmax] in metres")?,
        &format!("{path}.x"),
        "[xmin, xmax] in metres",
    )?;
    let y = numbers::<2>(
        required(obj, path, "y", "[ymin, ymax] in metres")?,
        &format!("{path}.y"),
        "[ymin, ymax] in metres",
    )?;
    let n_path = format!("{path}.n");
    let what = format!("[nx, ny], each in {}..={}", GRID_N.start(), GRID_N.end());
    let items = array(required(obj, path, "n", &what)?, &n_path, &what)?;
    if items.len() != 2 {
        return Err(Error::invalid(
            n_path,
            format!("must have 2 counts ({what}), got {}", items.len()),
        ));
    }
    let mut n = [0usize; 2];
    for (i, item) in items.iter().enumerate() {
        n[i] = integer(item, &format!("{n_path}[{i}]"), &GRID_N)? as usize;
    }
    Ok(Grid { x, y, n })
}

fn parse_friction(v: &Value, path: &str) -> Result<Friction> {
    if v.is_number() {
        return Ok(Friction::uniform(number(v, path, "μ, ≥ 0")?));
    }
    let obj = object(
        v,
        path,
        "{\"static\": μ_s, \"kinetic\": μ_k} with 0 ≤ μ_k ≤ μ_s, or one number",
    )?;
    check_keys(obj, path, &["static", "kinetic"])?;
    let get = |key: &str| -> Result<Option<f64>> {
        obj.get(key)
            .map(|v| number(v, &format!("{path}.{key}"), "≥ 0"))
            .transpose()
    };
    // A missing coefficient equals the other one; both missing: 0.3.
    let (stat, kinetic) = match (get("static")?, get("kinetic")?) {
        (Some(s), Some(k)) => (s, k),
        (Some(s), None) => (s, s),
        (None, Some(k)) => (k, k),
        (None, None) => (0.3, 0.3),
    };
    Ok(Friction { stat, kinetic })
}

const SWITCHES: [&str; 4] = ["centripetal", "tilt", "coriolis", "moving"];

fn parse_model(v: &Value, path: &str) -> Result<Model> {
    match v {
        Value::String(name) => match name.as_str() {
            "paper" => Ok(Model::PAPER),
            "full" => Ok(Model::FULL),
            other => Err(Error::invalid(
                path,
                format!(
                    "unknown model \"{other}\" (expected \"paper\", \"full\", or an object \
                     of switches {{\"centripetal\", \"tilt\", \"coriolis\", \"moving\"}})"
                ),
            )),
        },
        Value::Object(obj) => {
            check_keys(obj, path, &SWITCHES)?;
            let mut on = [false; 4];
            for (flag, key) in on.iter_mut().zip(SWITCHES) {
                *flag = boolean(
                    required(
                        obj,
                        path,
                        key,
                        "true or false; an explicit model sets all four switches",
                    )?,
                    &format!("{path}.{key}"),
                )?;
            }
            Ok(Model {
                centripetal: on[0],
                tilt: on[1],
                coriolis: on[2],
                moving: on[3],
            })
        }
        other => Err(Error::invalid(
            path,
            format!(
                "must be \"paper\", \"full\" or an object of switches, got {}",
                type_name(other)
            ),
        )),
    }
}

fn parse_numerics(v: &Value, path: &str) -> Result<Numerics> {
    let obj = object(v, path, "integrator settings, every field optional")?;
    check_keys(
        obj,
        path,
        &[
            "steps_per_cycle",
            "event_tol",
            "steady_tol",
            "steady_accept",
            "max_iterations",
        ],
    )?;
    let d = Numerics::default();
    Ok(Numerics {
        steps_per_cycle: integer_or(
            obj,
            path,
            "steps_per_cycle",
            d.steps_per_cycle,
            &(1..=1_000_000),
        )?,
        event_tol: number_or(obj, path, "event_tol", d.event_tol, "in (0, 1)")?,
        steady_tol: number_or(obj, path, "steady_tol", d.steady_tol, "in (0, 1)")?,
        steady_accept: number_or(obj, path, "steady_accept", d.steady_accept, "> 0")?,
        max_iterations: integer_or(
            obj,
            path,
            "max_iterations",
            d.max_iterations,
            &(1..=1_000_000),
        )?,
    })
}

const MOTION_TYPES: &str = "screw, signals, primitive";

fn parse_motion(v: &Value, path: &str) -> Result<SceneMotion> {
    let obj = object(
        v,
        path,
        &format!("a motion with \"type\" one of {MOTION_TYPES}"),
    )?;
    let ty = string(
        required(obj, path, "type", &format!("one of {MOTION_TYPES}"))?,
        &format!("{path}.type"),
        MOTION_TYPES,
    )?;
    match ty {
        "screw" => parse_screw(obj, path).map(|s| SceneMotion::Motion(Motion::Screw(s))),
        "signals" => parse_signals(obj, path).map(|s| SceneMotion::Motion(Motion::Signals(s))),
        "primitive" => parse_primitive(obj, path).map(SceneMotion::Primitive),
        other => Err(Error::invalid(
            format!("{path}.type"),
            format!("unknown motion type \"{other}\" (expected {MOTION_TYPES})"),
        )),
    }
}

const PERIOD_WHAT: &str = "the motion's period T in seconds, > 0";

fn parse_screw(obj: &Obj, path: &str) -> Result<Screw> {
    check_keys(
        obj,
        path,
        &["type", "axis", "point", "period", "rotation", "translation"],
    )?;
    let axis_what = "the axis direction k, [kx, ky, kz], non-zero";
    let point_what = "a point h on the axis, [x, y, z] in metres, z < 0 below the plate";
    let wave = |key: &str| -> Result<Waveform> {
        match obj.get(key) {
            None => Ok(Waveform::Zero),
            Some(v) => parse_waveform(v, &format!("{path}.{key}")),
        }
    };
    Ok(Screw {
        axis: numbers::<3>(
            required(obj, path, "axis", axis_what)?,
            &format!("{path}.axis"),
            axis_what,
        )?,
        point: numbers::<3>(
            required(obj, path, "point", point_what)?,
            &format!("{path}.point"),
            point_what,
        )?,
        period: number(
            required(obj, path, "period", PERIOD_WHAT)?,
            &format!("{path}.period"),
            PERIOD_WHAT,
        )?,
        rotation: wave("rotation")?,
        translation: wave("translation")?,
    })
}

const WAVE_TYPES: &str = "zero, sine, square, rest_to_rest, fourier";

fn parse_waveform(v: &Value, path: &str) -> Result<Waveform> {
    let obj = object(
        v,
        path,
        &format!("a waveform with \"type\" one of {WAVE_TYPES}"),
    )?;
    let ty = string(
        required(obj, path, "type", &format!("one of {WAVE_TYPES}"))?,
        &format!("{path}.type"),
        WAVE_TYPES,
    )?;
    let get = |key: &str, what: &str| -> Result<f64> {
        number(
            required(obj, path, key, what)?,
            &format!("{path}.{key}"),
            what,
        )
    };
    let accel = "acceleration amplitude: rad/s² for a rotation, m/s² for a translation";
    match ty {
        "zero" => {
            check_keys(obj, path, &["type"])?;
            Ok(Waveform::Zero)
        }
        "sine" => {
            check_keys(obj, path, &["type", "accel"])?;
            Ok(Waveform::Sine {
                accel: get("accel", accel)?,
            })
        }
        "square" => {
            check_keys(obj, path, &["type", "accel"])?;
            Ok(Waveform::Square {
                accel: get("accel", accel)?,
            })
        }
        "rest_to_rest" => {
            check_keys(obj, path, &["type", "amplitude"])?;
            Ok(Waveform::RestToRest {
                amplitude: get(
                    "amplitude",
                    "displacement amplitude q0: rad for a rotation, m for a translation",
                )?,
            })
        }
        "fourier" => {
            check_keys(obj, path, &["type", "terms", "offset"])?;
            let terms_what =
                "acceleration terms [{\"amplitude\": A, \"phase\": φ, \"harmonic\": n}, ...]";
            Ok(Waveform::Fourier {
                terms: parse_terms(
                    required(obj, path, "terms", terms_what)?,
                    &format!("{path}.terms"),
                )?,
                offset: number_or(obj, path, "offset", 0.0, "constant pose offset")?,
            })
        }
        other => Err(Error::invalid(
            format!("{path}.type"),
            format!("unknown waveform type \"{other}\" (expected {WAVE_TYPES})"),
        )),
    }
}

fn parse_terms(v: &Value, path: &str) -> Result<Vec<FourierTerm>> {
    let what = "a list of terms {\"amplitude\": A, \"phase\": φ, \"harmonic\": n}";
    array(v, path, what)?
        .iter()
        .enumerate()
        .map(|(i, item)| {
            let p = format!("{path}[{i}]");
            let obj = object(
                item,
                &p,
                "{\"amplitude\": A, \"phase\": φ, \"harmonic\": n}",
            )?;
            check_keys(obj, &p, &["amplitude", "phase", "harmonic"])?;
            let harmonic = match obj.get("harmonic") {
                None => 1,
                Some(h) => {
                    let hp = format!("{p}.harmonic");
                    integer(h, &hp, &HARMONIC).map_err(|e| match e {
                        Error::Invalid { field, message } if h.as_i64() == Some(0) => {
                            Error::Invalid {
                                field,
                                message: format!(
                                    "{message} (a constant acceleration is not periodic)"
                                ),
                            }
                        }
                        e => e,
                    })? as u32
                }
            };
            Ok(FourierTerm {
                amplitude: number(
                    required(obj, &p, "amplitude", "acceleration amplitude A")?,
                    &format!("{p}.amplitude"),
                    "acceleration amplitude A",
                )?,
                phase: number_or(obj, &p, "phase", 0.0, "phase φ in rad")?,
                harmonic,
            })
        })
        .collect()
}

fn parse_signals(obj: &Obj, path: &str) -> Result<Signals> {
    check_keys(obj, path, &["type", "period", "linear", "angular"])?;
    let axes = |key: &str| -> Result<Axes> {
        let p = format!("{path}.{key}");
        let Some(v) = obj.get(key) else {
            return Ok(Axes::default());
        };
        let o = object(v, &p, "{\"x\": TERMS, \"y\": TERMS, \"z\": TERMS}")?;
        check_keys(o, &p, &["x", "y", "z"])?;
        let terms = |axis: &str| -> Result<Vec<FourierTerm>> {
            o.get(axis)
                .map(|t| parse_terms(t, &format!("{p}.{axis}")))
                .transpose()
                .map(Option::unwrap_or_default)
        };
        Ok(Axes {
            x: terms("x")?,
            y: terms("y")?,
            z: terms("z")?,
        })
    };
    Ok(Signals {
        period: number(
            required(obj, path, "period", PERIOD_WHAT)?,
            &format!("{path}.period"),
            PERIOD_WHAT,
        )?,
        linear: axes("linear")?,
        angular: axes("angular")?,
    })
}

fn parse_primitive(obj: &Obj, path: &str) -> Result<Primitive> {
    check_keys(
        obj,
        path,
        &[
            "type",
            "kind",
            "omega",
            "amplitude",
            "translation",
            "depth",
            "rotation_deg",
            "shift",
        ],
    )?;
    let names: Vec<&str> = PrimitiveKind::ALL.iter().map(|k| k.name()).collect();
    let kind_path = format!("{path}.kind");
    let kind = PrimitiveKind::from_name(
        string(
            required(
                obj,
                path,
                "kind",
                &format!("the primitive, one of {}", names.join(", ")),
            )?,
            &kind_path,
            "a primitive name",
        )?,
        &kind_path,
    )?;
    let mut p = Primitive::new(kind);
    p.omega = number_or(
        obj,
        path,
        "omega",
        p.omega,
        "angular frequency ω in rad/s, > 0",
    )?;
    let opt = |key: &str, what: &str| -> Result<Option<f64>> {
        match obj.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => number(v, &format!("{path}.{key}"), what).map(Some),
        }
    };
    p.amplitude = opt("amplitude", "rotation amplitude ψ0 in rad")?;
    p.translation = opt("translation", "translation amplitude d0 in m")?;
    p.depth = number_or(
        obj,
        path,
        "depth",
        p.depth,
        "axis distance from the plate in m, > 0",
    )?;
    p.rotation_deg = number_or(obj, path, "rotation_deg", 0.0, "degrees")?;
    if let Some(v) = obj.get("shift") {
        p.shift = numbers::<2>(v, &format!("{path}.shift"), "[dx, dy] in metres")?;
    }
    Ok(p)
}

// ---------------------------------------------------------------------------
// JSON syntax errors, located by path.

/// A syntax error with the JSON path where it happened; `NaN`, `Infinity`
/// and out-of-range numbers are named as such.
fn syntax_error(text: &str, e: &serde_json::Error) -> Error {
    // serde_json reports 1-based line and column (bytes) of the offending
    // character.
    let mut offset = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        if i + 1 == e.line() {
            offset += e.column().saturating_sub(1).min(line.len());
            break;
        }
        offset += line.len();
    }
    let offset = offset.min(text.len());
    let bytes = text.as_bytes();
    let is_tok = |b: u8| b.is_ascii_alphanumeric() || b == b'+' || b == b'-' || b == b'.';
    let mut start = offset;
    while start > 0 && is_tok(bytes[start - 1]) {
        start -= 1;
    }
    let mut end = offset;
    while end < bytes.len() && is_tok(bytes[end]) {
        end += 1;
    }
    let token = &text[start..end];
    let bare = token.trim_start_matches(['+', '-']).to_ascii_lowercase();
    let path = json_path_at(text, start);
    let message = if matches!(bare.as_str(), "nan" | "inf" | "infinity") {
        format!("must be a finite number, got {token} (JSON has no NaN or Infinity)")
    } else if !token.is_empty() && token.parse::<f64>().is_ok_and(|x| x.is_infinite()) {
        format!("must be a finite number, got {token} (out of range for a 64-bit float)")
    } else {
        format!("invalid JSON: {e}")
    };
    Error::invalid(path, message)
}

/// The JSON path (`scene.motion.rotation.accel`) of byte `offset` in `text`,
/// found by scanning the (possibly malformed) text up to it.
fn json_path_at(text: &str, offset: usize) -> String {
    enum Frame {
        Object {
            key: Option<String>,
            expect_key: bool,
        },
        Array {
            index: usize,
        },
    }
    let bytes = text.as_bytes();
    let mut stack: Vec<Frame> = Vec::new();
    let mut i = 0;
    while i < offset.min(bytes.len()) {
        match bytes[i] {
            b'"' => {
                let mut j = i + 1;
                while j < bytes.len() && bytes[j] != b'"' {
                    j += if bytes[j] == b'\\' { 2 } else { 1 };
                }
                let j = j.min(bytes.len());
                if let Some(Frame::Object {
                    key,
                    expect_key: true,
                }) = stack.last_mut()
                {
                    let raw = &text[i..(j + 1).min(bytes.len())];
                    *key = Some(
                        serde_json::from_str::<String>(raw)
                            .unwrap_or_else(|_| raw.trim_matches('"').to_string()),
                    );
                }
                i = j + 1;
                continue;
            }
            b'{' => stack.push(Frame::Object {
                key: None,
                expect_key: true,
            }),
            b'[' => stack.push(Frame::Array { index: 0 }),
            b'}' | b']' => {
                stack.pop();
            }
            b',' => match stack.last_mut() {
                Some(Frame::Array { index }) => *index += 1,
                Some(Frame::Object { key, expect_key }) => {
                    *key = None;
                    *expect_key = true;
                }
                None => {}
            },
            b':' => {
                if let Some(Frame::Object { expect_key, .. }) = stack.last_mut() {
                    *expect_key = false;
                }
            }
            _ => {}
        }
        i += 1;
    }
    let mut path = String::from("scene");
    for frame in &stack {
        match frame {
            Frame::Object { key: Some(k), .. } => {
                path.push('.');
                path.push_str(k);
            }
            Frame::Object { key: None, .. } => {}
            Frame::Array { index } => {
                let _ = write!(path, "[{index}]");
            }
        }
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCREW: &str = r#"{
        "motion": {"type": "screw", "axis": [0, 1, 0], "point": [0, 0, -0.05],
                   "period": 0.03, "rotation": {"type": "rest_to_rest", "amplitude": 0.005}},
        "kind": "force",
        "grid": {"x": [-0.04, 0.04], "y": [-0.01, 0.01], "n": [5, 2]}
    }"#;

    fn err(text: &str) -> String {
        Scene::from_json_str(text).unwrap_err().to_string()
    }

    fn with(replace: &str, by: &str) -> String {
        assert!(SCREW.contains(replace), "{replace}");
        SCREW.replace(replace, by)
    }

    #[test]
    fn defaults_and_round_trip() {
        let s = Scene::from_json_str(SCREW).unwrap();
        assert_eq!(s.friction, Friction::uniform(0.3));
        assert_eq!(s.gravity, 9.81);
        assert_eq!(s.model, Model::FULL);
        assert_eq!(s.phases, 30);
        assert_eq!(s.numerics, Numerics::default());
        let back = Scene::from_json_str(&s.to_json().to_string()).unwrap();
        assert_eq!(back, s);
        let settings = s.settings();
        assert_eq!(settings.phases, 30);
        assert_eq!(
            settings.frozen_excursion,
            FieldSettings::default().frozen_excursion
        );
    }

    #[test]
    fn primitive_round_trip_and_models() {
        let text = r#"{"motion": {"type": "primitive", "kind": "SkewSink", "depth": 0.04,
            "shift": [0.01, 0]}, "kind": "velocity", "model": {"centripetal": false,
            "tilt": true, "coriolis": false, "moving": true}, "friction": {"kinetic": 0.25},
            "grid": {"x": [0, 0], "y": [0, 0], "n": [1, 1]}}"#;
        let s = Scene::from_json_str(text).unwrap();
        assert_eq!(s.friction, Friction::uniform(0.25));
        assert!(s.model.tilt && s.model.moving && !s.model.coriolis);
        let SceneMotion::Primitive(p) = &s.motion else {
            panic!()
        };
        assert_eq!(
            (p.kind, p.depth, p.shift),
            (PrimitiveKind::SkewSink, 0.04, [0.01, 0.0])
        );
        assert_eq!(Scene::from_json_str(&s.to_json().to_string()).unwrap(), s);
        let paper = text.replace(
            r#"{"centripetal": false,
            "tilt": true, "coriolis": false, "moving": true}"#,
            "\"paper\"",
        );
        assert_eq!(Scene::from_json_str(&paper).unwrap().model, Model::PAPER);
    }

    #[test]
    fn errors_name_the_path_and_range() {
        let cases = [
            (
                with("\"screw\"", "\"spiral\""),
                "scene.motion.type: unknown motion type \"spiral\" (expected screw, signals, primitive)",
            ),
            (
                with("[5, 2]", "[-3, 2]"),
                "scene.grid.n[0]: must be in 1..=1001, got -3",
            ),
            (with("[5, 2]", "[5, 2.5]"), "scene.grid.n[1]: must be an integer in 1..=1001"),
            (with("[5, 2]", "[5, 5000]"), "scene.grid.n[1]: must be in 1..=1001, got 5000"),
            (
                with("\"period\": 0.03,", ""),
                "scene.motion.period: missing (the motion's period T in seconds, > 0)",
            ),
            (with("\"period\": 0.03", "\"period\": -1"), "scene.motion.period: must be > 0"),
            (
                with("0.005}", "NaN}"),
                "scene.motion.rotation.amplitude: must be a finite number, got NaN",
            ),
            (
                with("0.005}", "-Infinity}"),
                "scene.motion.rotation.amplitude: must be a finite number, got -Infinity",
            ),
            (
                with("0.005}", "1e999}"),
                "scene.motion.rotation.amplitude: must be a finite number, got 1e999",
            ),
            (
                with("0.005}", "\"big\"}"),
                "scene.motion.rotation.amplitude: must be a finite number",
            ),
            (with("[0, 1, 0]", "[0, 0, 0]"), "scene.motion.axis: must be a non-zero vector"),
            (with("[0, 1, 0]", "[0, 1]"), "scene.motion.axis: must have 3 numbers"),
            (with("[-0.04, 0.04]", "[-0.04, null]"), "scene.grid.x[1]: must be a finite number"),
            (with("[-0.04, 0.04]", "[0.04, -0.04]"), "scene.grid.x: min must be < max"),
            (with("\"force\"", "\"speed\""), "scene.kind: unknown field kind \"speed\""),
            (with("\"rest_to_rest\"", "\"triangle\""), "scene.motion.rotation.type: unknown waveform type"),
            (with("\"kind\"", "\"knd\""), "scene.knd: unknown field"),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"friction\": {\"static\": 0.1, \"kinetic\": 0.3},"),
                "scene.friction.static: must be ≥ the kinetic coefficient",
            ),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"model\": \"exact\","),
                "scene.model: unknown model \"exact\"",
            ),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"model\": {\"tilt\": true},"),
                "scene.model.centripetal: missing",
            ),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"phases\": 0,"),
                "scene.phases: must be in 1..=1000, got 0",
            ),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"numerics\": {\"steps_per_cycle\": -1},"),
                "scene.numerics.steps_per_cycle: must be in 1..=1000000, got -1",
            ),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"numerics\": {\"event_tol\": 2},"),
                "scene.numerics.event_tol: must be in (0, 1)",
            ),
            (
                with("\"kind\": \"force\",", "\"kind\": \"force\", \"gravity\": 0,"),
                "scene.gravity: must be > 0",
            ),
            (with(
                    r#""grid": {"x": [-0.04, 0.04], "y": [-0.01, 0.01], "n": [5, 2]}"#,
                    r#""grid": 1"#,
                ), "scene.grid: must be an object"),
            (with("\"force\",", "\"force\""), "scene.kind: invalid JSON: expected `,` or `}`"),
        ];
        for (text, expected) in cases {
            let e = err(&text);
            assert!(e.starts_with(expected), "got {e:?}, expected {expected:?}");
        }
    }

    #[test]
    fn signal_and_primitive_errors() {
        let sig = r#"{"motion": {"type": "signals", "period": 0.03,
            "linear": {"x": [{"amplitude": 1, "harmonic": 0}]}}, "kind": "force",
            "grid": {"x": [0, 0], "y": [0, 0], "n": [1, 1]}}"#;
        let e = err(sig);
        assert!(
            e.starts_with(
                "scene.motion.linear.x[0].harmonic: must be in 1..=100000, got 0 (a constant"
            ),
            "{e}"
        );
        let e = err(&sig.replace("\"harmonic\": 0", "\"phase\": Infinity"));
        assert!(
            e.starts_with("scene.motion.linear.x[0].phase: must be a finite number, got Infinity"),
            "{e}"
        );
        let e = err(&sig.replace("\"linear\"", "\"lin\""));
        assert!(e.starts_with("scene.motion.lin: unknown field"), "{e}");
        let prim = r#"{"motion": {"type": "primitive", "kind": "Spiral"}, "kind": "force",
            "grid": {"x": [0, 0], "y": [0, 0], "n": [1, 1]}}"#;
        assert!(err(prim).starts_with("scene.motion.kind: unknown primitive \"Spiral\""));
        let e = err(&prim.replace("\"Spiral\"", "\"LineSink\", \"depth\": -1"));
        assert!(e.starts_with("scene.motion.depth: must be > 0"), "{e}");
    }

    #[test]
    fn load_prefixes_the_file() {
        let dir = std::env::temp_dir().join(format!("platefield-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.json");
        std::fs::write(&path, with("\"screw\"", "\"spiral\"")).unwrap();
        let e = Scene::load(&path).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("{}: scene.motion.type", path.display())),
            "{e}"
        );
        let e = Scene::load(&dir.join("missing.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.json"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn contact_loss_everywhere_is_an_error() {
        let s = Scene::from_json_str(&with("0.005}", "5.0}")).unwrap();
        let e = s.compute(true).unwrap_err().to_string();
        assert!(
            e.contains("leaves the plate (N < 0) at every grid point"),
            "{e}"
        );
        assert!(e.contains("scene.motion.rotation.amplitude"), "{e}");
        let mut ok = Scene::from_json_str(SCREW).unwrap();
        ok.phases = 4;
        let f = ok.compute(true).unwrap();
        assert_eq!(f.valid_count(), 10);
    }

    #[test]
    fn path_scanner() {
        let t = r#"{"a": [1, {"b": 2, "c": [3, 4, X"#;
        assert_eq!(json_path_at(t, t.len() - 1), "scene.a[1].c[2]");
        let t = r#"{"a\"q": {"b": 1}, "d": X"#;
        assert_eq!(json_path_at(t, t.len() - 1), "scene.d");
    }
}

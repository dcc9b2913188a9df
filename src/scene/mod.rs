//! Scenes: a plate motion, the physics around it and a sampling grid, read
//! from JSON (`platefield field SCENE.json`): serde types here, ranges in
//! `validate`, the field in [`compute`](Scene::compute).
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
//!   the second derivative θ'' of the plate's rotation vector θ, world axes
//!   (rad/s²; R = exp(\[θ\]×), to first order the angular acceleration:
//!   `motion::rotation`); TERMS is a list of
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
//! Reading goes through [`crate::input`]: unknown keys are errors, and
//! every error names its JSON path (`scene.motion.rotation.amplitude: must
//! be a number, got string "big"`); the allowed ranges are listed in
//! `validate`.

mod compute;
mod friction;
mod request;
mod validate;

use std::path::Path;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::Value;

use crate::basis::Primitive;
use crate::dynamics::{Friction, Model, Numerics};
use crate::error::{Error, Result};
use crate::field::{FieldKind, FieldSettings, Grid};
use crate::input;
use crate::motion::Motion;

pub use friction::FrictionSpec;
pub(crate) use friction::Interval;
pub use friction::MU;
pub use request::field;
pub use request::FieldRequest;
pub(crate) use validate::primitive as validate_primitive;
pub(crate) use validate::resolved as validate_resolved;
pub(crate) use validate::signals as validate_signals;
pub(crate) use validate::{
    ANGULAR_ACCEL, GRAVITY, GRAVITY_MIN, LINEAR_ACCEL, MAX_ITERATIONS, PERIOD,
};

/// The motion of a scene: a kinematic motion, or a library primitive.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneMotion {
    /// A screw or six-signal motion.
    Motion(Motion),
    /// A library primitive with its parameters.
    Primitive(Primitive),
}

/// The values of a scene motion's `"type"`.
pub(crate) const MOTION_TYPES: &[&str] = &["screw", "signals", "primitive"];

impl SceneMotion {
    /// The plate motion.
    pub(crate) fn to_motion(&self) -> Motion {
        match self {
            SceneMotion::Motion(m) => m.clone(),
            SceneMotion::Primitive(p) => p.motion(),
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

impl<'de> Deserialize<'de> for SceneMotion {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        input::tagged(d, "type", MOTION_TYPES, |kind, b| match kind {
            "screw" => b.rest().map(|s| SceneMotion::Motion(Motion::Screw(s))),
            "signals" => b.rest().map(|s| SceneMotion::Motion(Motion::Signals(s))),
            _ => b.rest().map(SceneMotion::Primitive),
        })
    }
}

/// Points per side of the sample grid [`Scene::rung`] measures the rungs
/// on: as many as `verify`'s default realised grid.
pub(crate) const RUNG_POINTS: usize = 5;

/// A scene: everything `platefield field` needs to compute one field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Optional name (the plot title).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Optional free-text description.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The plate motion.
    pub motion: SceneMotion,
    /// Force or velocity field.
    pub kind: FieldKind,
    /// Sampling grid (m).
    pub grid: Grid,
    /// Friction coefficients (default μ_s = μ_k = 0.3; one number sets
    /// both, a missing one equals the other).
    #[serde(default = "default_friction", deserialize_with = "friction")]
    pub friction: Friction,
    /// Gravity (m/s², default 9.81).
    #[serde(default = "default_gravity")]
    pub gravity: f64,
    /// Model switches: `"paper"`, `"full"` (default) or all four switches.
    #[serde(default = "default_model", deserialize_with = "model")]
    pub model: Model,
    /// Start phases of force fields (default 30).
    #[serde(default = "default_phases")]
    pub phases: usize,
    /// Integrator settings (defaults of [`Numerics`]).
    #[serde(default)]
    pub numerics: Numerics,
}

fn default_friction() -> Friction {
    Friction::uniform(0.3)
}

fn default_gravity() -> f64 {
    9.81
}

fn default_model() -> Model {
    Model::FULL
}

fn default_phases() -> usize {
    30
}

/// One exact friction in any form of [`FrictionSpec`] (`μ` or
/// `{"static": μ_s, "kinetic": μ_k}`); a range is for targets.
fn friction<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Friction, D::Error> {
    let spec = FrictionSpec::deserialize(d)?;
    if !spec.is_exact() {
        return Err(D::Error::custom(
            "a scene simulates one friction: give a number μ or {\"static\": μ_s, \"kinetic\": μ_k} (a range [low, high] is for targets, whose designs hold over it)",
        ));
    }
    Ok(spec.nominal())
}

/// `"paper"`, `"full"`, or an object of all four switches.
fn model<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Model, D::Error> {
    match Value::deserialize(d)? {
        Value::String(name) if name == "paper" => Ok(Model::PAPER),
        Value::String(name) if name == "full" => Ok(Model::FULL),
        v @ Value::Object(_) => input::nested::<D, Model>(v),
        other => Err(D::Error::custom(format!(
            "must be \"paper\", \"full\" or an object of the switches \
             {{\"centripetal\", \"tilt\", \"coriolis\", \"moving\"}}, got {}",
            input::describe(&other)
        ))),
    }
}

impl Scene {
    /// Reads and validates a scene from JSON text; errors name the JSON
    /// path (`scene.motion.period: ...`).
    pub fn from_json_str(text: &str) -> Result<Scene> {
        let scene: Scene =
            input::from_str(text, "scene").map_err(|e| Error::invalid(e.path, e.message))?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads and validates a scene file; errors are prefixed with the file
    /// path.
    pub fn load(path: &Path) -> Result<Scene> {
        let text = crate::input::read_input(path).map_err(|source| Error::Io {
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

    /// The scene as JSON (every default written out); reads back to the
    /// same scene.
    pub fn to_json(&self) -> Value {
        serde_json::to_value(self).unwrap_or(Value::Null)
    }

    /// The cheapest model rung whose field is within `tolerance` of the
    /// full model's ([`crate::field::rung::choose_rung`], the rule stated
    /// there), measured on 5 × 5 points (`RUNG_POINTS`) over the
    /// scene's grid (fewer where the grid has fewer), with the scene's kind
    /// and settings (its model ignored). What `field --model auto` plays.
    ///
    /// ```
    /// use platefield::scene::Scene;
    /// let text = r#"{"motion": {"type": "primitive", "kind": "Trans"}, "kind": "force",
    ///               "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [9, 9]}}"#;
    /// let scene = Scene::from_json_str(text).unwrap();
    /// let r = scene.rung(platefield::field::rung::DEFAULT_RUNG_TOLERANCE);
    /// assert_eq!((r.rung, r.error), ("paper", 0.0));
    /// ```
    pub fn rung(&self, tolerance: f64) -> crate::field::rung::RungReport {
        let sample = Grid {
            n: self.grid.n.map(|n| n.min(RUNG_POINTS)),
            ..self.grid
        };
        crate::field::rung::choose_rung(
            &self.motion.to_motion(),
            &sample,
            self.kind,
            &self.settings(),
            tolerance,
        )
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
}

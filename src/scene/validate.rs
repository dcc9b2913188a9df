//! The ranges of a scene's values, checked after it is read. Every bound is
//! stated here and in the README's scene table; errors name the JSON path
//! and the allowed range.
//!
//! The bounds keep every computed quantity finite and every run bounded:
//! the plate's pose amplitudes and accelerations are far above any
//! vibratory plate's (the paper's LineSink turns 0.005 rad and reaches
//! 218 rad/s²) and far below where a double overflows; friction, gravity
//! and the integrator's knobs are bounded so that a field cannot take
//! hours through one mistyped number.

use std::ops::RangeInclusive;

use super::{Scene, SceneMotion};
use crate::basis::Primitive;
use crate::error::{Error, Result};
use crate::input::num;
use crate::motion::{Axes, FourierTerm, Motion, Screw, Signals, Waveform};

/// Allowed range of `phases`.
pub(crate) const PHASES: RangeInclusive<u64> = 1..=1000;
/// Allowed range of each grid count.
pub(crate) const GRID_N: RangeInclusive<u64> = 1..=1001;
/// Largest |coordinate| (m) of the grid's corners and of a screw's point,
/// and the largest primitive depth and shift.
pub(crate) const GRID_EXTENT: f64 = 1.0;
/// Allowed range of a Fourier term's harmonic number: the highest the
/// largest [`STEPS_PER_CYCLE`] resolves at
/// [`STEPS_PER_HARMONIC`](crate::dynamics::STEPS_PER_HARMONIC) steps per
/// harmonic period (without it, harmonic 100000 would be accepted and
/// integrated as if resolved).
pub(crate) const HARMONIC: RangeInclusive<u64> =
    1..=(*STEPS_PER_CYCLE.end() / crate::dynamics::STEPS_PER_HARMONIC) as u64;
/// Largest number of Fourier terms in one signal or waveform.
pub(crate) const TERMS: usize = 1000;
/// Allowed range of a motion's period T (s).
pub(crate) const PERIOD: RangeInclusive<f64> = 1e-4..=100.0;
/// Largest rotation pose amplitude |q0| (rad): rest-to-rest amplitude,
/// Fourier offset, primitive amplitude.
pub(crate) const ROTATION: f64 = 0.5;
/// Largest translation pose amplitude |d0| (m).
pub(crate) const TRANSLATION: f64 = 0.1;
/// Largest peak angular acceleration (rad/s²) of a rotation.
pub(crate) const ANGULAR_ACCEL: f64 = crate::motion::ANGULAR_ACCEL;
/// Largest peak linear acceleration (m/s², about 1000 g) of a translation.
pub(crate) const LINEAR_ACCEL: f64 = crate::motion::LINEAR_ACCEL;
/// Largest gravity (m/s²; gravity is in [GRAVITY_MIN, GRAVITY]).
pub(crate) const GRAVITY: f64 = 100.0;
/// Smallest gravity (m/s²): 1 % of the paper's 9.81, below the Moon's
/// 1.62. Everything scales with g (the normal force N = g + a_z that
/// decides contact, the friction μN, the steady-state tolerances relative
/// to μ_k g T), so a g near 0 is no plate on a shaker: 1e-300 makes every
/// point "leave the plate" and the message asks to reduce the amplitude.
pub(crate) const GRAVITY_MIN: f64 = 0.1;
/// Allowed range of `numerics.steps_per_cycle`: 64 is the default and
/// 512 the reference of the speed study; a field at 4096 steps per cycle
/// already takes 64 times the default's time. The lower bound is
/// [`MIN_STEPS_PER_CYCLE`](crate::dynamics::MIN_STEPS_PER_CYCLE) (its
/// doc gives the measured errors below it).
pub(crate) const STEPS_PER_CYCLE: RangeInclusive<usize> =
    crate::dynamics::MIN_STEPS_PER_CYCLE..=4096;
/// Allowed range of `numerics.max_iterations` (cycle-map evaluations).
pub(crate) const MAX_ITERATIONS: RangeInclusive<usize> = 1..=10_000;

/// `v` in `[lo, hi]` (and finite), with `unit` in the message.
fn within(path: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<()> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        return Ok(());
    }
    Err(Error::invalid(
        path,
        format!(
            "must be in [{}, {}]{unit}, got {}",
            num(lo),
            num(hi),
            num(v)
        ),
    ))
}

/// `v` in `[-max, max]`.
fn magnitude(path: &str, v: f64, max: f64, unit: &str) -> Result<()> {
    within(path, v, -max, max, unit)
}

/// A count in `range`.
fn count<T: PartialOrd + std::fmt::Display>(
    path: &str,
    v: T,
    range: &RangeInclusive<T>,
) -> Result<()> {
    if range.contains(&v) {
        return Ok(());
    }
    Err(Error::invalid(
        path,
        format!("must be in {}..={}, got {v}", range.start(), range.end()),
    ))
}

/// Rotation or translation: the bounds and units of a waveform.
#[derive(Clone, Copy)]
struct Role {
    pose: f64,
    accel: f64,
    pose_unit: &'static str,
    accel_unit: &'static str,
}

const ROTATION_ROLE: Role = Role {
    pose: ROTATION,
    accel: ANGULAR_ACCEL,
    pose_unit: " rad",
    accel_unit: " rad/s²",
};

const TRANSLATION_ROLE: Role = Role {
    pose: TRANSLATION,
    accel: LINEAR_ACCEL,
    pose_unit: " m",
    accel_unit: " m/s²",
};

fn terms(list: &[FourierTerm], role: Role, at: &dyn Fn(&str) -> String) -> Result<()> {
    if list.len() > TERMS {
        return Err(Error::invalid(
            at(""),
            format!("must have at most {TERMS} terms, got {}", list.len()),
        ));
    }
    for (i, t) in list.iter().enumerate() {
        magnitude(
            &at(&format!("[{i}].amplitude")),
            t.amplitude,
            role.accel,
            role.accel_unit,
        )?;
        magnitude(&at(&format!("[{i}].phase")), t.phase, 1e3, " rad")?;
        count(
            &at(&format!("[{i}].harmonic")),
            u64::from(t.harmonic),
            &HARMONIC,
        )
        .map_err(|e| match e {
            Error::Invalid { field, message } if t.harmonic == 0 => Error::invalid(
                field,
                format!("{message} (a constant acceleration is not periodic)"),
            ),
            e => e,
        })?;
    }
    Ok(())
}

/// A waveform of period `period`; `at(key)` is the JSON path of its key.
fn wave(w: &Waveform, period: f64, role: Role, at: &dyn Fn(&str) -> String) -> Result<()> {
    match w {
        Waveform::Zero => Ok(()),
        Waveform::Sine { accel } | Waveform::Square { accel } => {
            magnitude(&at("accel"), *accel, role.accel, role.accel_unit)
        }
        Waveform::RestToRest { amplitude } => {
            // The acceleration q0 ω² cos ωt peaks at q0 ω².
            let omega = 2.0 * std::f64::consts::PI / period;
            let max = role.pose.min(role.accel / (omega * omega));
            magnitude(&at("amplitude"), *amplitude, max, role.pose_unit).map_err(|e| match e {
                Error::Invalid { field, message } if max < role.pose => Error::invalid(
                    field,
                    format!(
                        "{message} (the peak acceleration q0·ω² must stay within {}{} at T = {} s)",
                        num(role.accel),
                        role.accel_unit,
                        num(period)
                    ),
                ),
                e => e,
            })
        }
        Waveform::Fourier {
            terms: list,
            offset,
        } => {
            magnitude(&at("offset"), *offset, role.pose, role.pose_unit)?;
            terms(list, role, &|k| at(&format!("terms{k}")))
        }
    }
}

fn period(path: &str, t: f64) -> Result<()> {
    within(path, t, *PERIOD.start(), *PERIOD.end(), " s")
}

fn screw(s: &Screw, path: &str) -> Result<()> {
    period(&format!("{path}.period"), s.period)?;
    for (i, h) in s.point.iter().enumerate() {
        magnitude(&format!("{path}.point[{i}]"), *h, GRID_EXTENT, " m")?;
    }
    s.validate(path)?;
    wave(&s.rotation, s.period, ROTATION_ROLE, &|k| {
        format!("{path}.rotation.{k}")
    })?;
    wave(&s.translation, s.period, TRANSLATION_ROLE, &|k| {
        format!("{path}.translation.{k}")
    })
}

/// Checks a six-signal motion against the scene ranges (period in
/// `PERIOD`, at most `TERMS` terms per signal, each amplitude within
/// `LINEAR_ACCEL` or `ANGULAR_ACCEL`, phase within ±1000 rad,
/// harmonic in `HARMONIC`); errors name `path.linear.x[0].amplitude` etc.
/// Used for scene signals and for schedule segments alike.
pub(crate) fn signals(s: &Signals, path: &str) -> Result<()> {
    period(&format!("{path}.period"), s.period)?;
    let groups: [(&str, &Axes, Role); 2] = [
        ("linear", &s.linear, TRANSLATION_ROLE),
        ("angular", &s.angular, ROTATION_ROLE),
    ];
    for (group, axes, role) in groups {
        for (axis, list) in [("x", &axes.x), ("y", &axes.y), ("z", &axes.z)] {
            terms(list, role, &|k| format!("{path}.{group}.{axis}{k}"))?;
        }
    }
    s.validate(path)
}

/// The highest harmonic of the nonzero Fourier terms in `list` (named
/// `at("[i].harmonic")`), if any.
fn top_term(list: &[FourierTerm], at: &dyn Fn(&str) -> String) -> Option<(u32, String)> {
    list.iter()
        .enumerate()
        .filter(|(_, t)| t.amplitude != 0.0)
        .max_by_key(|(_, t)| t.harmonic)
        .map(|(i, t)| (t.harmonic, at(&format!("[{i}].harmonic"))))
}

/// The highest harmonic of a motion's Fourier terms and its JSON path
/// (`path.linear.y[0].harmonic`, `path.rotation.terms[1].harmonic`), if
/// it has any nonzero term.
fn top_harmonic(m: &Motion, path: &str) -> Option<(u32, String)> {
    let mut found = Vec::new();
    match m {
        Motion::Signals(s) | Motion::Ramped(crate::motion::Ramped { signals: s, .. }) => {
            for (group, axes) in [("linear", &s.linear), ("angular", &s.angular)] {
                for (axis, list) in [("x", &axes.x), ("y", &axes.y), ("z", &axes.z)] {
                    found.extend(top_term(list, &|k| format!("{path}.{group}.{axis}{k}")));
                }
            }
        }
        Motion::Screw(s) => {
            for (key, w) in [("rotation", &s.rotation), ("translation", &s.translation)] {
                if let Waveform::Fourier { terms: list, .. } = w {
                    found.extend(top_term(list, &|k| format!("{path}.{key}.terms{k}")));
                }
            }
        }
        // Held samples have no harmonics (never read from a scene).
        Motion::Held(_) => {}
    }
    found.into_iter().max_by_key(|(h, _)| *h)
}

/// Checks that `steps` RK4 steps per cycle (named `steps_path`) resolve
/// the highest harmonic of `m`: at least
/// [`STEPS_PER_HARMONIC`](crate::dynamics::STEPS_PER_HARMONIC) steps per
/// period of that harmonic (its doc gives the measured errors). A harmonic
/// above is refused, naming its path and the steps it needs, rather than
/// integrated as if resolved (far off, tens of per cent at a harmonic
/// of 100 at 64 steps).
pub(crate) fn resolved(m: &Motion, path: &str, steps: usize, steps_path: &str) -> Result<()> {
    let per = crate::dynamics::STEPS_PER_HARMONIC;
    match top_harmonic(m, path) {
        Some((h, at)) if (h as usize).saturating_mul(per) > steps => Err(Error::invalid(
            at,
            format!(
                "harmonic {h} needs at least {} steps per cycle ({per} per period of the harmonic) to be integrated, but {steps_path} is {steps}: raise {steps_path} to {} or more (at most {}), or lower the harmonic",
                h as usize * per,
                h as usize * per,
                STEPS_PER_CYCLE.end()
            ),
        )),
        _ => Ok(()),
    }
}

/// Checks a library primitive's parameters against the scene ranges
/// (omega from `PERIOD`, amplitude within `ROTATION`, translation within
/// `TRANSLATION`, depth and shift within `GRID_EXTENT`) and its resolved
/// motion's peak accelerations; errors name `path.<parameter>`. Used for
/// scene primitives and for schedule segments alike.
pub(crate) fn primitive(p: &Primitive, path: &str) -> Result<()> {
    let two_pi = 2.0 * std::f64::consts::PI;
    let (lo, hi) = (two_pi / PERIOD.end(), two_pi / PERIOD.start());
    within(&format!("{path}.omega"), p.omega, lo, hi, " rad/s")?;
    if let Some(a) = p.amplitude {
        magnitude(&format!("{path}.amplitude"), a, ROTATION, " rad")?;
    }
    if let Some(d) = p.translation {
        magnitude(&format!("{path}.translation"), d, TRANSLATION, " m")?;
    }
    within(&format!("{path}.depth"), p.depth, 1e-6, GRID_EXTENT, " m")?;
    magnitude(&format!("{path}.rotation_deg"), p.rotation_deg, 3600.0, "°")?;
    for (i, s) in p.shift.iter().enumerate() {
        magnitude(&format!("{path}.shift[{i}]"), *s, GRID_EXTENT, " m")?;
    }
    p.validate(path)?;
    // The resolved motion's peak accelerations, named by the primitive's
    // own parameters.
    if let Motion::Screw(s) = p.motion() {
        for (w, role, key) in [
            (&s.rotation, ROTATION_ROLE, "amplitude"),
            (&s.translation, TRANSLATION_ROLE, "translation"),
        ] {
            let peak = w.accel_bound(s.period);
            if peak.is_nan() || peak > role.accel {
                return Err(Error::invalid(
                    format!("{path}.{key}"),
                    format!(
                        "gives a peak acceleration of {}{} at omega = {} rad/s, above the allowed {}{}: lower {key} or omega",
                        num(peak),
                        role.accel_unit,
                        num(p.omega),
                        num(role.accel),
                        role.accel_unit
                    ),
                ));
            }
        }
    }
    p.motion().validate(path)
}

impl Scene {
    /// Checks every value against its allowed range (the constants of
    /// this module); the first problem found is returned, naming its JSON
    /// path and the range.
    pub(crate) fn validate(&self) -> Result<()> {
        let path = "scene.motion";
        match &self.motion {
            SceneMotion::Motion(Motion::Screw(s)) => screw(s, path)?,
            SceneMotion::Motion(
                Motion::Signals(s) | Motion::Ramped(crate::motion::Ramped { signals: s, .. }),
            ) => signals(s, path)?,
            // Held samples are never read from a scene; checked when built.
            SceneMotion::Motion(Motion::Held(_)) => {}
            SceneMotion::Primitive(p) => primitive(p, path)?,
        }
        let g = &self.grid;
        for (i, n) in g.n.iter().enumerate() {
            count(&format!("scene.grid.n[{i}]"), *n as u64, &GRID_N)?;
        }
        for (axis, range) in [("x", g.x), ("y", g.y)] {
            for (i, v) in range.iter().enumerate() {
                magnitude(&format!("scene.grid.{axis}[{i}]"), *v, GRID_EXTENT, " m")?;
            }
        }
        g.validate("scene.grid")?;
        super::FrictionSpec::exact(self.friction).validate("scene.friction")?;
        within("scene.gravity", self.gravity, GRAVITY_MIN, GRAVITY, " m/s²")?;
        let n = &self.numerics;
        let at = |k: &str| format!("scene.numerics.{k}");
        count(&at("steps_per_cycle"), n.steps_per_cycle, &STEPS_PER_CYCLE)?;
        if let SceneMotion::Motion(m) = &self.motion {
            resolved(m, path, n.steps_per_cycle, &at("steps_per_cycle"))?;
        }
        count(&at("max_iterations"), n.max_iterations, &MAX_ITERATIONS)?;
        for (key, v) in [
            ("event_tol", n.event_tol),
            ("steady_tol", n.steady_tol),
            ("steady_accept", n.steady_accept),
        ] {
            if !(v > 0.0 && v < 1.0) {
                return Err(Error::invalid(
                    at(key),
                    format!("must be in (0, 1), got {}", num(v)),
                ));
            }
        }
        n.validate("scene.numerics")?;
        count("scene.phases", self.phases as u64, &PHASES)
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::PrimitiveKind;
    use crate::dynamics::{Friction, Model, Numerics};
    use crate::field::FieldSettings;

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

    /// Each case's scene is refused with an error starting with its text;
    /// every mismatch is listed.
    fn assert_errors(cases: &[(String, &str)]) {
        let mut bad = Vec::new();
        for (text, expected) in cases {
            let e = err(text);
            if !e.starts_with(expected) {
                bad.push(format!("got {e:?}\n    expected {expected:?}"));
            }
        }
        assert!(bad.is_empty(), "{}", bad.join("\n"));
    }

    /// The screw scene with `key` (`"name": value`) added after its kind.
    fn adding(key: &str) -> String {
        with(
            "\"kind\": \"force\",",
            &format!("\"kind\": \"force\", {key},"),
        )
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
                "scene.motion.type: unknown type \"spiral\" (expected one of screw, signals, primitive)",
            ),
            (
                with("[5, 2]", "[-3, 2]"),
                "scene.grid.n[0]: must be a non-negative integer, got -3",
            ),
            (with("[5, 2]", "[5, 2.5]"), "scene.grid.n[1]: must be a non-negative integer, got 2.5"),
            (with("[5, 2]", "[5, 5000]"), "scene.grid.n[1]: must be in 1..=1001, got 5000"),
            (
                with("\"period\": 0.03,", ""),
                "scene.motion.period: missing (required)",
            ),
            (with("\"period\": 0.03", "\"period\": -1"), "scene.motion.period: must be in [0.0001, 100] s, got -1"),
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
                "scene.motion.rotation.amplitude: must be a number, got string \"big\"",
            ),
            (with("[0, 1, 0]", "[0, 0, 0]"), "scene.motion.axis: must be a non-zero vector"),
            (with("[0, 1, 0]", "[0, 1]"), "scene.motion.axis: must be an array of length 3, got 2"),
            (with("[-0.04, 0.04]", "[-0.04, null]"), "scene.grid.x[1]: must be a number, got null"),
            (with("[-0.04, 0.04]", "[0.04, -0.04]"), "scene.grid.x: min must be < max"),
            (with("\"force\"", "\"speed\""), "scene.kind: unknown value \"speed\" (expected \"force\" or \"velocity\")"),
            (with("\"rest_to_rest\"", "\"triangle\""), "scene.motion.rotation.type: unknown type \"triangle\" (expected one of zero, sine,"),
            (with("\"kind\"", "\"knd\""), "scene.knd: unknown field"),
            (adding(r#""friction": {"static": 0.1, "kinetic": 0.3}"#), "scene.friction.static: must be ≥ the kinetic coefficient"),
            (adding(r#""model": "exact""#), "scene.model: must be \"paper\", \"full\" or an object of the switches"),
            (adding(r#""model": {"tilt": true}"#), "scene.model.centripetal: missing"),
            (adding(r#""phases": 0"#), "scene.phases: must be in 1..=1000, got 0"),
            (adding(r#""numerics": {"steps_per_cycle": -1}"#), "scene.numerics.steps_per_cycle: must be a non-negative integer, got -1"),
            (adding(r#""numerics": {"event_tol": 2}"#), "scene.numerics.event_tol: must be in (0, 1)"),
            (adding(r#""gravity": 0"#), "scene.gravity: must be in [0.1, 100] m/s², got 0"),
            (with(
                    r#""grid": {"x": [-0.04, 0.04], "y": [-0.01, 0.01], "n": [5, 2]}"#,
                    r#""grid": 1"#,
                ), "scene.grid: must be an object, got 1"),
            (with("\"force\",", "\"force\""), "scene: invalid JSON: expected `,` or `}` at line 5"),
        ];
        assert_errors(&cases);
    }

    #[test]
    fn signal_and_primitive_errors() {
        let sig = r#"{"motion": {"type": "signals", "period": 0.03,
            "linear": {"x": [{"amplitude": 1, "harmonic": 0}]}}, "kind": "force",
            "grid": {"x": [0, 0], "y": [0, 0], "n": [1, 1]}}"#;
        let e = err(sig);
        assert!(
            e.starts_with(
                "scene.motion.linear.x[0].harmonic: must be in 1..=512, got 0 (a constant"
            ),
            "{e}"
        );
        // Harmonics the steps do not resolve (8 steps per harmonic period),
        // and above the largest steps' reach.
        for (harmonic, steps, expected) in [
            (9, 64, "harmonic 9 needs at least 72 steps per cycle (8 per period of the harmonic) to be integrated, but scene.numerics.steps_per_cycle is 64: raise scene.numerics.steps_per_cycle to 72 or more (at most 4096)"),
            (100, 512, "harmonic 100 needs at least 800 steps per cycle"),
            (100000, 4096, "must be in 1..=512, got 100000"),
        ] {
            let text = sig
                .replace("\"harmonic\": 0", &format!("\"harmonic\": {harmonic}"))
                .replace("\"kind\"", &format!("\"numerics\": {{\"steps_per_cycle\": {steps}}}, \"kind\""));
            let e = err(&text);
            assert!(
                e.starts_with(&format!("scene.motion.linear.x[0].harmonic: {expected}")),
                "{e}"
            );
        }
        // Resolved: 8 at 64 steps, 100 at 800; a zero term counts for nothing.
        for (harmonic, steps, amplitude) in [(8, 64, 1), (100, 800, 1), (500, 64, 0)] {
            let text = sig
                .replace("\"harmonic\": 0", &format!("\"harmonic\": {harmonic}"))
                .replace("\"amplitude\": 1", &format!("\"amplitude\": {amplitude}"))
                .replace(
                    "\"kind\"",
                    &format!("\"numerics\": {{\"steps_per_cycle\": {steps}}}, \"kind\""),
                );
            assert!(Scene::from_json_str(&text).is_ok(), "{harmonic} at {steps}");
        }
        let e = err(&sig.replace("\"harmonic\": 0", "\"phase\": Infinity"));
        assert!(
            e.starts_with("scene.motion.linear.x[0].phase: must be a finite number, got Infinity"),
            "{e}"
        );
        let e = err(&sig.replace("\"linear\"", "\"lin\""));
        assert!(e.starts_with("scene.motion.lin: unknown field"), "{e}");
        let prim = r#"{"motion": {"type": "primitive", "kind": "Spiral"}, "kind": "force",
            "grid": {"x": [0, 0], "y": [0, 0], "n": [1, 1]}}"#;
        let e = err(prim);
        assert!(
            e.starts_with(
                "scene.motion.kind: unknown value \"Spiral\" (expected one of \"LineSink\""
            ),
            "{e}"
        );
        let e = err(&prim.replace("\"Spiral\"", "\"LineSink\", \"depth\": -1"));
        assert!(
            e.starts_with("scene.motion.depth: must be in [0.000001, 1] m, got -1"),
            "{e}"
        );
        let e = err(&prim.replace("\"Spiral\"", "\"LineSink\", \"omega\": 20000"));
        assert!(
            e.starts_with("scene.motion.amplitude: gives a peak acceleration of 2000000 rad/s² at omega = 20000 rad/s, above the allowed 100000 rad/s²"),
            "{e}"
        );
    }

    /// Out-of-range physics is refused before any computation,
    /// naming the field and the allowed range, with short numbers.
    #[test]
    fn physics_out_of_range() {
        let cases = [
            (adding("\"friction\": 1e5"), "scene.friction: must be in [0, 2], got 100000"),
            (adding("\"friction\": {\"kinetic\": -0.1}"), "scene.friction: must be in [0, 2], got -0.1"),
            (adding("\"friction\": {\"static\": 0.3, \"kinetic\": 2.5}"), "scene.friction.kinetic: must be in [0, 2], got 2.5"),
            (adding("\"friction\": [0.2, 0.4]"), "scene.friction: a scene simulates one friction"),
            (adding("\"gravity\": 1e308"), "scene.gravity: must be in [0.1, 100] m/s², got 1e308"),
            (
                with("0.005}", "1e308}"),
                "scene.motion.rotation.amplitude: must be in [-0.5, 0.5] rad, got 1e308",
            ),
            (
                with("0.03,", "0.0002,"),
                "scene.motion.rotation.amplitude: must be in [-1.0132e-4, 1.0132e-4] rad, got 0.005 (the peak acceleration q0·ω² must stay within 100000 rad/s² at T = 0.0002 s)",
            ),
            (
                adding("\"numerics\": {\"steps_per_cycle\": 1000000}"),
                "scene.numerics.steps_per_cycle: must be in 8..=4096, got 1000000",
            ),
            (
                adding("\"numerics\": {\"steps_per_cycle\": 2}"),
                "scene.numerics.steps_per_cycle: must be in 8..=4096, got 2",
            ),
            (
                adding("\"numerics\": {\"steady_tol\": -1e300}"),
                "scene.numerics.steady_tol: must be in (0, 1), got -1e300",
            ),
            (adding("\"phases\": 100000"), "scene.phases: must be in 1..=1000, got 100000"),
            (with("[-0.04, 0.04]", "[-40, 0.04]"), "scene.grid.x[0]: must be in [-1, 1] m, got -40"),
            (with("-0.05]", "-1e300]"), "scene.motion.point[2]: must be in [-1, 1] m, got -1e300"),
            (with("\"period\": 0.03", "\"period\": 1e9"), "scene.motion.period: must be in [0.0001, 100] s, got 1e9"),
        ];
        assert_errors(&cases);
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
        let s = Scene::from_json_str(&with("0.005}", "0.4}")).unwrap();
        let e = s
            .compute(crate::progress::ProgressMode::Quiet)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("leaves the plate (N < 0) at every grid point"),
            "{e}"
        );
        assert!(e.contains("scene.motion.rotation.amplitude"), "{e}");
        let mut ok = Scene::from_json_str(SCREW).unwrap();
        ok.phases = 4;
        let f = ok.compute(crate::progress::ProgressMode::Quiet).unwrap();
        assert_eq!(f.valid_count(), 10);
    }
}

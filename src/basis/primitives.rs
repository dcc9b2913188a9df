//! The primitive library of the paper's section IV:
//! periodic screw motions {k, h, ψ(t), d(t)} whose fields have the forms of
//! the paper's Table I.
//!
//! Defaults are the paper's: ω = 209 rad/s (T = 0.03 s), ψ0 = 0.005 rad,
//! d0 = 0.05 cm, μ = 0.3. The paper's figure with the axis points is lost;
//! the axis points, amplitudes and waveforms below are this crate's
//! reconstruction. Every default waveform is
//! rest-to-rest (q = q0(1 − cos ωt), or an asymmetric series with q(0) =
//! q'(0) = 0), so that primitives can be sequenced with the plate at rest in
//! the home pose at every join.

use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

#[cfg(test)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::motion::{FourierTerm, Motion, Screw, Waveform};

/// The eight primitives of the paper's Table I.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum PrimitiveKind {
    /// Rotation about a horizontal axis below the plate: f ≈ a(−x, 0).
    LineSink,
    /// The same with the axis above: f ≈ a(x, 0).
    LineSource,
    /// Screw (rotation and translation in phase) about an axis below: f ≈ a(−x, x).
    SkewSink,
    /// Screw about an axis above: f ≈ a(x, −x).
    SkewSource,
    /// Rotation about an axis through the centre tilted 45°: f ≈ (a x y, b x²).
    DivCircle,
    /// Asymmetric in-plane translation: f ≈ a(1, 0).
    Trans,
    /// Asymmetric in-plane rotation, small amplitude: f ≈ a(−y, x).
    ScaledCircle,
    /// Asymmetric in-plane rotation, large amplitude: f ≈ a(−y, x)/|(x, y)|.
    Circle,
}

impl PrimitiveKind {
    /// All eight, in Table I order.
    pub const ALL: [PrimitiveKind; 8] = [
        PrimitiveKind::Trans,
        PrimitiveKind::ScaledCircle,
        PrimitiveKind::Circle,
        PrimitiveKind::DivCircle,
        PrimitiveKind::LineSink,
        PrimitiveKind::LineSource,
        PrimitiveKind::SkewSink,
        PrimitiveKind::SkewSource,
    ];

    /// The name used in files and JSON.
    pub fn name(&self) -> &'static str {
        match self {
            PrimitiveKind::LineSink => "LineSink",
            PrimitiveKind::LineSource => "LineSource",
            PrimitiveKind::SkewSink => "SkewSink",
            PrimitiveKind::SkewSource => "SkewSource",
            PrimitiveKind::DivCircle => "DivCircle",
            PrimitiveKind::Trans => "Trans",
            PrimitiveKind::ScaledCircle => "ScaledCircle",
            PrimitiveKind::Circle => "Circle",
        }
    }

    /// Parses a name (as in [`PrimitiveKind::name`]).
    #[cfg(test)]
    pub(crate) fn from_name(name: &str, field: &str) -> Result<PrimitiveKind> {
        PrimitiveKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                let all: Vec<&str> = PrimitiveKind::ALL.iter().map(|k| k.name()).collect();
                Error::invalid(
                    field,
                    format!(
                        "unknown primitive \"{name}\" (expected one of {})",
                        all.join(", ")
                    ),
                )
            })
    }
}

/// A primitive with its parameters; every field but `kind` has the paper's
/// default and can be overridden from JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Primitive {
    /// Which primitive.
    pub kind: PrimitiveKind,
    /// Angular frequency ω (rad/s); T = 2π/ω.
    #[serde(default = "defaults::omega")]
    pub omega: f64,
    /// Rotation amplitude ψ0 (rad) for the out-of-plane primitives; for the
    /// in-plane rotations, the amplitude of the first harmonic.
    #[serde(default)]
    pub amplitude: Option<f64>,
    /// Translation amplitude d0 (m) of the Skew primitives and Trans.
    #[serde(default)]
    pub translation: Option<f64>,
    /// Axis distance from the plate surface (m) for the Line and Skew primitives.
    #[serde(default = "defaults::depth")]
    pub depth: f64,
    /// Rotation of the whole motion about the vertical (degrees).
    #[serde(default)]
    pub rotation_deg: f64,
    /// Horizontal shift of the whole motion (m).
    #[serde(default)]
    pub shift: [f64; 2],
}

mod defaults {
    pub(crate) fn omega() -> f64 {
        209.0
    }
    pub(crate) fn depth() -> f64 {
        0.05
    }
}

/// Paper default ψ0 (rad).
pub const PSI0: f64 = 0.005;
/// Paper default d0 (m).
pub(crate) const D0: f64 = 0.0005;

/// Ratio of second to first harmonic in the asymmetric in-plane waveform.
const ASYM: f64 = 0.5;

impl Primitive {
    /// A primitive with the paper's defaults.
    pub fn new(kind: PrimitiveKind) -> Primitive {
        Primitive {
            kind,
            omega: defaults::omega(),
            amplitude: None,
            translation: None,
            depth: defaults::depth(),
            rotation_deg: 0.0,
            shift: [0.0, 0.0],
        }
    }

    /// Period T = 2π/ω.
    pub fn period(&self) -> f64 {
        2.0 * PI / self.omega
    }

    /// Default rotation amplitude of this kind (rad).
    pub(crate) fn default_amplitude(kind: PrimitiveKind) -> f64 {
        match kind {
            // Asymmetric in-plane rotation: first-harmonic angle amplitude.
            PrimitiveKind::ScaledCircle => 0.004,
            PrimitiveKind::Circle => 0.1,
            _ => PSI0,
        }
    }

    /// Default translation amplitude of this kind (m).
    pub(crate) fn default_translation(kind: PrimitiveKind) -> f64 {
        match kind {
            PrimitiveKind::Trans => D0,
            // Tuned so that the along-axis part matches the squeeze, as in
            // Table I's a(∓x, ±x); the sign picks the direction of the skew.
            PrimitiveKind::SkewSink => -0.6 * D0,
            PrimitiveKind::SkewSource => 0.6 * D0,
            _ => 0.0,
        }
    }

    /// Validates parameters.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        positive(&format!("{field}.omega"), self.omega)?;
        if let Some(a) = self.amplitude {
            finite(&format!("{field}.amplitude"), a)?;
        }
        if let Some(d) = self.translation {
            finite(&format!("{field}.translation"), d)?;
        }
        positive(&format!("{field}.depth"), self.depth)?;
        finite(&format!("{field}.rotation_deg"), self.rotation_deg)?;
        finite(&format!("{field}.shift[0]"), self.shift[0])?;
        finite(&format!("{field}.shift[1]"), self.shift[1])?;
        Ok(())
    }

    /// The untransformed motion (rotation 0, shift 0).
    pub(crate) fn base_motion(&self) -> Motion {
        let period = self.period();
        let psi0 = self.amplitude.unwrap_or(Self::default_amplitude(self.kind));
        let d0 = self
            .translation
            .unwrap_or(Self::default_translation(self.kind));
        let h = self.depth;
        let rest = |q0: f64| Waveform::RestToRest { amplitude: q0 };
        let screw = |axis: [f64; 3], point: [f64; 3], rotation: Waveform, translation: Waveform| {
            Motion::Screw(Screw {
                axis,
                point,
                period,
                rotation,
                translation,
            })
        };
        let s = std::f64::consts::FRAC_1_SQRT_2;
        match self.kind {
            PrimitiveKind::LineSink => {
                screw([0.0, 1.0, 0.0], [0.0, 0.0, -h], rest(psi0), Waveform::Zero)
            }
            PrimitiveKind::LineSource => {
                screw([0.0, 1.0, 0.0], [0.0, 0.0, h], rest(psi0), Waveform::Zero)
            }
            PrimitiveKind::SkewSink => screw([0.0, 1.0, 0.0], [0.0, 0.0, -h], rest(psi0), rest(d0)),
            PrimitiveKind::SkewSource => {
                screw([0.0, 1.0, 0.0], [0.0, 0.0, h], rest(psi0), rest(d0))
            }
            PrimitiveKind::DivCircle => {
                screw([0.0, s, s], [0.0, 0.0, 0.0], rest(psi0), Waveform::Zero)
            }
            PrimitiveKind::Trans => screw(
                [1.0, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                Waveform::Zero,
                sawtooth(-d0, self.omega),
            ),
            PrimitiveKind::ScaledCircle => screw(
                [0.0, 0.0, 1.0],
                [0.0, 0.0, 0.0],
                asymmetric(psi0, self.omega),
                Waveform::Zero,
            ),
            PrimitiveKind::Circle => screw(
                [0.0, 0.0, 1.0],
                [0.0, 0.0, 0.0],
                sawtooth(-psi0, self.omega),
                Waveform::Zero,
            ),
        }
    }

    /// The motion with this primitive's rotation and shift applied.
    pub fn motion(&self) -> Motion {
        self.base_motion()
            .transformed(self.rotation_deg.to_radians(), self.shift)
    }
}

/// Asymmetric rest-to-rest waveform: acceleration
/// −q0 ω² (cos ωt + β cos 2ωt), β = 1/2: a short strong push one way and a
/// long weak pull back, so that a part slips in one phase and is carried in
/// the other (Reznik and Canny's mechanism). q(0) = q'(0) = 0.
pub(crate) fn asymmetric(q0: f64, omega: f64) -> Waveform {
    let a = -q0 * omega * omega;
    Waveform::Fourier {
        terms: vec![
            FourierTerm {
                amplitude: a,
                phase: FRAC_PI_2,
                harmonic: 1,
            },
            FourierTerm {
                amplitude: a * ASYM,
                phase: FRAC_PI_2,
                harmonic: 2,
            },
        ],
        // Zero-mean pose is −(a/ω²) cos − (aβ/4ω²) cos 2; shift so q(0) = 0.
        offset: (a / (omega * omega)) * (1.0 + ASYM / 4.0),
    }
}

/// Rest-to-rest waveform with an asymmetric *velocity*: q' = q0 ω (sin ωt +
/// (β/2)(cos ωt − cos 2ωt)), β = 1, so the plate moves one way for longer
/// than the other. Where the plate is much faster than the part (large
/// amplitude) the part always slips and the net friction follows the sign
/// of the plate velocity, so what matters is how long each sign lasts.
/// q(0) = q'(0) = 0.
pub(crate) fn sawtooth(q0: f64, omega: f64) -> Waveform {
    let a = q0 * omega * omega;
    let beta = 1.0;
    // q'' = a (cos − (β/2) sin + β sin 2), as sin(nωt + φ) terms.
    let terms = vec![
        FourierTerm {
            amplitude: a,
            phase: FRAC_PI_2,
            harmonic: 1,
        },
        FourierTerm {
            amplitude: -a * beta / 2.0,
            phase: 0.0,
            harmonic: 1,
        },
        FourierTerm {
            amplitude: a * beta,
            phase: 0.0,
            harmonic: 2,
        },
    ];
    let w = Waveform::Fourier {
        terms: terms.clone(),
        offset: 0.0,
    };
    let q_at_0 = w.eval(0.0, 2.0 * PI / omega).q;
    Waveform::Fourier {
        terms,
        offset: -q_at_0,
    }
}

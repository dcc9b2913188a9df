//! Computing a scene's field, and its summary.

use std::fmt::Write as _;

use super::{Scene, SceneMotion};
use crate::basis::{Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::field::{Field, FieldKind};
use crate::motion::{Motion, Waveform, V3};
use crate::progress::{Progress, ProgressMode};

impl SceneMotion {
    /// JSON paths (under `path`) of the parameters that set the motion's
    /// amplitude, for error messages.
    pub(crate) fn amplitude_fields(&self, path: &str) -> Vec<String> {
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
            SceneMotion::Motion(
                Motion::Signals(s) | Motion::Ramped(crate::motion::Ramped { signals: s, .. }),
            ) => {
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
            // Held samples are never read from a scene.
            SceneMotion::Motion(Motion::Held(_)) => Vec::new(),
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

impl Scene {
    /// Computes the field (with its progress as `progress` asks). A scene in which the part leaves the plate at every grid
    /// point is physically invalid and an error naming the motion's
    /// amplitude parameters; so is one with no valid sample at all for
    /// any other reason (no steady state converged, e.g. with μ_k = 0),
    /// an error stating the counts by reason.
    pub fn compute(&self, progress: ProgressMode) -> Result<Field> {
        let motion = self.motion.to_motion();
        let settings = self.settings();
        let label = match self.kind {
            FieldKind::Force => "force field",
            FieldKind::Velocity => "velocity field",
        };
        let progress = Progress::new(label, "samples", self.grid.len() as u64, progress);
        let tick = || progress.inc(1);
        let field = Field::compute(&motion, &self.grid, self.kind, &settings, &tick);
        progress.finish();
        let stats = field.stats();
        if stats.samples > 0 && stats.contact_lost == stats.samples {
            let fields = self.motion.amplitude_fields("scene.motion");
            let normal = self.min_normal(&motion);
            return Err(Error::ContactLost(format!(
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
        if stats.samples > 0 && stats.valid == 0 {
            return Err(Error::ContactLost(self.no_valid_sample(&stats)));
        }
        Ok(field)
    }

    /// Why a field with no valid sample at all (but not every contact
    /// lost, reported above) is refused: the counts by reason and what each
    /// asks for.
    fn no_valid_sample(&self, st: &crate::field::FieldStats) -> String {
        let mut reasons = Vec::new();
        let mut hints = Vec::new();
        if st.not_converged > 0 {
            reasons.push(format!(
                "the steady state did not converge at {}",
                st.not_converged
            ));
            if self.friction.kinetic == 0.0 {
                hints.push(
                    "with kinetic friction μ_k = 0 (scene.friction) nothing drives the part to a steady velocity, so there is no friction field"
                        .to_string(),
                );
            } else {
                hints.push(format!(
                    "raise scene.numerics.max_iterations (now {}) or scene.numerics.steady_accept",
                    self.numerics.max_iterations
                ));
            }
        }
        if st.contact_lost > 0 {
            reasons.push(format!("the part left the plate at {}", st.contact_lost));
            let fields = self.motion.amplitude_fields("scene.motion");
            hints.push(format!(
                "reduce the amplitude ({})",
                if fields.is_empty() {
                    "scene.motion".to_string()
                } else {
                    fields.join(", ")
                }
            ));
        }
        if st.frozen_invalid > 0 {
            reasons.push(format!(
                "the frozen-position field is invalid (the part moves too far within a cycle) at {}",
                st.frozen_invalid
            ));
            hints.push("use a model with moving positions (scene.model)".to_string());
        }
        if st.non_finite > 0 {
            reasons.push(format!("the result was not finite at {}", st.non_finite));
        }
        if st.outside_source > 0 {
            reasons.push(format!(
                "outside the simulated region at {}",
                st.outside_source
            ));
        }
        format!(
            "no valid sample in the field: of {} samples, {}{}",
            st.samples,
            reasons.join(", "),
            if hints.is_empty() {
                String::new()
            } else {
                format!("; {}", hints.join("; "))
            }
        )
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
            SceneMotion::Motion(
                Motion::Signals(s) | Motion::Ramped(crate::motion::Ramped { signals: s, .. }),
            ) => {
                format!("six signals, T = {} s", s.period)
            }
            SceneMotion::Motion(Motion::Held(h)) => {
                format!("held samples, Δt = {} s", h.dt())
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
        let _ = writeln!(s, "grid:    {}", g.describe());
        let m = self.motion.to_motion();
        let _ = writeln!(
            s,
            "points:  simulated {} of {} ({})",
            crate::field::simulated_points(&m, g),
            g.len(),
            m.invariance()
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
            "valid:   {} of {} samples (contact lost {}, not converged {}, frozen invalid {}{})",
            st.valid,
            st.samples,
            st.contact_lost,
            st.not_converged,
            st.frozen_invalid,
            if st.non_finite > 0 {
                format!(", not finite {}", st.non_finite)
            } else {
                String::new()
            }
        );
        let _ = writeln!(s, "max |f|: {:.6e} {units}", st.max_magnitude);
        let _ = writeln!(s, "time:    {seconds:.3} s");
        s
    }
}

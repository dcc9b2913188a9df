//! The paper's section II: the LineSink, a plate rotating symmetrically
//! about a horizontal axis a depth h below its surface.
//!
//! With angular acceleration α(t) about the axis (k = −y, so that the
//! paper's eqs. 2–3 hold literally: a_x = −h α, a_z = r α at plate position
//! x = r), the effective gravity is g_eff = g + r α (eq. 4).
//!
//! For the square wave of eq. 1 (±α), frozen position, small angle, no
//! centripetal term, the part always slipping (h α > μ (g + |r| α)) and in
//! contact (|r| α ≤ g), the steady-state velocity is eq. 17:
//!
//! ```text
//! v_ss = (μ²(g² − (rα)²) − 3(hα)²) / (8 (hα)²) · α μ r T   ≈ −3 μ T α r / 8   (eq. 21)
//! ```
//!
//! For an axis above the surface (h < 0, a LineSource) the same derivation
//! with h → |h| and r → −r gives v_ss(h, r) = −v_ss(|h|, r).
//!
//! For a sine wave of amplitude A the part is held for the whole cycle
//! wherever |h A sin| ≤ μ_s (g + r A sin) at every phase, i.e. inside the
//! deadband |r| ≤ (μ_s g − |h| A)/(μ_s A) when |h| A < μ_s g.

use std::fmt::Write as _;

use serde::Serialize;

use platefield::dynamics::{
    ContactLoss, Friction, Model, Numerics, PartPhysics, Simulator, SteadyFailure,
};
use platefield::error::{finite, non_negative, positive, Error, Result};
use platefield::motion::{Motion, Screw, Waveform};

/// Angular-acceleration waveform of the LineSink shaker.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Wave {
    /// The paper's eq. 1: ±α square wave.
    Square,
    /// ψ'' = A sin ωt.
    Sine,
}

/// A one-axis LineSink shaker.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LineSink {
    /// Waveform of the angular acceleration.
    pub wave: Wave,
    /// α (square) or the sine's amplitude A (rad/s²).
    pub accel: f64,
    /// Axis depth h below the surface (m); negative = above (LineSource).
    pub depth: f64,
    /// Period T (s).
    pub period: f64,
    /// Friction coefficients.
    pub friction: Friction,
    /// Gravity g (m/s²).
    pub gravity: f64,
}

/// One row of the `linesink` command.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineSinkRow {
    /// Distance from the axis (m).
    pub r: f64,
    /// Simulated steady-state velocity (m/s); `None` when it does not exist.
    pub v_ss: Option<f64>,
    /// Eq. 17 where its assumptions hold, else `None`.
    pub eq17: Option<f64>,
    /// Fraction of the cycle the part is stuck.
    pub stick_fraction: Option<f64>,
    /// True when the part leaves the plate.
    pub contact_lost: bool,
    /// Where and when contact was lost.
    pub contact_loss: Option<ContactLoss>,
    /// Failure message (contact loss, not converged), if any.
    pub error: Option<String>,
}

impl LineSink {
    /// Validates all parameters (field names are the CLI arguments).
    pub fn validate(&self) -> Result<()> {
        finite("--accel", self.accel)?;
        finite("--depth", self.depth)?;
        positive("--period", self.period)?;
        non_negative("--mu", self.friction.kinetic)?;
        // μ_k = 0: no friction force, so nothing drives the part to a
        // steady velocity (its mean velocity is whatever it started with);
        // `field` refuses the same (platefield::scene).
        if self.friction.kinetic == 0.0 {
            return Err(Error::invalid(
                "--mu",
                "must be > 0, got 0: with kinetic friction μ_k = 0 nothing drives the part to a steady velocity, so there is no friction field (`field` refuses it too)",
            ));
        }
        self.friction.validate("--mu").map_err(|_| {
            Error::invalid(
                "--mu-static",
                format!(
                    "must be ≥ --mu ({}), got {}",
                    self.friction.kinetic, self.friction.stat
                ),
            )
        })?;
        positive("gravity", self.gravity)?;
        Ok(())
    }

    /// The screw motion: rotation about k = −y through (0, 0, −h).
    pub fn motion(&self) -> Motion {
        Motion::Screw(Screw {
            axis: [0.0, -1.0, 0.0],
            point: [0.0, 0.0, -self.depth],
            period: self.period,
            rotation: match self.wave {
                Wave::Square => Waveform::Square { accel: self.accel },
                Wave::Sine => Waveform::Sine { accel: self.accel },
            },
            translation: Waveform::Zero,
        })
    }

    /// Eq. 17 at distance `r`, or `None` outside its assumptions (square
    /// wave, always slipping, in contact).
    pub fn eq17(&self, r: f64) -> Option<f64> {
        let (mu, g, a, t) = (
            self.friction.kinetic,
            self.gravity,
            self.accel.abs(),
            self.period,
        );
        let h = self.depth.abs();
        let always_slips = h * a > self.friction.stat * (g + r.abs() * a);
        let in_contact = r.abs() * a <= g;
        if self.wave != Wave::Square || !always_slips || !in_contact || self.depth == 0.0 {
            return None;
        }
        let ha = h * a;
        let v = (mu * mu * (g * g - (r * a).powi(2)) - 3.0 * ha * ha) / (8.0 * ha * ha)
            * a
            * mu
            * r
            * t;
        Some(v * self.depth.signum())
    }

    /// Eq. 21, the small-r, large-h limit: −3 μ T α r / 8.
    pub fn eq21(&self, r: f64) -> f64 {
        -3.0 * self.friction.kinetic * self.period * self.accel.abs() * r / 8.0
            * self.depth.signum()
    }

    /// Edge of the sine wave's stick deadband, (μ_s g − |h| A)/(μ_s A), or
    /// `None` when there is none (|h| A ≥ μ_s g, or a square wave). The
    /// paper model's (small angle, frozen position, no centripetal term):
    /// the full model's tilt and centripetal terms move the edge, so it is
    /// printed for `--model paper` only.
    pub fn deadband_edge(&self) -> Option<f64> {
        let (mus, g, a, h) = (
            self.friction.stat,
            self.gravity,
            self.accel.abs(),
            self.depth.abs(),
        );
        (self.wave == Wave::Sine && h * a < mus * g && mus > 0.0 && a > 0.0)
            .then(|| (mus * g - h * a) / (mus * a))
    }

    /// Simulates the steady state at each distance in `rs`.
    pub fn rows(&self, rs: &[f64], model: Model, numerics: Numerics) -> Vec<LineSinkRow> {
        let motion = self.motion();
        let sim = Simulator::new(
            &motion,
            PartPhysics::new(self.friction, self.gravity, model),
            numerics,
        );
        rs.iter()
            .map(|&r| {
                let eq17 = self.eq17(r);
                match sim.steady_state([r, 0.0]) {
                    Ok(s) => LineSinkRow {
                        r,
                        v_ss: Some(s.velocity[0]),
                        eq17,
                        stick_fraction: Some(s.stick_fraction),
                        contact_lost: false,
                        contact_loss: None,
                        error: None,
                    },
                    Err(e) => LineSinkRow {
                        r,
                        v_ss: None,
                        eq17,
                        stick_fraction: None,
                        contact_lost: matches!(e, SteadyFailure::ContactLoss(_)),
                        contact_loss: match e {
                            SteadyFailure::ContactLoss(c) => Some(c),
                            _ => None,
                        },
                        error: Some(e.to_string()),
                    },
                }
            })
            .collect()
    }

    /// `platefield study linesink`: validates the shaker and the distances `rs`,
    /// simulates each, and returns the rows as JSON (`json`) or as a table
    /// beside eq. 17.
    pub fn report(
        &self,
        rs: &[f64],
        model: Model,
        numerics: Numerics,
        json: bool,
    ) -> Result<String> {
        self.validate()?;
        if rs.is_empty() {
            return Err(Error::invalid("--r", "must list at least one number"));
        }
        for &r in rs {
            finite("--r", r)?;
        }
        let rows = self.rows(rs, model, numerics);
        if json {
            let mut s =
                serde_json::to_string_pretty(&rows).map_err(|e| Error::Internal(e.to_string()))?;
            s.push('\n');
            return Ok(s);
        }
        let mut s = format!(
            "LineSink: {:?} wave, accel {} rad/s², depth {} m, T {} s, μ_k {}, μ_s {}, model {}\n",
            self.wave,
            self.accel,
            self.depth,
            self.period,
            self.friction.kinetic,
            self.friction.stat,
            model.name()
        );
        match self.deadband_edge() {
            Some(edge) if model == platefield::dynamics::Preset::Paper.model() => {
                let _ = writeln!(s, "stick deadband: |r| ≤ {edge:.6} m");
            }
            Some(edge) => {
                let _ = writeln!(
                    s,
                    "the paper model's stick deadband |r| ≤ {edge:.6} m does not hold for the {} model: its rows' stuck column says where the part is held",
                    model.name()
                );
            }
            None => {}
        }
        let _ = writeln!(
            s,
            "{:>10} {:>14} {:>14} {:>8}  note",
            "r (m)", "v_ss (m/s)", "eq17 (m/s)", "stuck"
        );
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.6e}"));
        for row in rows {
            let _ = writeln!(
                s,
                "{:>10.5} {:>14} {:>14} {:>8}  {}",
                row.r,
                opt(row.v_ss),
                opt(row.eq17),
                row.stick_fraction.map_or("-".into(), |s| format!("{s:.3}")),
                row.error.unwrap_or_default()
            );
        }
        Ok(s)
    }
}

//! `platefield study linesink`: arguments of the one-axis LineSink study.

use clap::Args;

use super::values::{choices, PRESETS, WAVES};
use super::{Json, Steps};
use platefield::dynamics::{Friction, Preset};
use platefield::Result;
use platefield_studies::linesink::{LineSink, Wave};

/// Arguments of `platefield study linesink`.
#[derive(Args)]
pub struct LinesinkArgs {
    /// Angular-acceleration waveform: square (eq. 1, ±α) or sine (ψ'' = A sin ωt).
    #[arg(long, value_parser = choices(&WAVES), default_value = "square", hide_possible_values = true)]
    pub wave: Wave,
    /// α of the square wave, or the sine's amplitude A (rad/s²).
    #[arg(long, allow_negative_numbers = true)]
    pub accel: f64,
    /// Axis depth below the plate surface (m); negative = above (LineSource).
    #[arg(long, allow_negative_numbers = true)]
    pub depth: f64,
    /// Period T (s).
    #[arg(long, default_value_t = 0.03, allow_negative_numbers = true)]
    pub period: f64,
    /// Kinetic friction coefficient μ.
    #[arg(long, default_value_t = 0.3, allow_negative_numbers = true)]
    pub mu: f64,
    /// Static friction coefficient (default: equal to --mu).
    #[arg(long, allow_negative_numbers = true)]
    pub mu_static: Option<f64>,
    /// Plate positions from the axis (m), comma separated.
    #[arg(
        long,
        required = true,
        allow_negative_numbers = true,
        value_delimiter = ','
    )]
    pub r: Vec<f64>,
    /// Model preset: paper (small angle, frozen position, no centripetal/tilt/Coriolis), full, or frozen (full, position frozen).
    #[arg(long, value_parser = choices(&PRESETS), default_value = "paper", hide_possible_values = true)]
    pub model: Preset,
    /// The part moves during the cycle (free steady state); implied by --model full.
    #[arg(long)]
    pub free: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub steps: Steps,
    /// Gravity (m/s²).
    #[arg(long, default_value_t = 9.81, allow_negative_numbers = true)]
    pub gravity: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub json: Json,
}

impl LinesinkArgs {
    /// Runs the study at the `--r` positions and returns the table (or JSON) to print.
    pub fn run(&self) -> Result<String> {
        let ls = LineSink {
            wave: self.wave,
            accel: self.accel,
            depth: self.depth,
            period: self.period,
            friction: Friction {
                stat: self.mu_static.unwrap_or(self.mu),
                kinetic: self.mu,
            },
            gravity: self.gravity,
        };
        let mut model = self.model.model();
        model.moving |= self.free;
        ls.report(&self.r, model, self.steps.numerics(), self.json.json)
    }
}
